#!/usr/bin/env bash
# Miri (nightly) on the unit tests of ccss-core and ccss-ffi: undefined
# behaviour in the unsafe code (the C ABI's pointer handling, the core's
# caller-slice views) fails the run. Tests too slow for Miri's interpreter
# (about 1000x slower than native) are `#[cfg_attr(miri, ignore)]` in the
# source; the rest use `cfg(miri)` sizes. Feature `ccss-core/miri` gives
# libm's software square root (Miri cannot run its x86 inline assembly).
#
# Usage: scripts/miri.sh [SECONDS]   total time bound (default 600); exits
# non-zero on any failure, UB report or time-out. Needs `rustup +nightly
# component add miri rust-src`. Prints tests run / ignored per crate.
set -euo pipefail
cd "$(dirname "$0")/.."
limit=${1:-600}
export CARGO_TARGET_DIR=${CARGO_TARGET_DIR:-target}
export MIRIFLAGS=${MIRIFLAGS:-}
start=$(date +%s)
status=0
# ccss-ffi: these run (status/message tables, the panic guard, argument
# checks that need no build, and the handle checks on an evaluator and a
# feature evaluator of the cube, whose standard tables come from the baked
# file under Miri: `build_set` in ffi/src/tables.rs). The rest take minutes
# each interpreted (FUZZING.md, "Miri").
ffi_tests=(tests::status:: new_status_values_are_appended weights_check_reports_continuity
  new_statuses_have_messages options_default_and_checks depth_method_values_are_stable
  garbage_foreign_and_overwritten_handles_are_refused
  feature_handles_garbage_and_foreign_name_the_feature_evaluator
  index_block_life_cycle)
for crate in ccss-core ccss-ffi; do
  filter=()
  if [ "$crate" = ccss-ffi ]; then filter=("${ffi_tests[@]}"); fi
  left=$((limit - ($(date +%s) - start)))
  if [ "$left" -le 0 ]; then
    echo "miri: $crate: not run, the ${limit} s bound is used up" >&2
    status=1
    break
  fi
  log=$(mktemp)
  set +e
  timeout "$left" cargo +nightly miri test -p "$crate" --lib --features ccss-core/miri \
    -- "${filter[@]}" 2>&1 | tee "$log"
  rc=${PIPESTATUS[0]}
  set -e
  summary=$(grep -E '^test result:' "$log" | tail -1 || true)
  rm -f "$log"
  if [ "$rc" -eq 124 ]; then
    echo "miri: $crate: timed out (bound ${limit} s in all)" >&2
    status=1
  elif [ "$rc" -ne 0 ]; then
    echo "miri: $crate: FAILED (exit $rc): ${summary:-no test summary}" >&2
    status=1
  else
    run=$(sed -E 's/.* ([0-9]+) passed.*/\1/' <<<"$summary")
    ign=$(sed -E 's/.* ([0-9]+) ignored.*/\1/' <<<"$summary")
    out=$(sed -E 's/.* ([0-9]+) filtered out.*/\1/' <<<"$summary")
    echo "miri: $crate: $run tests run, $ign ignored, $out not selected; no undefined behaviour"
  fi
done
echo "miri: $(( $(date +%s) - start )) s"
exit "$status"
