"""The references as arrays equal the files `shadowtruth reference` writes, bit for bit."""

import numpy as np
import pytest
from conftest import SCENE_FILES, read_exr, read_png, scene_id

import shadowtruth

PLANE_BOX = next(p for p in SCENE_FILES if p.stem == "plane_box")


@pytest.mark.parametrize("path", SCENE_FILES, ids=scene_id)
def test_hard_reference_is_the_commands_png(path, command, scenes, tmp_path):
    command("reference", path, "--out", tmp_path / "mask.png")
    expected = read_png(tmp_path / "mask.png")
    got = shadowtruth.hard_reference(scenes(path))
    assert got.dtype == np.uint8
    np.testing.assert_array_equal(got, expected)
    assert set(np.unique(got)) <= {0, 64, 96, 128, 192, 255}


def soft_from_command(command, path, kind, out, grid=None):
    samples = [] if grid is None else ["--samples", grid]
    command("reference", path, "--kind", kind, *samples, "--out", out)
    channels = read_exr(out)
    return channels["V"], channels["E"]


def assert_same_soft(got, expected):
    for array, want in zip(got, expected):
        assert array.dtype == np.float32
        np.testing.assert_array_equal(array, want)


@pytest.mark.parametrize("path", SCENE_FILES, ids=scene_id)
def test_coverage_reference_is_the_commands_exr(path, command, scenes, tmp_path):
    expected = soft_from_command(command, path, "coverage", tmp_path / "coverage.exr", grid=2)
    assert_same_soft(shadowtruth.coverage_reference(scenes(path), grid=2), expected)


@pytest.mark.parametrize("path", SCENE_FILES, ids=scene_id)
def test_area_light_reference_is_the_commands_exr(path, command, scenes, tmp_path):
    expected = soft_from_command(command, path, "area", tmp_path / "area.exr", grid=3)
    assert_same_soft(shadowtruth.area_light_reference(scenes(path), grid=3), expected)


def test_default_grids_are_the_commands(command, scenes, tmp_path):
    scene = scenes(PLANE_BOX)
    coverage = soft_from_command(command, PLANE_BOX, "coverage", tmp_path / "coverage.exr")
    assert_same_soft(shadowtruth.coverage_reference(scene), coverage)
    area = soft_from_command(command, PLANE_BOX, "area", tmp_path / "area.exr")
    assert_same_soft(shadowtruth.area_light_reference(scene), area)
    assert (shadowtruth.DEFAULT_COVERAGE_GRID, shadowtruth.DEFAULT_AREA_LIGHT_GRID) == (4, 8)


def test_named_camera_and_light_are_the_defaults_here(scenes):
    scene = scenes(PLANE_BOX)
    np.testing.assert_array_equal(
        shadowtruth.hard_reference(scene, "main", "sun"), shadowtruth.hard_reference(scene)
    )
