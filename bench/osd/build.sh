#!/bin/sh
# Build the OpenSubdiv 3.5 oracle/benchmark harnesses: osd_eval (patch
# evaluation, benchmark peer) and osd_refine (uniform refinement + limit
# positions with creases, corners, holes and boundary modes).
# Usage: bench/osd/build.sh OUTDIR
set -eu
if [ $# -ne 1 ]; then
    echo "usage: $0 OUTDIR" >&2
    exit 2
fi
OUTDIR=$1
HERE=$(cd "$(dirname "$0")" && pwd)
CXX=${CXX:-g++}

if ! command -v "$CXX" >/dev/null 2>&1; then
    echo "error: C++ compiler '$CXX' not found" >&2
    exit 1
fi
# Check that the OpenSubdiv headers (Debian: libosd-dev) are usable.
if ! printf '#include <opensubdiv/far/patchTableFactory.h>\nint main(){return 0;}\n' \
        | "$CXX" -std=c++17 -x c++ -fsyntax-only - 2>/dev/null; then
    echo "error: OpenSubdiv headers not found (<opensubdiv/far/patchTableFactory.h>)." >&2
    echo "       Install them, e.g.: apt-get install libosd-dev" >&2
    exit 1
fi

mkdir -p "$OUTDIR"
"$CXX" -O2 -std=c++17 "$HERE/osd_eval.cpp" -losdCPU -o "$OUTDIR/osd_eval"
"$CXX" -O2 -std=c++17 "$HERE/osd_refine.cpp" -losdCPU -o "$OUTDIR/osd_refine"
echo "built $OUTDIR/osd_eval $OUTDIR/osd_refine"
