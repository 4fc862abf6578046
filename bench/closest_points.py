#!/usr/bin/env python3
"""Seeded random query points around a mesh, for bench/closest_bench.sh.

    closest_points.py MESH.obj N SEED > POINTS.txt

Writes '# diag D' then N lines 'x y z': uniform points of the control
points' box grown by a quarter on each side (as `ccss bench query` draws
its closest-point queries). Python's Mersenne Twister with the given seed:
the same points every run.
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
    rng = random.Random(seed)
    print(f"# diag {math.dist(lo, hi):.17g}")
    for _ in range(n):
        q = [c[k] + 0.625 * (hi[k] - lo[k]) * (2 * rng.random() - 1) for k in range(3)]
        print(f"{q[0]:.17g} {q[1]:.17g} {q[2]:.17g}")


if __name__ == "__main__":
    main()
