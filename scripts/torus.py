#!/usr/bin/env python3
"""Writes meshes/torus.obj, the closed collider mesh of scenes/torus.json: a ring lying flat
(its axis along y), centred at the origin, triangles counter-clockwise seen from outside.

    python3 scripts/torus.py [--out meshes/torus.obj] [--major 0.45] [--minor 0.15]
                             [--around 48] [--across 24]
"""
import argparse
import math


def torus(major, minor, around, across):
    """Vertices and triangles (0-based) of a torus of radii `major` (centre of the tube) and
    `minor` (the tube's), `around` segments along the ring and `across` round the tube."""
    vertices = []
    for i in range(around):
        u = 2.0 * math.pi * i / around
        for j in range(across):
            v = 2.0 * math.pi * j / across
            r = major + minor * math.cos(v)
            vertices.append((r * math.cos(u), minor * math.sin(v), -r * math.sin(u)))
    triangles = []
    for i in range(around):
        for j in range(across):
            a = i * across + j
            b = ((i + 1) % around) * across + j
            c = ((i + 1) % around) * across + (j + 1) % across
            d = i * across + (j + 1) % across
            triangles += [(a, b, c), (a, c, d)]
    return vertices, triangles


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", default="meshes/torus.obj")
    parser.add_argument("--major", type=float, default=0.45, help="m, ring radius")
    parser.add_argument("--minor", type=float, default=0.15, help="m, tube radius")
    parser.add_argument("--around", type=int, default=48, help="segments along the ring")
    parser.add_argument("--across", type=int, default=24, help="segments round the tube")
    args = parser.parse_args()
    if not (0.0 < args.minor < args.major) or args.around < 3 or args.across < 3:
        parser.error("need 0 < minor < major and at least 3 segments each way")
    vertices, triangles = torus(args.major, args.minor, args.around, args.across)
    with open(args.out, "w", encoding="ascii") as f:
        f.write("# torus: major %g m, minor %g m (scripts/torus.py)\n" % (args.major, args.minor))
        for x, y, z in vertices:
            f.write("v %.6f %.6f %.6f\n" % (x, y, z))
        for a, b, c in triangles:
            f.write("f %d %d %d\n" % (a + 1, b + 1, c + 1))


if __name__ == "__main__":
    main()
