#!/usr/bin/env bash
# Side-by-side single-threaded evaluation timings: ccss (Rust API and C ABI)
# vs OpenSubdiv 3.5, on identical points.
#
# usage: bench/run_eval_bench.sh [MESH.obj ...]
#        (default: catmark_torus, catmark_righthanded from tests/data/osd and
#        icosa_quads, bipyramid12, hexprism written by bench/meshes/gen_meshes.py)
#
# Environment:
#   POINTS   points per class (default 100000)
#   SEED     seed of the point generator (default 1)
#   RUNS     runs of each tool per mesh, interleaved; the table shows the median (default 3)
#   CLASSES  point classes (default RXUMNDCK; see `ccss bench eval --help`)
#   SECOND   1 (default): also time position + first + second derivatives; 0: skip
#
# Steps: build ccss (release, CLI and libccss), the C ABI driver
# bench/c_eval_bench.c (linked against libccss.a, -O2) and the OSD harness
# (bench/osd/build.sh into $CARGO_TARGET_DIR/osd-bench; skipped with a note
# when the OpenSubdiv headers, Debian libosd-dev, are missing); write one
# points file per mesh with `ccss bench eval --classes $CLASSES
# --write-points`; then time, interleaved, on exactly those points:
#   rust   `ccss bench eval --points-file` (Evaluator::eval_derivs per point;
#          with --second Evaluator::eval_second),
#   cabi   `c_eval_bench` (ccss_evaluator_eval / _eval_second per point, which
#          also compute the unit normal; cabi-batch: ccss_evaluator_eval_batch
#          over chunks of 4096; cabi-derivs, cabi-batch-derivs: the same
#          without the normal, ccss_evaluator_eval_derivs / _second_derivs /
#          _batch_derivs, the outputs osd_eval computes),
#   osd    `osd_eval` (FindPatch + EvaluateBasis<double> + the CV sums).
# X points are also split by sub-class (Xn: one extraordinary vertex of
# valence n; Xmulti: several) into separate files for osd_eval and the C
# driver. Every command run is printed, prefixed with '$ '.
set -euo pipefail

