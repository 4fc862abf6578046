#!/bin/sh
# Certified closest points (ccss) beside Embree 3's rtcPointQuery on a
# tessellation, in one run on the same points (issue #30's closest-point
# comparison).
#
#   bench/closest_bench.sh [CCSS] [POINTS] [EPS...]
#
# CCSS: the ccss binary (default target/release/ccss); POINTS per mesh
# (default 2000); EPS: tessellation tolerances relative to the control
# points' box diagonal (default 1e-3 1e-4 1e-5). Needs Embree 3
# (libembree-dev); exits 3 with a message without it. A benchmark only:
# no test runs it.
#
# Per mesh (torus, righthanded, cube_creases1 from tests/data/osd):
#  1. bench/closest_points.py writes POINTS seeded random points of the
#     control box grown by a quarter, read by both sides;
#  2. `ccss closest --timing` (RAYON_NUM_THREADS=1, tolerance 1e-9 of the
#     diagonal) times the certified closest points (query loop only);
#  3. per EPS: `ccss tessellate --abs-flatness eps --triangulate`
#     (guaranteed bound eps = EPS x diagonal), then
#     bench/embree/closest_embree builds the BVH (one thread, timed
#     separately) and times rtcPointQuery with an exact point-triangle
#     callback on those triangles;
#  4. bench/closest_compare.py: |d_embree - d_ccss| against eps (the
#     tessellation's error bounds the difference).
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
ccss=${1:-$root/target/release/ccss}
npts=${2:-2000}
[ $# -ge 2 ] && shift 2 || shift $#
epss=${*:-1e-3 1e-4 1e-5}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$root/bench/embree/build.sh" "$tmp/ray_embree" >/dev/null
echo "machine: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg), embree $(dpkg-query -W -f '${Version}' libembree-dev 2>/dev/null || echo '?')"
for m in catmark_torus catmark_righthanded catmark_cube_creases1; do
    obj=$root/tests/data/osd/$m.obj
    python3 "$root/bench/closest_points.py" "$obj" "$npts" 30 >"$tmp/pts.txt"
    diag=$(sed -n 's/^# diag //p' "$tmp/pts.txt")
    RAYON_NUM_THREADS=1 "$ccss" closest --timing "$obj" <"$tmp/pts.txt" >"$tmp/ccss.txt" 2>"$tmp/ccss.err"
    ctime=$(grep '^ccss closest:' "$tmp/ccss.err")
    cs=$(echo "$ctime" | sed 's/.*seconds=\([^ ]*\).*/\1/')
    echo "== $m diag=$diag points=$npts"
    echo "ccss certified closest (tol 1e-9 diag, 1 thread): us_per_point=$(python3 -c "print(f'{$cs*1e6/$npts:.1f}')") ($ctime)"
    for e in $epss; do
        eps=$(python3 -c "print(f'{$e*$diag:.6e}')")
        tline=$(RAYON_NUM_THREADS=1 "$ccss" tessellate --abs-flatness "$eps" --triangulate "$obj" -o "$tmp/t.obj")
        echo "-- eps=$e x diag = $eps: tessellate $tline"
        "$tmp/closest_embree" "$tmp/t.obj" "$tmp/pts.txt" "$tmp/embree.txt" 10
        python3 "$root/bench/closest_compare.py" "$tmp/ccss.txt" "$tmp/embree.txt" "$eps"
    done
done
