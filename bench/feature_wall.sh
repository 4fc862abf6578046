#!/usr/bin/env bash
# Wall time (ns per evaluation) of near-feature points against interior
# extraordinary points, issue #24's "within 2x of our interior
# extraordinary cost": five interleaved repeats on one core, the median of
# each. Run it on a quiet machine (the figures are memory-bound: other
# jobs evict the caches).
#
# usage: bench/feature_wall.sh CCSS [REPEATS]
#   CCSS     the ccss binary (release)
#   REPEATS  interleaved repeats (default 5)
# Points: car and bishop near-feature X points (drawn by the pre-tree
# cache, `--cache-depth 2`, so X = the points next to boundary, crease,
# corner and dart vertices), righthanded's extraordinary faces
# (`gen_points.py`, evaluated with `--creasing uniform`), and car's own
# interior extraordinary vertices (`interior_ev_points.py`: faces whose
# 1-ring has no boundary, crease or corner, points within 1/4 of the face
# size of the extraordinary corner, as the near-feature points lie within
# the irregular level-2 pieces; `car_ev`), the reference on the same mesh:
# its points read car's eigen pieces (0.5 MB), the near-feature points
# car's tree of refined pieces (24 MB), so the ratio between the two shows
# what the tree's size costs. Prints one line per file: median, min, max
# and the ratio to righthanded's median; car also its ratio to car_ev's.
set -euo pipefail
if [ $# -lt 1 ]; then
    echo "usage: $0 CCSS [REPEATS]" >&2
    exit 2
fi
CCSS=$1 REPEATS=${2:-5}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
OSD=$ROOT/tests/data/osd
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
x_only() { awk '/^#/ {print; next} $5 == "X" {print}' "$1" >"$2"; }
for m in car bishop; do
    "$CCSS" bench features "$OSD/catmark_$m.obj" --cache-depth 2 --points 20000 \
        --write-points "$TMP/$m.all" >/dev/null
    x_only "$TMP/$m.all" "$TMP/$m.pts"
done
python3 "$ROOT/bench/osd/gen_points.py" "$OSD/catmark_righthanded.obj" 2000 1 >"$TMP/rh.all"
x_only "$TMP/rh.all" "$TMP/rh.pts"
python3 "$ROOT/bench/osd/interior_ev_points.py" "$OSD/catmark_car.obj" 20000 1 0.25 >"$TMP/car_ev.pts"
ns() { awk '/class=X/ {sub("ns_per_eval=", "", $4); print $4}'; }
for _ in $(seq "$REPEATS"); do
    for m in car bishop; do
        taskset -c 1 "$CCSS" bench features "$OSD/catmark_$m.obj" --points-file "$TMP/$m.pts" \
            --samples 3 | ns >>"$TMP/$m.ns"
    done
    taskset -c 1 "$CCSS" bench features "$OSD/catmark_car.obj" --points-file "$TMP/car_ev.pts" \
        --samples 3 | ns >>"$TMP/car_ev.ns"
    taskset -c 1 "$CCSS" bench features "$OSD/catmark_righthanded.obj" --points-file "$TMP/rh.pts" \
        --samples 3 --creasing uniform | ns >>"$TMP/rh.ns"
done
median() { sort -g "$1" | awk '{v[NR] = $1} END {print v[int((NR + 1) / 2)], v[1], v[NR]}'; }
read -r rh _ _ < <(median "$TMP/rh.ns")
echo "load average: $(cut -d' ' -f1-3 /proc/loadavg)"
read -r car_ev _ _ < <(median "$TMP/car_ev.ns")
for m in car bishop rh car_ev; do
    read -r med lo hi < <(median "$TMP/$m.ns")
    same=""
    [ "$m" = car ] && same=" ratio_to_car_ev=$(awk -v a="$med" -v b="$car_ev" 'BEGIN {printf "%.2f", a / b}')"
    echo "$m median_ns=$med min=$lo max=$hi ratio_to_rh=$(awk -v a="$med" -v b="$rh" 'BEGIN {printf "%.2f", a / b}')$same"
done
