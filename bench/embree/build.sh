#!/bin/sh
# Builds bench/embree/ray_embree (and closest_embree beside it) against
# Embree 3 (Debian: libembree-dev).
# Usage: bench/embree/build.sh [OUT]   (default OUT: bench/embree/ray_embree;
# the closest-point host goes to OUT's directory as closest_embree)
# Exits 3 with a message when Embree 3 is not installed.
set -eu
here=$(cd "$(dirname "$0")" && pwd)
out=${1:-$here/ray_embree}
if ! printf '#include <embree3/rtcore.h>\nint main(void){return 0;}\n' |
  ${CXX:-c++} -x c++ - -o /dev/null -lembree3 2>/dev/null; then
  echo "bench/embree/build.sh: Embree 3 not found (apt-get install libembree-dev)" >&2
  exit 3
fi
${CXX:-c++} -std=c++17 -O2 -march=native -Wall -Wextra -o "$out" "$here/ray_embree.cpp" -lembree3
${CXX:-c++} -std=c++17 -O2 -march=native -Wall -Wextra -o "$(dirname "$out")/closest_embree" "$here/closest_embree.cpp" -lembree3
echo "$out"
