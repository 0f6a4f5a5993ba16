#!/usr/bin/env python3
"""Write a closed icosphere OBJ (unit radius, centred at the origin).

Usage: make_icosphere.py SUBDIVISIONS OUT.obj
Each subdivision splits every triangle into 4 and projects the new vertices
onto the sphere; 20 * 4**n triangles, watertight (shared vertices).
Coordinates are printed with 9 significant digits, enough to round-trip f32.
"""
import math
import sys


def icosphere(levels):
    t = (1.0 + math.sqrt(5.0)) / 2.0
    verts = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t),
             (0, -1, -t), (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    verts = [normalize(v) for v in verts]
    faces = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
             (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
             (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    for _ in range(levels):
        cache = {}

        def mid(a, b):
            key = (min(a, b), max(a, b))
            if key not in cache:
                pa, pb = verts[a], verts[b]
                verts.append(normalize(tuple((pa[k] + pb[k]) / 2 for k in range(3))))
                cache[key] = len(verts) - 1
            return cache[key]

        new = []
        for a, b, c in faces:
            ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
            new += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        faces = new
    return verts, faces


def normalize(v):
    n = math.sqrt(sum(x * x for x in v))
    return tuple(x / n for x in v)


def main():
    levels, out = int(sys.argv[1]), sys.argv[2]
    verts, faces = icosphere(levels)
    with open(out, "w") as f:
        f.write(f"# icosphere, {levels} subdivisions, {len(faces)} triangles, written by scripts/make_icosphere.py\n")
        for v in verts:
            f.write("v %.9g %.9g %.9g\n" % v)
        for a, b, c in faces:
            f.write(f"f {a + 1} {b + 1} {c + 1}\n")


if __name__ == "__main__":
    main()
