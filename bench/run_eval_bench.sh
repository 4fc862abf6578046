#!/usr/bin/env bash
# Side-by-side single-threaded evaluation timings: ccss vs OpenSubdiv 3.5.
#
# usage: bench/run_eval_bench.sh [MESH.obj ...]
#        (default: tests/data/osd/catmark_torus.obj tests/data/osd/catmark_righthanded.obj)
#
# Environment:
#   POINTS  points per class (default 1000000)
#   SEED    seed of the point generator (default 1)
#   RUNS    runs of each tool per mesh, interleaved; the table shows the median (default 3)
#
# Steps: build ccss (release) and the OSD harness (bench/osd/build.sh into
# target/osd-bench; skipped with a note when the OpenSubdiv headers, Debian
# libosd-dev, are missing), write one points file per mesh with
# `ccss bench eval --write-points`, then time both tools on exactly those
# points (`ccss bench eval --points-file`, `osd_eval MESH POINTS`). X points
# are also split by sub-class (one extraordinary vertex of valence n: Xn;
# several: Xmulti) into separate files for osd_eval; ccss reports the
# sub-classes itself. Every command run is printed, prefixed with '$ '.
set -euo pipefail

ROOT=$(cd "$(dirname "$0")/.." && pwd)
cd "$ROOT"
POINTS=${POINTS:-1000000}
SEED=${SEED:-1}
RUNS=${RUNS:-3}
TARGET=${CARGO_TARGET_DIR:-target}
OUT=$TARGET/osd-bench
if [ $# -gt 0 ]; then
    MESHES=("$@")
else
    MESHES=(tests/data/osd/catmark_torus.obj tests/data/osd/catmark_righthanded.obj)
fi

run() {
    echo "\$ $*" >&2
    "$@"
}

# median [DECIMALS]: median of the numbers on stdin, one per line; "-" when
# there are none (e.g. only "nan").
median() {
    awk '/^[0-9]+(\.[0-9]*)?$/ {print}' | sort -g | awk -v d="${1:-1}" '{a[NR]=$1} END {
        if (NR == 0) { print "-"; exit }
        m = (NR % 2) ? a[(NR+1)/2] : (a[NR/2]+a[NR/2+1])/2
        printf "%.*f\n", d, m }'
}

# ns_of CLASS TOOL FILE...: the ns_per_eval values of "TOOL class=CLASS" lines.
ns_of() {
    local cls=$1 tool=$2
    shift 2
    cat "$@" 2>/dev/null | awk -v p="$tool class=$cls " 'index($0, p) == 1 {
        for (i = 1; i <= NF; i++) if ($i ~ /^ns_per_eval=/) print substr($i, 13) }'
}

# setup_of TOOL FILE...: the setup_ms values of "TOOL setup_ms=" lines.
setup_of() {
    local tool=$1
    shift
    cat "$@" 2>/dev/null | awk -v p="$tool setup_ms=" 'index($0, p) == 1 {
        split($2, kv, "="); print kv[2] }'
}

# points_of CLASS FILE: the point count of the "ccss class=CLASS" line.
points_of() {
    awk -v p="ccss class=$1 " 'index($0, p) == 1 {
        for (i = 1; i <= NF; i++) if ($i ~ /^points=/) print substr($i, 8) }' "$2"
}

echo "== machine"
echo "arch:    $(uname -m)"
echo "cpu:     $(lscpu 2>/dev/null | sed -n 's/^Model name:[[:space:]]*//p' | head -1)"
echo "nproc:   $(nproc)"
echo "load:    $(cut -d' ' -f1-3 /proc/loadavg 2>/dev/null || echo '?') (1/5/15 min, before the run)"
echo "points:  $POINTS per class, seed $SEED, $RUNS interleaved runs per tool (median shown)"
echo

echo "== build"
run cargo build --release -p ccss-cli
CCSS=$TARGET/release/ccss

