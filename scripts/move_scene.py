#!/usr/bin/env python3
"""Writes a copy of a shadowtruth scene moved OFFSET units from where it was.

Usage: python3 scripts/move_scene.py SCENE OFFSET OUT [--direction X,Y,Z]

Everything that has a position moves by the same vector: every object (its `transform`'s
`translate`, or each of its `instances`' translations; an object without a transform gets one),
every camera's `position` and `look_at`, and every spot light's `position`, on paths too. Light
and camera directions and `up` vectors are unchanged. The vector is OFFSET along the fixed
direction (0.6, 0.3, -0.74), normalized (or --direction), rounded to whole units: whole units
keep coordinates that are multiples of 2^-k exact in f32 as long as they stay below 2^(24-k),
so a scene whose geometry lies on such a lattice (crates/shadowtruth/tests/far/coplanar_quad.json)
moves without any rounding. The loader applies each transform in f64 and rounds every vertex
once to f32; only an existing non-zero `translate` plus the offset is rounded to f32 on load.

The files the scene names (`mesh`, `gltf` and a glTF's relative buffer and image URIs) must stay
inside the scene's folder, so when OUT lies in another folder they are copied beside it at the
same relative paths. The moved scene is named "<name>_moved_<OFFSET>".

Example, the island 10^4 units out, then checked exactly:
  python3 scripts/move_scene.py scenes/papers/island.json 1e4 far/island_1e4.json
  shadowtruth verify far/island_1e4.json --pixels all
"""

import argparse
import json
import math
import shutil
import sys
from pathlib import Path

DIRECTION = (0.6, 0.3, -0.74)


def offset_vector(distance, direction):
    length = math.sqrt(sum(c * c for c in direction))
    if length == 0.0 or not math.isfinite(length):
        raise ValueError("the direction must be a non-zero finite vector")
    return [float(round(distance * c / length)) for c in direction]


def shifted(value, offset, what):
    if not (isinstance(value, list) and len(value) == 3 and all(isinstance(c, (int, float)) for c in value)):
        raise ValueError(f"{what} is not a vector of three numbers")
    return [c + o for c, o in zip(value, offset)]


def move_transform(transform, offset, what):
    transform = dict(transform or {})
    transform["translate"] = shifted(transform.get("translate", [0.0, 0.0, 0.0]), offset, f"{what}.translate")
    return transform


def move_path(path, offset, fields, what):
    path = dict(path)
    keys = []
    for k, key in enumerate(path.get("keys", [])):
        key = dict(key)
        for field in fields:
            if field in key:
                key[field] = shifted(key[field], offset, f"{what}.keys[{k}].{field}")
        keys.append(key)
    path["keys"] = keys
    return path


def move_scene(scene, offset):
    scene = dict(scene)
    objects = []
    for i, obj in enumerate(scene.get("objects", [])):
        obj = dict(obj)
        what = f"objects[{i}]"
        if "instances" in obj:
            obj["instances"] = [move_transform(t, offset, f"{what}.instances[{j}]") for j, t in enumerate(obj["instances"])]
        else:
            obj["transform"] = move_transform(obj.get("transform"), offset, f"{what}.transform")
        objects.append(obj)
    scene["objects"] = objects
    cameras = []
    for i, camera in enumerate(scene.get("cameras", [])):
        camera = dict(camera)
        for field in ("position", "look_at"):
            if field in camera:
                camera[field] = shifted(camera[field], offset, f"cameras[{i}].{field}")
        if "path" in camera:
            camera["path"] = move_path(camera["path"], offset, ("position", "look_at"), f"cameras[{i}].path")
        cameras.append(camera)
    scene["cameras"] = cameras
    lights = []
    for i, light in enumerate(scene.get("lights", [])):
        light = dict(light)
        if "position" in light:
            light["position"] = shifted(light["position"], offset, f"lights[{i}].position")
        if "path" in light:
            light["path"] = move_path(light["path"], offset, ("position",), f"lights[{i}].path")
        lights.append(light)
    scene["lights"] = lights
    return scene


def referenced_files(scene, folder):
    """Relative paths of the files the scene reads: meshes, glTFs and a glTF's relative URIs."""
    files = []
    for obj in scene.get("objects", []):
        for key in ("mesh", "gltf"):
            if isinstance(obj.get(key), str):
                files.append(obj[key])
                if key == "gltf" and obj[key].lower().endswith(".gltf"):
                    files.extend(gltf_uris(folder, obj[key]))
    return files


def gltf_uris(folder, relative):
    with open(folder / relative, encoding="utf-8") as f:
        gltf = json.load(f)
    base = Path(relative).parent
    uris = []
    for item in gltf.get("buffers", []) + gltf.get("images", []):
        uri = item.get("uri")
        if isinstance(uri, str) and not uri.startswith("data:") and "://" not in uri:
            uris.append(str(base / uri))
    return uris


def main(argv):
    parser = argparse.ArgumentParser(
        description=__doc__.split("\n\n", 1)[0],
        epilog=__doc__.split("\n\n", 1)[1],
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("scene", type=Path, help="the scene JSON to move")
    parser.add_argument("offset", type=float, help="how far to move it, in scene units (e.g. 1e4)")
    parser.add_argument("out", type=Path, help="where to write the moved scene JSON")
    parser.add_argument(
        "--direction",
        default=",".join(str(c) for c in DIRECTION),
        help="the direction to move along, X,Y,Z (default %(default)s; normalized)",
    )
    args = parser.parse_args(argv)
    try:
        direction = [float(c) for c in args.direction.split(",")]
        if len(direction) != 3:
            raise ValueError("--direction takes three numbers")
        offset = offset_vector(args.offset, direction)
        with open(args.scene, encoding="utf-8") as f:
            scene = json.load(f)
        moved = move_scene(scene, offset)
        moved["name"] = f"{scene.get('name', args.scene.stem)}_moved_{args.offset:g}"
        source, target = args.scene.resolve().parent, args.out.resolve().parent
        target.mkdir(parents=True, exist_ok=True)
        if source != target:
            for relative in referenced_files(scene, source):
                destination = target / relative
                destination.parent.mkdir(parents=True, exist_ok=True)
                shutil.copyfile(source / relative, destination)
        with open(args.out, "w", encoding="utf-8") as f:
            json.dump(moved, f, indent=2)
            f.write("\n")
    except (OSError, ValueError, json.JSONDecodeError) as e:
        print(f"move_scene.py: {e}", file=sys.stderr)
        return 2
    print(f"{args.out}: moved by {offset}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
