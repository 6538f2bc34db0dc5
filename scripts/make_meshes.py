#!/usr/bin/env python3
"""Writes the meshes of the built-in cases (cases/meshes/). Run from the repository's root:

    python3 scripts/make_meshes.py

cylinder.stl: a vertical cylinder of radius 0.06 m and height 0.2 m, as a 24-sided prism, standing on
z = 0 with its axis through the origin (binary STL, counter-clockwise seen from outside)."""
import math
import struct
from pathlib import Path


def cylinder(radius, height, sides):
    bottom = [(radius * math.cos(2 * math.pi * i / sides), radius * math.sin(2 * math.pi * i / sides), 0.0)
              for i in range(sides)]
    top = [(x, y, height) for x, y, _ in bottom]
    centre_bottom, centre_top = (0.0, 0.0, 0.0), (0.0, 0.0, height)
    triangles = []
    for i in range(sides):
        j = (i + 1) % sides
        triangles.append((bottom[i], bottom[j], top[j]))  # side, outwards
        triangles.append((bottom[i], top[j], top[i]))
        triangles.append((centre_bottom, bottom[j], bottom[i]))  # floor, downwards
        triangles.append((centre_top, top[i], top[j]))  # top, upwards
    return triangles


def normal(a, b, c):
    u = [b[k] - a[k] for k in range(3)]
    v = [c[k] - a[k] for k in range(3)]
    n = (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])
    length = math.sqrt(sum(x * x for x in n))
    return tuple(x / length for x in n)


def binary_stl(triangles, title):
    out = bytearray(title.encode().ljust(80, b" ")[:80])
    out += struct.pack("<I", len(triangles))
    for t in triangles:
        out += struct.pack("<3f", *normal(*t))
        for p in t:
            out += struct.pack("<3f", *p)
        out += struct.pack("<H", 0)
    return bytes(out)


if __name__ == "__main__":
    path = Path("cases/meshes/cylinder.stl")
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_bytes(binary_stl(cylinder(0.06, 0.2, 24), "sluice cylinder r = 0.06 m, h = 0.2 m"))
    print(f"wrote {path}")
