#!/usr/bin/env bash
# Paired wall-time comparison of two `ccss` binaries on one tessellation.
#
#   bench/ab_tessellate.sh A B MODEL.obj [ROUNDS] [-- extra bench args]
#
# Runs `A bench tessellate MODEL --adaptive-only --reps 15` and the same
# with B, back to back, ROUNDS times (default 30), alternating which goes
# first. Each run reports its fast decile (vertices / 10th percentile of
# its run times, M vertices/s). Prints the geometric mean of B/A over the
# pairs and the largest figure of each. Adjacent runs share the host's
# slow and fast stretches, so the ratio is steadier than either figure.
#
# Resolution on the 2-vCPU VM of BENCHMARKS.md: A against a copy of A
# gave 0.994; the same pair run as (A, B) and as (B, A) differed by up
# to 3-4 %. Smaller differences are not resolved.
set -euo pipefail
if [ $# -lt 3 ]; then
    sed -n 2,16p "$0"
    exit 2
fi
a=$1
b=$2
model=$3
shift 3
rounds=30
if [ $# -gt 0 ] && [ "$1" != "--" ]; then
    rounds=$1
    shift
fi
[ "${1:-}" = "--" ] && shift
run() {
    "$1" bench tessellate "$model" --adaptive-only --reps 15 "${@:2}" |
        tr ' ' '\n' | sed -n 's/^fast_decile_mvertices_per_s=//p'
}
for r in $(seq "$rounds"); do
    if [ $((r % 2)) = 0 ]; then
        x=$(run "$a" "$@")
        y=$(run "$b" "$@")
    else
        y=$(run "$b" "$@")
        x=$(run "$a" "$@")
    fi
    echo "$x $y"
done | awk '{ s += log($2 / $1); n++; if ($1 > ma) ma = $1; if ($2 > mb) mb = $2 }
    END { printf "pairs=%d geo_mean_b_over_a=%.3f best_a=%.2f best_b=%.2f\n", n, exp(s / n), ma, mb }'
