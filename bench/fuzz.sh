#!/bin/sh
# Long runs of the stable mutation drivers that run inside `cargo test`
# (the cargo-fuzz targets: fuzz/run.sh, FUZZING.md): the structure-aware
# mutation driver over the core
# builders, evaluation, mass properties and voxelization
# (tests/tests/fuzz_driver.rs) and the OBJ reader driver
# (cli/src/io/mesh_in.rs, test fuzz_obj_reader). Prints executions/s.
#   bench/fuzz.sh [ITERATIONS]   (default 100000)
set -eu
n=${1:-100000}
cd "$(dirname "$0")/.."
CCSS_FUZZ_ITERS=$n cargo test --release -p ccss-tests --test fuzz_driver -- --nocapture 2>&1 | grep -E 'fuzz:|test result'
CCSS_FUZZ_ITERS=$n cargo test --release -p ccss-cli --lib fuzz_obj_reader -- --nocapture 2>&1 | grep -E 'fuzz:|test result'
