"""The package's surface: the scene's attributes and the documentation `help` shows."""

import inspect
import json

import pytest
from conftest import SCENE_FILES, scene_id

import shadowtruth


@pytest.mark.parametrize("path", SCENE_FILES, ids=scene_id)
def test_scene_has_the_files_names(path, scenes):
    scene, text = scenes(path), json.loads(path.read_text())
    assert scene.name == text["name"]
    assert scene.cameras == [c["name"] for c in text["cameras"]]
    assert scene.lights == [light["name"] for light in text["lights"]]
    assert scene.triangle_count > 0
    camera = text["cameras"][0]
    assert scene.image_size() == (camera["width"], camera["height"])
    assert repr(scene).startswith(f"Scene(name={scene.name!r}, cameras={scene.cameras!r}")


@pytest.mark.parametrize(
    "function, says",
    [
        (shadowtruth.load_scene, "Returns a `Scene`"),
        (shadowtruth.hard_reference, "255 lit, 0 shadowed, 128 background"),
        (shadowtruth.coverage_reference, "Returns (visibility, std_error)"),
        (shadowtruth.area_light_reference, "Returns (visibility, std_error)"),
        (shadowtruth.verify, "Returns a dict"),
        (shadowtruth.score, "Returns a dict with the counts"),
    ],
)
def test_help_says_what_each_function_returns(function, says):
    assert says in function.__doc__
    assert function.__text_signature__ is not None


def test_error_is_a_value_error():
    assert issubclass(shadowtruth.Error, ValueError)


def test_signatures_show_the_defaults():
    def default(function, name):
        return inspect.signature(function).parameters[name].default

    assert default(shadowtruth.coverage_reference, "grid") == shadowtruth.DEFAULT_COVERAGE_GRID
    assert default(shadowtruth.area_light_reference, "grid") == shadowtruth.DEFAULT_AREA_LIGHT_GRID
    assert default(shadowtruth.score, "depth_tolerance") == shadowtruth.DEFAULT_DEPTH_TOLERANCE
    assert default(shadowtruth.score, "resolution") == shadowtruth.DEFAULT_ATTRIBUTION_RESOLUTION == 2048
    assert shadowtruth.DEFAULT_SAMPLE_PIXELS == 100000
