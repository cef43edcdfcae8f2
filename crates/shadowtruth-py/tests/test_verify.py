"""`verify` returns the view's entry of `shadowtruth verify --json`."""

import json

import pytest
from conftest import SCENE_FILES, scene_id

import shadowtruth


def without_time(view):
    return {k: v for k, v in view.items() if k != "seconds"}


@pytest.mark.parametrize("path", SCENE_FILES, ids=scene_id)
def test_verify_is_the_commands_json(path, command, scenes, tmp_path):
    scene = scenes(path)
    camera, light = scene.cameras[0], scene.lights[0]
    out = tmp_path / "verify.json"
    # Exit 1 would be a disagreement outside the band: still a result to compare.
    command("verify", path, "--camera", camera, "--light", light, "--pixels", 20000, "--json", out, ok_codes=(0, 1))
    (expected,) = json.loads(out.read_text())["views"]
    got = shadowtruth.verify(scene, camera, light, pixels=20000)
    assert without_time(got) == without_time(expected)
    assert got["seconds"] >= 0


def test_verify_all_pixels_checks_every_evaluated_pixel_and_every_primary_ray(scenes):
    scene = scenes(SCENE_FILES[0])
    got = shadowtruth.verify(scene, pixels="all")
    # Flagged pixels outside the evaluated ones are checked too.
    assert got["evaluated"] <= got["checked"] <= got["evaluated"] + got["uncertain"]
    assert got["evaluated"] > 0
    assert got["primary_checked"] == got["width"] * got["height"]
