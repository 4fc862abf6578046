#!/usr/bin/env bash
# Instructions per evaluation (callgrind) of `ccss bench features` and of
# OpenSubdiv's `osd_eval --tags` on the same points: deterministic, unlike
# wall time on a shared machine.
#
# usage: bench/feature_instr.sh CCSS OSD_EVAL MESH POINTS [ccss options...]
#   CCSS      the ccss binary (release)
#   OSD_EVAL  bench/osd/build.sh's osd_eval
#   MESH      the OBJ (its tags are honoured by both)
#   POINTS    a points file ("face sub u v class"); only its X points are
#             counted (keep it small: 2,000 points take a few seconds)
# Prints "ccss_instr_per_eval=N osd_instr_per_eval=M" for the X points.
# ccss: collected inside `FeatureEvaluator::eval_impl` (a warm-up pass plus
# one sample: two evaluations per point); OpenSubdiv: inside `runPass` (one
# pass with --repeat 1: one evaluation per point).
set -euo pipefail
if [ $# -lt 4 ]; then
    echo "usage: $0 CCSS OSD_EVAL MESH POINTS [ccss options...]" >&2
    exit 2
fi
CCSS=$1 OSD=$2 MESH=$3 POINTS=$4
shift 4
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
awk '/^#/ {print; next} $5 == "X" {print}' "$POINTS" >"$TMP/x.txt"
N=$(grep -vc '^#' "$TMP/x.txt")

total() {
    callgrind_annotate "$1" 2>/dev/null | awk '/PROGRAM TOTALS/ && !done {gsub(",", "", $1); print $1; done = 1}'
}

valgrind --tool=callgrind --toggle-collect='*FeatureEvaluator*eval_impl*' \
    --callgrind-out-file="$TMP/ccss.cg" \
    "$CCSS" bench features "$MESH" --points-file "$TMP/x.txt" --samples 1 "$@" >/dev/null 2>&1
valgrind --tool=callgrind --toggle-collect='*runPass*' \
    --callgrind-out-file="$TMP/osd.cg" \
    "$OSD" "$MESH" "$TMP/x.txt" --tags --repeat 1 >/dev/null 2>&1
C=$(total "$TMP/ccss.cg")
O=$(total "$TMP/osd.cg")
echo "points=$N ccss_instr_per_eval=$((C / (2 * N))) osd_instr_per_eval=$((O / N))"
