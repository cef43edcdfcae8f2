"""Bad input raises clear errors: what is wrong, and where."""

import json

import numpy as np
import pytest
from conftest import SCENE_FILES

import shadowtruth

PLANE_BOX = next(p for p in SCENE_FILES if p.stem == "plane_box")


@pytest.fixture
def scene(scenes):
    return scenes(PLANE_BOX)


def test_missing_scene_file_names_it(tmp_path):
    missing = tmp_path / "no_such_scene.json"
    with pytest.raises(shadowtruth.Error, match="no_such_scene.json"):
        shadowtruth.load_scene(missing)


def test_invalid_scene_names_the_file_and_json_path(tmp_path):
    text = json.loads(PLANE_BOX.read_text())
    text["cameras"][0]["fov_y_deg"] = "wide"
    bad = tmp_path / "bad_scene.json"
    bad.write_text(json.dumps(text))
    with pytest.raises(shadowtruth.Error) as error:
        shadowtruth.load_scene(bad)
    assert "bad_scene.json" in str(error.value) and "cameras[0].fov_y_deg" in str(error.value)
    assert isinstance(error.value, ValueError)


def test_unknown_camera_and_light_list_the_names(scene):
    with pytest.raises(ValueError, match=r"no camera named 'nope' \(have: main\)"):
        shadowtruth.hard_reference(scene, camera="nope")
    with pytest.raises(ValueError, match=r"no light named 'moon' \(have: sun\)"):
        shadowtruth.score(scene, None, "moon", np.ones((768, 1024), np.float32))


def test_visibility_of_the_wrong_shape_dtype_or_type(scene):
    with pytest.raises(ValueError, match=r"shape \(768, 1024\).*got shape \(768, 1000\)"):
        shadowtruth.score(scene, None, None, np.ones((768, 1000), np.float32))
    with pytest.raises(ValueError, match=r"got shape \(786432,\)"):
        shadowtruth.score(scene, None, None, np.ones(768 * 1024, np.float32))
    with pytest.raises(ValueError, match="got dtype float64"):
        shadowtruth.score(scene, None, None, np.ones((768, 1024)))
    with pytest.raises(ValueError, match="visibility: expected a float32 numpy array.*got list"):
        shadowtruth.score(scene, None, None, [[1.0]])
    with pytest.raises(ValueError, match=r"depth: .*got shape \(2, 2\)"):
        shadowtruth.score(scene, None, None, np.ones((768, 1024), np.float32), depth=np.ones((2, 2), np.float32))


def test_values_out_of_range(scene):
    visibility = np.ones((768, 1024), np.float32)
    visibility[1, 2] = 2.0
    with pytest.raises(ValueError, match=r"visibility: pixel \(2, 1\) is 2: visibility must be in \[0, 1\]"):
        shadowtruth.score(scene, None, None, visibility)
    depth = np.full((768, 1024), -1.0, np.float32)
    with pytest.raises(ValueError, match=r"depth: pixel \(0, 0\) is -1: depth must be ≥ 0"):
        shadowtruth.score(scene, None, None, np.ones((768, 1024), np.float32), depth=depth)


def test_bad_grid_resolution_and_pixels(scene):
    for grid in (0, 65, -1):
        with pytest.raises(ValueError, match=rf"grid {grid} is outside 1..=64"):
            shadowtruth.coverage_reference(scene, grid=grid)
    with pytest.raises(shadowtruth.Error, match="shadow-map resolution 0"):
        shadowtruth.score(scene, None, None, np.ones((768, 1024), np.float32), resolution=0)
    for pixels in (0, -2, "some", 1.5):
        with pytest.raises(ValueError, match=rf"pixels: '{pixels}' is neither `all` nor a positive number"):
            shadowtruth.verify(scene, pixels=pixels)


def test_area_light_without_a_size_is_refused_as_by_the_command(command, tmp_path):
    text = json.loads(PLANE_BOX.read_text())
    del text["lights"][0]["angular_diameter_deg"]
    sizeless = tmp_path / "sizeless.json"
    sizeless.write_text(json.dumps(text))
    with pytest.raises(shadowtruth.Error) as error:
        shadowtruth.area_light_reference(shadowtruth.load_scene(sizeless))
    refused = command("reference", sizeless, "--kind", "area", "--out", tmp_path / "a.exr", ok_codes=(2,))
    library_message = str(error.value).split(": ", 1)[1]
    assert str(sizeless) in str(error.value) and library_message in refused.stderr
