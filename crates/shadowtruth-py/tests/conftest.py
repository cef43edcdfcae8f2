"""Shared fixtures: the `shadowtruth` command the package is compared with, the bundled scenes,
and readers and writers of the files the command reads and writes."""

import json
import os
import subprocess
from pathlib import Path

import numpy as np
import OpenEXR
import pytest
from PIL import Image

import shadowtruth

WORKSPACE = Path(__file__).resolve().parents[3]
SCENE_FILES = sorted((WORKSPACE / "scenes").glob("*.json"))


def scene_id(path):
    return path.stem


@pytest.fixture(scope="session")
def command():
    """Runs the `shadowtruth` command (SHADOWTRUTH_BIN, or target/release/shadowtruth of the
    workspace) and returns the finished process; fails the test when it exits otherwise than
    `ok_codes` allow."""
    binary = Path(os.environ.get("SHADOWTRUTH_BIN") or WORKSPACE / "target" / "release" / "shadowtruth")
    if not binary.is_file():
        pytest.fail(
            f"the shadowtruth command is missing at {binary}: run `cargo build --release` in "
            f"{WORKSPACE}, or set SHADOWTRUTH_BIN to the binary",
            pytrace=False,
        )

    def run(*args, ok_codes=(0,)):
        done = subprocess.run([str(binary), *map(str, args)], capture_output=True, text=True, cwd=WORKSPACE)
        if done.returncode not in ok_codes:
            pytest.fail(f"shadowtruth {' '.join(map(str, args))} exited {done.returncode}:\n{done.stderr}")
        return done

    return run


@pytest.fixture(scope="session")
def scenes():
    """The bundled scenes, each loaded once, so that every test of a scene shares its BVH."""
    loaded = {}

    def get(path):
        if path not in loaded:
            loaded[path] = shadowtruth.load_scene(path)
        return loaded[path]

    return get


@pytest.fixture(scope="session")
def scene_json():
    return lambda path: json.loads(Path(path).read_text())


def read_png(path):
    return np.asarray(Image.open(path))


def write_png(path, values):
    """A visibility buffer in [0, 1] as an 8-bit grey PNG; returns the float32 values the command
    reads back from it."""
    grey = np.round(values * 255).astype(np.uint8)
    Image.fromarray(grey, mode="L").save(path)
    return grey.astype(np.float32) / np.float32(255)


def read_exr(path):
    """Every channel of an EXR file, by name, as (height, width) arrays."""
    with OpenEXR.File(str(path), separate_channels=True) as exr:
        return {name: channel.pixels for name, channel in exr.channels().items()}


def write_exr(path, channels):
    header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
    with OpenEXR.File(header, {name: np.ascontiguousarray(v, np.float32) for name, v in channels.items()}) as exr:
        exr.write(str(path))
