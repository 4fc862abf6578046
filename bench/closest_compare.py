#!/usr/bin/env python3
"""Compares `ccss closest` with closest_embree on the same points.

    closest_compare.py CCSS.txt EMBREE.txt EPS

CCSS.txt: 'dist face sub u v px py pz' per point (certified distance to
the limit surface within the tolerance); EMBREE.txt: the distance to the
tessellation per point. The tessellation is within EPS of the surface
(both ways), so the two distances differ by at most EPS (+ the ccss
tolerance). Prints the largest and mean difference in units of EPS and the
number of points beyond EPS.
"""
import sys


def main():
    cpath, epath, eps = sys.argv[1], sys.argv[2], float(sys.argv[3])
    with open(cpath) as f:
        c = [float(line.split()[0]) for line in f if line.strip()]
    with open(epath) as f:
        e = [float(line) for line in f if line.strip()]
    if len(c) != len(e):
        sys.exit(f"closest_compare: {len(c)} ccss rows vs {len(e)} embree rows")
    diffs = [abs(a - b) for a, b in zip(c, e)]
    over = sum(d > eps * (1 + 1e-6) for d in diffs)
    print(
        f"compare points={len(c)} max_diff_over_eps={max(diffs) / eps:.3f} "
        f"mean_diff_over_eps={sum(diffs) / len(diffs) / eps:.3f} beyond_eps={over}"
    )


if __name__ == "__main__":
    main()
