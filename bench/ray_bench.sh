#!/bin/sh
# Certified ray casting (ccss) beside Embree 3 on a tessellation, in one
# run on the same rays (issue #30's ray comparison).
#
#   bench/ray_bench.sh [CCSS] [RAYS] [EPS...]
#
# CCSS: the ccss binary (default target/release/ccss); RAYS per mesh
# (default 2000); EPS: tessellation tolerances relative to the control
# points' box diagonal (default 1e-3 1e-4 1e-5). Needs Embree 3
# (libembree-dev); exits 3 with a message without it. A benchmark only:
# no test runs it.
#
# Per mesh (torus, righthanded, cube_creases1 from tests/data/osd):
#  1. bench/ray_rays.py writes RAYS seeded random rays aimed at the object
#     (unit directions), read by both sides;
#  2. `ccss raycast --timing` (RAYON_NUM_THREADS=1, tolerance 1e-9 of the
#     diagonal) times the certified first hits (query loop only);
#  3. per EPS: `ccss tessellate --abs-flatness eps --triangulate`
#     (guaranteed bound eps = EPS x diagonal), then bench/embree/ray_embree
#     builds the BVH (one thread, timed separately) and times rtcIntersect1
#     / 4 / 8 on those triangles;
#  4. bench/ray_compare.py: |t_embree - t_ccss| against eps / |cos a|, and
#     Embree's misses / extra hits. The difference is the tessellation's
#     error (the certified hit is within 1e-9 x diag of the limit surface;
#     Embree's float rounding is ~1e-7 x diag), not Embree's.
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
ccss=${1:-$root/target/release/ccss}
nrays=${2:-2000}
[ $# -ge 2 ] && shift 2 || shift $#
epss=${*:-1e-3 1e-4 1e-5}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$root/bench/embree/build.sh" "$tmp/ray_embree" >/dev/null
echo "machine: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg), embree $(dpkg-query -W -f '${Version}' libembree-dev 2>/dev/null || echo '?')"
for m in catmark_torus catmark_righthanded catmark_cube_creases1; do
    obj=$root/tests/data/osd/$m.obj
    python3 "$root/bench/ray_rays.py" "$obj" "$nrays" 30 >"$tmp/rays.txt"
    diag=$(sed -n 's/^# diag //p' "$tmp/rays.txt")
    RAYON_NUM_THREADS=1 "$ccss" raycast --timing "$obj" <"$tmp/rays.txt" >"$tmp/ccss.txt" 2>"$tmp/ccss.err"
    ctime=$(grep '^ccss raycast:' "$tmp/ccss.err")
    cs=$(echo "$ctime" | sed 's/.*seconds=\([^ ]*\).*/\1/')
    chits=$(grep -vc '^miss' "$tmp/ccss.txt" || true)
    echo "== $m diag=$diag rays=$nrays"
    echo "ccss certified first hit (tol 1e-9 diag, 1 thread): hit_rays=$chits us_per_ray=$(python3 -c "print(f'{$cs*1e6/$nrays:.1f}')") ($ctime)"
    for e in $epss; do
        eps=$(python3 -c "print(f'{$e*$diag:.6e}')")
        tline=$(RAYON_NUM_THREADS=1 "$ccss" tessellate --abs-flatness "$eps" --triangulate "$obj" -o "$tmp/t.obj")
        echo "-- eps=$e x diag = $eps: tessellate $tline"
        "$tmp/ray_embree" "$tmp/t.obj" "$tmp/rays.txt" "$tmp/embree.txt" 10
        python3 "$root/bench/ray_compare.py" "$tmp/rays.txt" "$tmp/ccss.txt" "$tmp/embree.txt" "$eps"
    done
done
