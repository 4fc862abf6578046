#!/usr/bin/env python3
"""Seeded random rays aimed at a mesh, for bench/ray_bench.sh.

    ray_rays.py MESH.obj N SEED > RAYS.txt

Writes '# diag D' then N lines 'ox oy oz dx dy dz': the origin on the
sphere of radius one diagonal of the control points' box around the box's
centre, aimed at a uniform point of the box's inner half (as
`ccss bench query` draws its rays), the direction of unit length so that
t is a distance. Python's Mersenne Twister with the given seed: the same
rays every run.
"""
import math
import random
import sys


def main():
    path, n, seed = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
    pts = []
    with open(path) as f:
        for line in f:
            w = line.split()
            if w and w[0] == "v":
                pts.append([float(x) for x in w[1:4]])
    lo = [min(p[k] for p in pts) for k in range(3)]
    hi = [max(p[k] for p in pts) for k in range(3)]
    c = [0.5 * (lo[k] + hi[k]) for k in range(3)]
    diag = math.dist(lo, hi)
    rng = random.Random(seed)
    print(f"# diag {diag:.17g}")
    for _ in range(n):
        while True:
            u = [2 * rng.random() - 1 for _ in range(3)]
            r = math.hypot(*u)
            if 1e-3 < r <= 1:
                break
        o = [c[k] + u[k] / r * diag for k in range(3)]
        t = [c[k] + 0.25 * (hi[k] - lo[k]) * (2 * rng.random() - 1) for k in range(3)]
        d = [t[k] - o[k] for k in range(3)]
        m = math.hypot(*d)
        d = [x / m for x in d]
        print(" ".join(f"{x:.17g}" for x in o + d))


main()
