#!/bin/sh
# Builds the cargo-fuzz targets (libFuzzer + AddressSanitizer, debug
# assertions on; without comparison tracing, which halved the speed of the
# numeric targets: the OBJ tokens come from the dictionary obj.dict) and runs each for SECONDS (default 15) from the seed
# corpora of fuzz/seed.sh; fails on the first crash, panic, leak, timeout
# (an input slower than 10 s) or out-of-memory. Prints executions and
# executions/s per target. The stable toolchain is enough: RUSTC_BOOTSTRAP=1
# lets it accept cargo-fuzz's -Z flags (it ships the ASan runtime).
#   fuzz/run.sh [SECONDS] [TARGET...]     (default: every target)
# Needs `cargo install cargo-fuzz --version 0.13.2 --locked`. Crash inputs
# land in fuzz/artifacts/<target>/ (reproduce: cargo fuzz run <target> <file>).
set -eu
secs=${1:-15}
[ $# -gt 0 ] && shift
cd "$(dirname "$0")"
export RUSTC_BOOTSTRAP=1
targets=${*:-"obj topology evaluator eval tessellate voxel measure refine feature ffi"}
[ -d corpus/ffi ] || ./seed.sh corpus
t0=$(date +%s)
cargo fuzz build --no-trace-compares
echo "fuzz: build $(($(date +%s) - t0)) s"
for t in $targets; do
  log=$(mktemp)
  if ! cargo fuzz run --no-trace-compares "$t" "corpus/$t" -- -max_total_time="$secs" -timeout=10 \
    -rss_limit_mb=2048 -max_len=16384 -dict=obj.dict -print_final_stats=1 >"$log" 2>&1; then
    tail -60 "$log"
    echo "fuzz: target $t FAILED (input in fuzz/artifacts/$t/)" >&2
    rm -f "$log"
    exit 1
  fi
  runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log")
  rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log")
  echo "fuzz: $t: $runs executions in ${secs} s, $rate exec/s"
  rm -f "$log"
done
echo "fuzz: all targets passed ($(($(date +%s) - t0)) s)"
