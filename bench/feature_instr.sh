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
# Prints "points=N evaluations=E ccss_instr_per_eval=I osd_instr_per_eval=M"
# for the X points. ccss: collected inside `FeatureEvaluator::eval_impl`,
# divided by the calls to it that callgrind counted (a warm-up pass plus
# one sample, whose passes repeat until it lasts 20 ms: two or more
# evaluations per point, as many as the machine's speed under valgrind
# asks for); OpenSubdiv: inside `runPass` (one pass with --repeat 1: one
# evaluation per point).
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
# Calls to eval_impl: the "calls=" line after each "cfn=" naming it.
CALLS=$(awk '
    /^c?fn=/ {
        id = $1; sub(/^c?fn=/, "", id)
        if (index($0, " ") > 0) name[id] = substr($0, index($0, " ") + 1)
        is_eval = ($0 ~ /^cfn=/ && name[id] ~ /eval_impl/); next
    }
    /^calls=/ && is_eval { split($1, c, "="); n += c[2]; is_eval = 0 }
    END { print n + 0 }' "$TMP/ccss.cg")
if [ "$CALLS" -eq 0 ]; then
    echo "feature_instr.sh: callgrind counted no call to eval_impl" >&2
    exit 1
fi
echo "points=$N evaluations=$CALLS ccss_instr_per_eval=$((C / CALLS)) osd_instr_per_eval=$((O / N))"
