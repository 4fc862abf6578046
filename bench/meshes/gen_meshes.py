#!/usr/bin/env python3
"""Writes the closed meshes of the near-extraordinary evaluation benchmark
(bench/run_eval_bench.sh) into the directory given as argument:

  icosa_quads.obj      an icosahedron whose triangles are each split into three
                       quads (one Catmull-Clark step of the triangles, points
                       projected to the sphere): valences 5 (the 12 original
                       vertices), 4 (edge points) and 3 (face points); every
                       quad has two extraordinary vertices.
  bipyramid12.obj      the same split of a 12-gonal bipyramid: valence-12
                       poles, valence-3 face points, two extraordinary
                       vertices per quad.
  hexprism.obj         a hexagonal prism: two hexagon caps (n-gon centres of
                       valence 6 after one step) and six side quads; every
                       vertex has valence 3.

Deterministic (no randomness), plain Python 3.
"""
import math
import os
import sys


def write(path, verts, faces, comment):
    with open(path, "w") as fh:
        fh.write(f"# {comment}\n# written by bench/meshes/gen_meshes.py\n")
        for v in verts:
            fh.write("v %.17g %.17g %.17g\n" % tuple(v))
        for f in faces:
            fh.write("f " + " ".join(str(i + 1) for i in f) + "\n")


def split_triangles(verts, tris, radius=None):
    """Each triangle (a, b, c) becomes the quads (a, ab, abc, ca), ... ."""
    verts = [list(v) for v in verts]
    edge = {}

    def mid(a, b):
        key = (min(a, b), max(a, b))
        if key not in edge:
            p = [(verts[a][i] + verts[b][i]) / 2 for i in range(3)]
            edge[key] = len(verts)
            verts.append(p)
        return edge[key]

    quads = []
    for a, b, c in tris:
        ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
        f = len(verts)
        verts.append([(verts[a][i] + verts[b][i] + verts[c][i]) / 3 for i in range(3)])
        quads += [(a, ab, f, ca), (b, bc, f, ab), (c, ca, f, bc)]
    if radius is not None:
        for v in verts:
            r = math.sqrt(sum(x * x for x in v))
            for i in range(3):
                v[i] *= radius / r
    return verts, quads


def icosahedron():
    t = (1 + math.sqrt(5)) / 2
    v = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t),
         (0, -1, -t), (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    f = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9),
         (5, 11, 4), (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2),
         (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10),
         (8, 6, 7), (9, 8, 1)]
    return v, f


def bipyramid(n):
    v = [(math.cos(2 * math.pi * i / n), math.sin(2 * math.pi * i / n), 0.0) for i in range(n)]
    v += [(0.0, 0.0, 1.2), (0.0, 0.0, -1.2)]
    top, bot = n, n + 1
    f = []
    for i in range(n):
        j = (i + 1) % n
        f += [(i, j, top), (j, i, bot)]
    return v, f


def prism(n):
    v = []
    for z in (-0.5, 0.5):
        for i in range(n):
            a = 2 * math.pi * i / n
            v.append((math.cos(a), math.sin(a), z))
    f = [tuple(reversed(range(n))), tuple(range(n, 2 * n))]
    for i in range(n):
        j = (i + 1) % n
        f.append((i, j, n + j, n + i))
    return v, f


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: gen_meshes.py OUTDIR")
    out = sys.argv[1]
    os.makedirs(out, exist_ok=True)
    v, q = split_triangles(*icosahedron(), radius=1.0)
    write(os.path.join(out, "icosa_quads.obj"), v, q, "icosahedron, triangles split into quads")
    v, q = split_triangles(*bipyramid(12))
    write(os.path.join(out, "bipyramid12.obj"), v, q, "12-gonal bipyramid, triangles split into quads")
    v, f = prism(6)
    write(os.path.join(out, "hexprism.obj"), v, f, "hexagonal prism")


if __name__ == "__main__":
    main()