ROOT=$(cd "$(dirname "$0")/.." && pwd)
cd "$ROOT"
POINTS=${POINTS:-100000}
SEED=${SEED:-1}
RUNS=${RUNS:-3}
CLASSES=${CLASSES:-RXUMNDCK}
SECOND=${SECOND:-1}
TARGET=${CARGO_TARGET_DIR:-target}
OUT=$TARGET/osd-bench
if [ $# -gt 0 ]; then
    MESHES=("$@")
else
    run_gen=1
    MESHES=(tests/data/osd/catmark_torus.obj tests/data/osd/catmark_righthanded.obj
        "$OUT/meshes/icosa_quads.obj" "$OUT/meshes/bipyramid12.obj" "$OUT/meshes/hexprism.obj")
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
echo "points:  $POINTS per class ($CLASSES), seed $SEED, $RUNS interleaved runs per tool (median shown)"
echo

echo "== build"
run cargo build --release -p ccss-cli -p ccss-ffi
CCSS=$TARGET/release/ccss
mkdir -p "$OUT/points" "$OUT/results"
CABI=$OUT/c_eval_bench
run "${CC:-cc}" -O2 -std=c11 -Wall -Wextra -Wpedantic -Werror -Iinclude bench/c_eval_bench.c \
    "$TARGET/release/libccss.a" -lpthread -ldl -lm -o "$CABI"
OSD=""
if printf '#include <opensubdiv/far/patchTableFactory.h>\nint main(){return 0;}\n' |
    "${CXX:-g++}" -std=c++17 -x c++ -fsyntax-only - 2>/dev/null; then
    run bench/osd/build.sh "$OUT"
    OSD=$OUT/osd_eval
else
    echo "note: OpenSubdiv headers not found (apt-get install libosd-dev); OSD timings skipped"
fi
if [ -n "${run_gen:-}" ]; then
    run python3 bench/meshes/gen_meshes.py "$OUT/meshes"
fi
echo

# Derivative modes: "" (P, dP/du, dP/dv) and, with SECOND=1, "--second".
MODES=("")
if [ "$SECOND" = 1 ]; then MODES+=("--second"); fi

declare -a TABLE
for mesh in "${MESHES[@]}"; do
    name=$(basename "$mesh" .obj)
    pts=$OUT/points/$name.pts
    res=$OUT/results/$name
    echo "== $mesh"
    run "$CCSS" bench eval "$mesh" --points "$POINTS" --seed "$SEED" --classes "$CLASSES" \
        --write-points "$pts"
    # Sub-class files (sixth column written by ccss) for osd_eval and c_eval_bench.
    subs=$(awk '!/^#/ && $5 == "X" && NF >= 6 {print $6}' "$pts" | sort -u |
        awk '{k = substr($0, 2); print (k ~ /^[0-9]+$/ ? k : 1e9), $0}' | sort -n | cut -d' ' -f2)
    nsubs=$(printf '%s\n' $subs | awk 'NF' | wc -l)
    if [ "$nsubs" -gt 1 ]; then
        for s in $subs; do
            awk -v s="$s" '!/^#/ && $5 == "X" && $6 == s' "$pts" >"$pts.$s"
        done
    fi
    rm -f "$res".*
    for r in $(seq 1 "$RUNS"); do
        for mode in "${MODES[@]}"; do
            m=${mode:+2}
            run "$CCSS" bench eval "$mesh" --points-file "$pts" $mode | tee "$res.rust$m.$r"
            run "$CABI" "$mesh" "$pts" $mode | tee "$res.cabi$m.$r"
            if [ "$nsubs" -gt 1 ]; then
                for s in $subs; do
                    run "$CABI" "$mesh" "$pts.$s" $mode | tee "$res.cabi$m.$s.$r"
                done
            fi
            if [ -n "$OSD" ]; then
                run "$OSD" "$mesh" "$pts" $mode | tee "$res.osd$m.$r"
                if [ "$nsubs" -gt 1 ]; then
                    for s in $subs; do
                        run "$OSD" "$mesh" "$pts.$s" $mode | tee "$res.osd$m.$s.$r"
                    done
                fi
            fi
        done
    done
    ratio() { # ratio OSD CCSS
        if [ "$1" != "-" ] && [ "$2" != "-" ]; then
            awk -v a="$2" -v b="$1" 'BEGIN { printf "%.2f", b / a }'
        else
            echo "-"
        fi
    }
    # peer TOOLFILEPREFIX TOOLNAME CLASS: median over the runs (sub-classes
    # from their own files, reported there as class X).
    peer() {
        case $3 in
            R | X | [A-Z]) ns_of "$3" "$2" "$1".[0-9]* | median ;;
            *) ns_of X "$2" "$1"."$3".* | median ;;
        esac
    }
    for mode in "${MODES[@]}"; do
        m=${mode:+2}
        for cls in R X $([ "$nsubs" -gt 1 ] && echo $subs) $(echo "$CLASSES" | sed 's/[RX]//g; s/./& /g'); do
            npts=$(points_of "$cls" "$res.rust$m.1")
            [ "${npts:-0}" = 0 ] && continue
            rust=$(ns_of "$cls" ccss "$res.rust$m".* | median)
            cabi=$(peer "$res.cabi$m" cabi "$cls")
            batch=$(peer "$res.cabi$m" cabi-batch "$cls")
            derivs=$(peer "$res.cabi$m" cabi-derivs "$cls")
            bderivs=$(peer "$res.cabi$m" cabi-batch-derivs "$cls")
            o="-"
            if [ -n "$OSD" ]; then o=$(peer "$res.osd$m" osd "$cls"); fi
            label=$cls${m:+ 2nd}
            TABLE+=("$(printf '| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |' \
                "$name" "$label" "$npts" "$rust" "$cabi" "$batch" "$derivs" "$bderivs" "$o" \
                "$(ratio "$o" "$rust")" "$(ratio "$o" "$cabi")" "$(ratio "$o" "$batch")" \
                "$(ratio "$o" "$derivs")" "$(ratio "$o" "$bderivs")")")
        done
    done
    cs=$(setup_of ccss "$res".rust.* | median 3)
    os="-"
    if [ -n "$OSD" ]; then os=$(setup_of osd "$res".osd.[0-9]* | median 3); fi
    TABLE+=("$(printf '| %s | setup | - | %s ms | - | - | - | - | %s ms | - | - | - | - | - |' "$name" "$cs" "$os")")
    echo
done

echo "== results (single thread; ns per point, median of $RUNS interleaved runs; rust: Evaluator::eval_derivs,"
echo "   cabi: ccss_evaluator_eval per point (with the unit normal), batch: ccss_evaluator_eval_batch;"
echo "   derivs: ccss_evaluator_eval_derivs per point (no normal, as osd_eval), batch derivs: _eval_batch_derivs;"
echo "   '2nd': with second derivatives (eval_second, ccss_evaluator_eval_second, osd_eval --second);"
echo "   setup: per-mesh build, ccss topology + evaluator (eigen tables excluded), osd refiner + patch table)"
echo "| mesh | class | points | rust ns | C ABI ns | batch ns | derivs ns | batch derivs ns | OSD ns | OSD/rust | OSD/C ABI | OSD/batch | OSD/derivs | OSD/batch derivs |"
echo "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
for line in "${TABLE[@]}"; do
    echo "$line"
done
