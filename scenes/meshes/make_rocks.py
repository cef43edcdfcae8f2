#!/usr/bin/env python3
"""Writes rocks_terrain.obj (an open heightfield) and rocks.obj (three closed, displaced
icospheres) for scenes/rocks.json. Deterministic: run it again and the files come out the same.
    python3 scenes/meshes/make_rocks.py
"""
import math
import os

HERE = os.path.dirname(os.path.abspath(__file__))


def height(x, z):
    return (0.35 * math.sin(0.9 * x + 0.3) * math.cos(0.7 * z - 0.2)
            + 0.12 * math.sin(2.3 * x + 1.7 * z) + 0.05 * math.cos(4.1 * x - 3.3 * z))


def terrain(n=48, half=8.0):
    verts = []
    for j in range(n + 1):
        for i in range(n + 1):
            x = -half + 2 * half * i / n
            z = -half + 2 * half * j / n
            verts.append((x, height(x, z), z))
    faces = []
    for j in range(n):
        for i in range(n):
            a = j * (n + 1) + i
            b, c, d = a + 1, a + n + 2, a + n + 1
            # Counter-clockwise seen from above (+y): a, d, c and a, c, b.
            faces += [(a, d, c), (a, c, b)]
    return verts, faces


def icosphere(subdivisions):
    t = (1 + 5 ** 0.5) / 2
    verts = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t),
             (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    verts = [tuple(c / math.sqrt(sum(k * k for k in v)) for c in v) for v in verts]
    faces = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
             (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
             (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    for _ in range(subdivisions):
        cache = {}

        def mid(a, b):
            key = (min(a, b), max(a, b))
            if key not in cache:
                m = [(verts[a][k] + verts[b][k]) / 2 for k in range(3)]
                r = math.sqrt(sum(c * c for c in m))
                verts.append(tuple(c / r for c in m))
                cache[key] = len(verts) - 1
            return cache[key]

        new = []
        for a, b, c in faces:
            ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
            new += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        faces = new
    return verts, faces


def rocks():
    verts, faces = [], []
    for (cx, cz, r, seed) in ((-2.0, 1.0, 1.1, 0.3), (2.2, -1.5, 0.8, 1.9), (0.5, 3.0, 0.6, 4.2)):
        sv, sf = icosphere(3)
        base = len(verts)
        cy = height(cx, cz) + 0.55 * r
        for (x, y, z) in sv:
            bump = 1 + 0.18 * math.sin(5 * x + seed) * math.sin(4 * y - seed) * math.cos(3 * z + 2 * seed)
            verts.append((cx + r * 1.2 * x * bump, cy + r * 0.8 * y * bump, cz + r * z * bump))
        faces += [(a + base, b + base, c + base) for a, b, c in sf]
    return verts, faces


def write(name, verts, faces):
    with open(os.path.join(HERE, name), "w") as fh:
        fh.write("# written by make_rocks.py\n")
        for v in verts:
            fh.write("v %.6f %.6f %.6f\n" % v)
        for f in faces:
            fh.write("f %d %d %d\n" % tuple(i + 1 for i in f))


if __name__ == "__main__":
    write("rocks_terrain.obj", *terrain())
    write("rocks.obj", *rocks())
