#!/bin/sh
# Build the CGAL reference Boolean and mesh-measurement tool (boolean_ref.cpp)
# used by the oracle test of `ccss boolean` (cli/tests/boolean_oracle.rs) and
# by bench/boolean_bench.sh. Needs a C++17 compiler, CGAL 5 headers, GMP and
# MPFR (Debian: libcgal-dev). Rebuilds only when the source is newer than
# the binary (CGAL takes about a minute to compile).
# Usage: bench/boolean/build.sh OUTDIR      (prints the binary's path)
set -eu
if [ $# -ne 1 ]; then
    echo "usage: $0 OUTDIR" >&2
    exit 2
fi
OUTDIR=$1
HERE=$(cd "$(dirname "$0")" && pwd)
CXX=${CXX:-g++}
BIN="$OUTDIR/boolean_ref"

if ! command -v "$CXX" >/dev/null 2>&1; then
    echo "error: C++ compiler '$CXX' not found" >&2
    exit 1
fi
if ! printf '#include <CGAL/Polygon_mesh_processing/corefinement.h>\nint main(){return 0;}\n' \
        | "$CXX" -std=c++17 -x c++ -fsyntax-only - 2>/dev/null; then
    echo "error: CGAL headers not found (<CGAL/Polygon_mesh_processing/corefinement.h>)." >&2
    echo "       Install them, e.g.: apt-get install libcgal-dev" >&2
    exit 1
fi
mkdir -p "$OUTDIR"
if [ ! -x "$BIN" ] || [ "$HERE/boolean_ref.cpp" -nt "$BIN" ] || [ "$0" -nt "$BIN" ]; then
    # Build to a temporary name: concurrent test processes never see half a binary.
    "$CXX" -O2 -DNDEBUG -std=c++17 -w "$HERE/boolean_ref.cpp" -o "$BIN.tmp.$$" -lgmp -lmpfr
    mv -f "$BIN.tmp.$$" "$BIN"
fi
echo "$BIN"
