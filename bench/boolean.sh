#!/bin/sh
# Booleans of ~1k-face closed solids at eps = 1e-3 of the bounding-box
# diagonal, single-threaded: `ccss boolean` (tessellate both at t, exact
# corefinement, shrink t until amplification x t <= eps).
#
#   bench/boolean.sh [CCSS] [RUNS]
#
# Inputs (written to a temp directory): `icosa_quads.obj` of
# bench/meshes/gen_meshes.py refined twice with Catmull-Clark (960 quads,
# valence-5 and valence-3 extraordinary vertices) against a rotated and
# shifted copy; and catmark_torus refined twice (512 quads) against a
# rotated, shifted copy of the same. The best of RUNS (default 3) wall
# times is printed per operation with the output line of `ccss boolean`.
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
ccss=${1:-$root/target/release/ccss}
runs=${2:-3}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
python3 "$root/bench/meshes/gen_meshes.py" "$tmp" >/dev/null
"$ccss" refine --scheme catmull-clark --levels 2 "$tmp/icosa_quads.obj" -o "$tmp/blobA.obj" >/dev/null
"$ccss" refine --scheme catmull-clark --levels 2 "$root/tests/data/osd/catmark_torus.obj" -o "$tmp/torusA.obj" >/dev/null
# B = A rotated about x, y, z by 0.21, -0.33, 0.17 rad and shifted by
# (0.23, 0.11, 0.07) x the box extents; prints the control box diagonal.
move() {
    python3 - "$1" "$2" <<'PY'
import math, sys
src, dst = sys.argv[1], sys.argv[2]
lines = open(src).read().splitlines()
V = [list(map(float, l.split()[1:4])) for l in lines if l.startswith("v ")]
lo = [min(v[i] for v in V) for i in range(3)]
hi = [max(v[i] for v in V) for i in range(3)]
a, b, c = 0.21, -0.33, 0.17
def xf(p):
    x, y, z = p
    y, z = y * math.cos(a) - z * math.sin(a), y * math.sin(a) + z * math.cos(a)
    x, z = x * math.cos(b) + z * math.sin(b), -x * math.sin(b) + z * math.cos(b)
    x, y = x * math.cos(c) - y * math.sin(c), x * math.sin(c) + y * math.cos(c)
    d = [hi[i] - lo[i] for i in range(3)]
    return [x + 0.23 * d[0], y + 0.11 * d[1], z + 0.07 * d[2]]
out = ["v %r %r %r" % tuple(xf(list(map(float, l.split()[1:4])))) if l.startswith("v ") else l for l in lines]
open(dst, "w").write("\n".join(out) + "\n")
print(math.dist(lo, hi))
PY
}
for s in blob torus; do
    diag=$(move "$tmp/${s}A.obj" "$tmp/${s}B.obj")
    eps=$(python3 -c "print($diag * 1e-3)")
    faces=$(grep -c '^f ' "$tmp/${s}A.obj")
    for op in union intersection difference; do
        best=
        line=
        i=0
        while [ $i -lt "$runs" ]; do
            line=$(RAYON_NUM_THREADS=1 "$ccss" boolean --op $op --eps "$eps" "$tmp/${s}A.obj" "$tmp/${s}B.obj" -o "$tmp/out.stl")
            t=$(echo "$line" | sed 's/.*seconds=//')
            best=$(python3 -c "print(min(float('$t'), float('${best:-inf}')))")
            i=$((i + 1))
        done
        echo "$s faces=$faces diag=$diag eps=$eps op=$op best_seconds=$best $line"
    done
done
