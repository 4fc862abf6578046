#!/bin/sh
# Times `ccss interpolate` per mesh size, tolerance and preconditioner.
# usage: bench/interpolate.sh [CCSS]   (default target/release/ccss)
# Meshes: corpus shapes and their Catmull-Clark refinements (ccss refine).
set -eu
B=${1:-target/release/ccss}
D=$(mktemp -d)
trap 'rm -rf "$D"' EXIT
M=tests/data/osd
cp $M/catmark_toroidal_tet.obj "$D/ttet.obj"
cp $M/catmark_torus.obj "$D/torus0.obj"
cp $M/catmark_lefthanded.obj "$D/hand0.obj"
"$B" refine --scheme catmull-clark $M/catmark_torus.obj -o "$D/torus1.obj" >/dev/null
"$B" refine --scheme catmull-clark --levels 2 $M/catmark_torus.obj -o "$D/torus2.obj" >/dev/null
"$B" refine --scheme catmull-clark $M/catmark_lefthanded.obj -o "$D/hand1.obj" >/dev/null
printf 'mesh\tP_vertices\tpreconditioner\ttolerance\tresult\n'
for m in ttet torus0 torus1 hand0 torus2 hand1; do
  for pc in block-jacobi none; do
    for tol in 1e-3 1e-6; do
      r=$(/usr/bin/time -f 'maxrss_kb=%M' "$B" interpolate "$D/$m.obj" -o "$D/q.obj" \
        --tolerance $tol --preconditioner $pc --max-iterations 100000 2>&1 | tr '\n' ' ')
      printf '%s\t%s\t%s\t%s\t%s\n' "$m" "$(grep -c '^v ' "$D/$m.obj")" "$pc" "$tol" "$r"
    done
  done
done
