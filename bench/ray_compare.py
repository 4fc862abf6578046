#!/usr/bin/env python3
"""Compare certified first hits with Embree's on a tessellation, for
bench/ray_bench.sh.

    ray_compare.py RAYS.txt CCSS_HITS.txt EMBREE_HITS.txt EPS

CCSS_HITS: `ccss raycast` output (t face sub u v px py pz nx ny nz, or
'miss'); EMBREE_HITS: ray_embree's (t or 'miss'). Directions are unit.
For rays both hit, |dt| = |t_embree - t_ccss|; the tessellation lies within
EPS of the limit surface, so near a transversal crossing |dt| is about
EPS / |cos a| at most, a the angle between the ray and the normal at the
certified hit; `ratio` = |dt| |cos a| / EPS (<= 1 up to curvature and
float rounding). Prints one line with the maxima, the count of rays over
EPS / |cos a| and the misses / extra hits (with the smallest |cos a| among
the rays Embree misses: grazing rays are expected there).
"""
import sys


def rows(path):
    with open(path) as f:
        return [l.split() for l in f if l.strip() and not l.startswith("#")]


def main():
    rays, cc, em = rows(sys.argv[1]), rows(sys.argv[2]), rows(sys.argv[3])
    eps = float(sys.argv[4])
    assert len(rays) == len(cc) == len(em), (len(rays), len(cc), len(em))
    both = miss = extra = over = 0
    max_dt = max_ratio = 0.0
    min_cos_miss = 1.0
    worst = None
    for r, c, e in zip(rays, cc, em):
        d = [float(x) for x in r[3:6]]
        if c[0] == "miss":
            extra += e[0] != "miss"
            continue
        n = [float(x) for x in c[8:11]]
        cos = abs(sum(a * b for a, b in zip(d, n)))
        if e[0] == "miss":
            miss += 1
            min_cos_miss = min(min_cos_miss, cos)
            continue
        both += 1
        dt = abs(float(e[0]) - float(c[0]))
        ratio = dt * cos / eps
        max_dt = max(max_dt, dt)
        over += ratio > 1.0
        if ratio > max_ratio:
            max_ratio, worst = ratio, (dt, cos)
    w = f"{worst[0]:.2e}@cos={worst[1]:.3f}" if worst else "-"
    print(
        f"compare eps={eps:.3e} both_hit={both} max_dt={max_dt:.3e} max_dt_over_eps={max_dt / eps:.3f} "
        f"max_ratio={max_ratio:.3f} (dt={w}) over_eps_per_cos={over} "
        f"embree_misses={miss} min_cos_of_misses={min_cos_miss if miss else float('nan'):.4f} "
        f"embree_extra_hits={extra}"
    )


main()
