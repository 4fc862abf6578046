#!/bin/sh
# Times `ccss interpolate` per mesh size and solver path at the default
# tolerance 1e-6: CPU time (perf stat -e task-clock: build + assembly +
# solve + OBJ I/O, one thread), peak RSS (/usr/bin/time), iterations.
# usage: bench/interpolate.sh [CCSS] [RUNS]   (default target/release/ccss, 3)
# PATHS="assembled sgs matrix-free" (the default) selects the solver paths;
# MESHES="ttet ... hand2" the meshes.
# CPU time is the minimum over RUNS runs. Meshes: corpus shapes, their
# Catmull-Clark refinements (ccss refine) and bench/data/genus2_polycube.obj.
set -eu
B=${1:-target/release/ccss}
RUNS=${2:-3}
D=$(mktemp -d)
trap 'rm -rf "$D"' EXIT
M=tests/data/osd
cp $M/catmark_toroidal_tet.obj "$D/ttet.obj"
cp $M/catmark_torus.obj "$D/torus0.obj"
cp $M/catmark_lefthanded.obj "$D/hand0.obj"
cp bench/data/genus2_polycube.obj "$D/poly2.obj"
"$B" refine --scheme catmull-clark $M/catmark_torus.obj -o "$D/torus1.obj" >/dev/null
"$B" refine --scheme catmull-clark --levels 2 $M/catmark_torus.obj -o "$D/torus2.obj" >/dev/null
"$B" refine --scheme catmull-clark $M/catmark_lefthanded.obj -o "$D/hand1.obj" >/dev/null
"$B" refine --scheme catmull-clark --levels 2 $M/catmark_lefthanded.obj -o "$D/hand2.obj" >/dev/null
"$B" refine --scheme catmull-clark bench/data/genus2_polycube.obj -o "$D/poly3.obj" >/dev/null
echo "# $(uptime)"
printf 'mesh\tP_vertices\tpath\titerations\tsimilarity\tcpu_ms\tmaxrss_kb\n'
for m in ${MESHES:-ttet torus0 torus1 hand0 torus2 poly2 hand1 poly3 hand2}; do
  for path in ${PATHS:-assembled sgs matrix-free}; do
    case $path in
      assembled) args="" ;;
      sgs) args="--preconditioner symmetric-gauss-seidel" ;;
      matrix-free) args="--matrix-free" ;;
    esac
    best=""
    i=0
    while [ $i -lt "$RUNS" ]; do
      # shellcheck disable=SC2086
      perf stat -x, -e task-clock -o "$D/perf" \
        "$B" interpolate "$D/$m.obj" -o "$D/q.obj" $args >"$D/out"
      ms=$(grep task-clock "$D/perf" | cut -d, -f1)
      if [ -z "$best" ] || [ "$(echo "$ms < $best" | bc)" = 1 ]; then best=$ms; fi
      i=$((i + 1))
    done
    # Peak RSS of ccss alone (a separate run: not perf's).
    # shellcheck disable=SC2086
    /usr/bin/time -o "$D/time" -f '%M' "$B" interpolate "$D/$m.obj" -o "$D/q.obj" $args >/dev/null
    it=$(tr ' ' '\n' <"$D/out" | grep '^iterations=' | cut -d= -f2)
    sim=$(tr ' ' '\n' <"$D/out" | grep '^similarity=' | cut -d= -f2)
    printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$m" "$(grep -c '^v ' "$D/$m.obj")" "$path" \
      "$it" "$sim" "$best" "$(cat "$D/time")"
  done
done
