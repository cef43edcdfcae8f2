"""`score` gives the counts, attribution and rates `shadowtruth score` records in report.json
for the same buffer."""

import json

import numpy as np
import pytest
from conftest import SCENE_FILES, read_exr, scene_id, write_exr, write_png

import shadowtruth

LIT, SHADOWED = 255, 0


def renderer_like(mask, seed):
    """A plausible renderer's buffer: the reference shifted by a few pixels (errors at the shadow
    boundaries) with a sprinkle of flipped pixels (errors away from them), lit off the surfaces."""
    visibility = np.where(mask == SHADOWED, 0.0, 1.0)
    visibility = np.roll(visibility, (2, 3), axis=(0, 1))
    flipped = np.random.default_rng(seed).random(mask.shape) < 0.01
    return np.where(flipped, 1.0 - visibility, visibility)


def commands_run(command, path, scene, out, *files):
    command(
        "score", path, "--camera", scene.cameras[0], "--light", scene.lights[0], *files,
        "--out", out, "--no-cache", "--no-figures", "--quiet",
    )  # fmt: skip
    (run,) = json.loads((out / "report.json").read_text())["runs"]
    return run


def assert_same_score(got, run):
    expected = dict(run["counts"], surface_mismatch=run["counts"].get("surface_mismatch", 0))
    assert {k: v for k, v in got.items() if k != "rates"} == expected
    assert got["rates"] == run["rates"]


@pytest.mark.parametrize("path", SCENE_FILES, ids=scene_id)
def test_score_is_the_commands_report(path, command, scenes, tmp_path):
    scene = scenes(path)
    mask = shadowtruth.hard_reference(scene)
    visibility = write_png(tmp_path / "visibility.png", renderer_like(mask, seed=len(path.stem)))
    run = commands_run(command, path, scene, tmp_path / "report", "--visibility", tmp_path / "visibility.png")
    got = shadowtruth.score(scene, None, None, visibility)
    assert_same_score(got, run)
    assert got["false_shadow"] > 0 and got["false_lit"] > 0
    attributed = got["aliasing"] + got["seam"] + got["acne"] + got["leak"] + got["light_bleeding"]
    assert attributed == got["false_shadow"] + got["false_lit"]


def camera_depth(command, path, scene_json, tmp_path):
    """The reference's distance from the camera of every pixel (+inf off the surfaces), from the
    G-buffer positions `shadowtruth view-export` writes."""
    command("view-export", path, "--out", tmp_path / "view", "--quiet")
    position = read_exr(tmp_path / "view" / "position.exr")
    xyz = np.stack([position["R"], position["G"], position["B"]], axis=-1).astype(np.float64)
    eye = np.array(scene_json(path)["cameras"][0]["position"], np.float64)
    depth = np.linalg.norm(xyz - eye, axis=-1)
    return np.where(np.isfinite(depth), depth, np.inf).astype(np.float32)


@pytest.mark.parametrize("path", SCENE_FILES[:2], ids=scene_id)
def test_score_with_background_and_depth_is_the_commands(path, command, scenes, scene_json, tmp_path):
    scene = scenes(path)
    mask = shadowtruth.hard_reference(scene)
    visibility = renderer_like(mask, seed=5).astype(np.float32)
    height, width = mask.shape
    visibility[: height // 4, : width // 4] = np.nan  # the renderer drew background there
    depth = camera_depth(command, path, scene_json, tmp_path)
    depth[:, -width // 3 :] *= np.float32(1.01)  # another surface than the reference's there
    write_exr(tmp_path / "visibility.exr", {"V": visibility})
    write_exr(tmp_path / "depth.exr", {"Z": depth})
    run = commands_run(
        command, path, scene, tmp_path / "report",
        "--visibility", tmp_path / "visibility.exr", "--depth", tmp_path / "depth.exr",
    )  # fmt: skip
    got = shadowtruth.score(scene, None, None, visibility, depth=depth)
    assert_same_score(got, run)
    assert 0 < got["surface_mismatch"] < got["evaluated"]


def test_exact_buffer_scores_no_error(scenes):
    scene = scenes(SCENE_FILES[0])
    mask = shadowtruth.hard_reference(scene)
    got = shadowtruth.score(scene, None, None, (mask != SHADOWED).astype(np.float32))
    assert (got["false_shadow"], got["false_lit"], got["rates"]["error"]) == (0, 0, 0.0)
    assert got["evaluated"] == np.count_nonzero((mask == LIT) | (mask == SHADOWED))
