#!/usr/bin/env bash
# Deterministic memory behaviour of `FeatureEvaluator::eval_impl` on the X
# points of a points file (callgrind cache simulation; independent of the
# machine's load, unlike wall time).
#
# usage: bench/feature_cachesim.sh CCSS MESH POINTS [--tlb] [ccss options...]
#   CCSS    the ccss binary (release)
#   MESH    the OBJ (a name is looked up in tests/data/osd/)
#   POINTS  a points file ("face sub u v class"); its X points are used
#   --tlb   model the data TLB instead of the caches: "caches" of 4 KiB
#           lines, 64 entries (first level) and 2,048 entries 16-way
#           (second level)
# Prints per evaluation (warm-up pass + one sample: two per point):
# instructions, first-level and last-level read misses (caches: D1 32 KiB
# 8-way, last level 1 MiB 16-way, the size of one core's L2 on machine A).
set -euo pipefail
if [ $# -lt 3 ]; then
    echo "usage: $0 CCSS MESH POINTS [--tlb] [ccss options...]" >&2
    exit 2
fi
CCSS=$1 MESH=$2 POINTS=$3
shift 3
ROOT=$(cd "$(dirname "$0")/.." && pwd)
[ -f "$MESH" ] || MESH=$ROOT/tests/data/osd/$MESH
SIM=(--I1=32768,8,64 --D1=32768,8,64 --LL=1048576,16,64)
WHAT="D1_read_misses L2_read_misses"
if [ "${1:-}" = --tlb ]; then
    shift
    SIM=(--I1=65536,16,4096 --D1=262144,64,4096 --LL=8388608,16,4096)
    WHAT="pages_missed_64 pages_missed_2048"
fi
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
awk '/^#/ {print; next} $5 == "X" {print}' "$POINTS" >"$TMP/x.txt"
N=$(grep -vc '^#' "$TMP/x.txt")
valgrind --tool=callgrind --cache-sim=yes "${SIM[@]}" \
    --toggle-collect='*FeatureEvaluator*eval_impl*' --callgrind-out-file="$TMP/cg" \
    "$CCSS" bench features "$MESH" --points-file "$TMP/x.txt" --samples 1 "$@" >/dev/null 2>&1
# Events: Ir Dr Dw I1mr D1mr D1mw ILmr DLmr DLmw (percentages dropped).
callgrind_annotate "$TMP/cg" 2>/dev/null | awk -v n="$N" -v what="$WHAT" '
    /PROGRAM TOTALS/ && !done {
        gsub(",", ""); gsub(/\([^)]*\)/, ""); $0 = $0; split(what, w, " ")
        printf "points=%d instr=%.1f %s=%.3f %s=%.3f\n", n, $1 / (2 * n), w[1], $5 / (2 * n), w[2], $8 / (2 * n)
        done = 1
    }'