OSD=""
if printf '#include <opensubdiv/far/patchTableFactory.h>\nint main(){return 0;}\n' |
    "${CXX:-g++}" -std=c++17 -x c++ -fsyntax-only - 2>/dev/null; then
    run bench/osd/build.sh "$OUT"
    OSD=$OUT/osd_eval
else
    echo "note: OpenSubdiv headers not found (apt-get install libosd-dev); OSD timings skipped"
fi
mkdir -p "$OUT/points" "$OUT/results"
echo

declare -a TABLE
for mesh in "${MESHES[@]}"; do
    name=$(basename "$mesh" .obj)
    pts=$OUT/points/$name.pts
    res=$OUT/results/$name
    echo "== $mesh"
    run "$CCSS" bench eval "$mesh" --points "$POINTS" --seed "$SEED" --write-points "$pts"
    # Sub-class files for osd_eval (sixth column written by ccss).
    subs=$(awk '!/^#/ && $5 == "X" && NF >= 6 {print $6}' "$pts" | sort -u |
        awk '{k = substr($0, 2); print (k ~ /^[0-9]+$/ ? k : 1e9), $0}' | sort -n | cut -d' ' -f2)
    nsubs=$(printf '%s\n' $subs | awk 'NF' | wc -l)
    if [ -n "$OSD" ] && [ "$nsubs" -gt 1 ]; then
        for s in $subs; do
            awk -v s="$s" '!/^#/ && $5 == "X" && $6 == s' "$pts" >"$pts.$s"
        done
    fi
    rm -f "$res".*
    for r in $(seq 1 "$RUNS"); do
        run "$CCSS" bench eval "$mesh" --points-file "$pts" | tee "$res.ccss.$r"
        if [ -n "$OSD" ]; then
            run "$OSD" "$mesh" "$pts" | tee "$res.osd.$r"
            if [ "$nsubs" -gt 1 ]; then
                for s in $subs; do
                    run "$OSD" "$mesh" "$pts.$s" | tee "$res.osd.$s.$r"
                done
            fi
        fi
    done
    row() { # row CLASS CCSS_NS OSD_NS POINTS
        local ratio="-"
        if [ "$2" != "-" ] && [ "$3" != "-" ]; then
            ratio=$(awk -v a="$2" -v b="$3" 'BEGIN { printf "%.2f", b / a }')
        fi
        TABLE+=("$(printf '%-24s %-7s %9s %13s %12s %9s' "$name" "$1" "$4" "$2" "$3" "$ratio")")
    }
    for cls in R X $( [ "$nsubs" -gt 1 ] && echo $subs ); do
        c=$(ns_of "$cls" ccss "$res".ccss.* | median)
        npts=$(points_of "$cls" "$res.ccss.1")
        o="-"
        if [ -n "$OSD" ]; then
            case $cls in
                R | X) o=$(ns_of "$cls" osd "$res".osd.[0-9]* | median) ;;
                *) o=$(ns_of X osd "$res".osd."$cls".* | median) ;;
            esac
        fi
        row "$cls" "$c" "$o" "${npts:-0}"
    done
    cs=$(setup_of ccss "$res".ccss.* | median 3)
    os="-"
    if [ -n "$OSD" ]; then os=$(setup_of osd "$res".osd.[0-9]* | median 3); fi
    TABLE+=("$(printf '%-24s %-7s %9s %13s %12s %9s' "$name" "setup" "-" "$cs ms" "$os ms" "-")")
    echo
done

echo "== results (single thread; ns per evaluation of P, dP/du, dP/dv, median of $RUNS runs;"
echo "   setup: per-mesh build, ccss topology + evaluator (eigen tables excluded), osd refiner + patch table)"
printf '%-24s %-7s %9s %13s %12s %9s\n' mesh class points "ccss ns/eval" "osd ns/eval" "osd/ccss"
for line in "${TABLE[@]}"; do
    echo "$line"
done
