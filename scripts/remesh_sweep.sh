#!/bin/sh
# The robustness table of docs/REMESH.md: remeshes every mesh of ../shared/data/scans
# (or $SCANS) over 150, 300 and 600 base faces at J = 4 and 5 and prints, for each, the
# base size obtained, what is left (flipped, zero-area, crossing triangles; of those, the
# pairs where the input crosses itself), how much the
# clean-up had to move, the distances to the input, whether genus, boundary loops and
# components were kept, and the time of remesh().
#
#   scripts/remesh_sweep.sh [BUILD_DIR] [SIZES] [LEVELS]
#   (defaults: build, "150 300 600", "4 5"; $MESHES: names to run, default all;
#   $REMESH_ARGS: further options of every remeshing, e.g. "--stages vertex")
set -eu
build=${1:-build}
sizes=${2:-150 300 600}
levels=${3:-4 5}
scans=${SCANS:-../shared/data/scans}
out=$(mktemp /tmp/osdmra-sweep-XXXXXX.obj)
trap 'rm -f "$out"' EXIT
echo "| mesh | input faces | base faces asked | base faces | J | flipped | zero-area | crossing pairs | clean-up moved | RMS | Hausdorff | topology kept | time (s) |"
echo "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|---:|"
for path in "$scans"/*.obj "$scans"/*.off "$scans"/*.ply; do
  [ -f "$path" ] || continue
  name=$(basename "$path"); name=${name%.*}
  if [ -n "${MESHES:-}" ] && ! echo " $MESHES " | grep -q " $name "; then continue; fi
  # The input's topology: of the mesh remesh() gets (unreferenced vertices dropped, as
  # remesh does: a base as large as the input, not split).
  clean=$(mktemp /tmp/osdmra-sweep-XXXXXX.obj)
  if ! "$build/osdmra" remesh "$path" --base-faces 16777216 --levels 0 -o "$clean" \
        >/dev/null 2>/tmp/osdmra-sweep-err ||
     ! topo_in=$("$build/osdmra" info "$clean" --json 2>/tmp/osdmra-sweep-err); then
    rm -f "$clean"
    echo "| $name | | | | | | | | | | | rejected: $(head -c 200 /tmp/osdmra-sweep-err | tr '|\n' '/ ') | |"
    continue
  fi
  rm -f "$clean"
  for n in $sizes; do
    for J in $levels; do
      # shellcheck disable=SC2086 # REMESH_ARGS is a list of options
      json=$("$build/osdmra" remesh "$path" --base-faces "$n" --levels "$J" ${REMESH_ARGS:-} \
        -o "$out" --json)
      topo_out=$("$build/osdmra" info "$out" --json)
      python3 -c "
import json, sys
j = json.loads(sys.argv[1]); a = json.loads(sys.argv[2])['mesh']; b = json.loads(sys.argv[3])['mesh']
keys = ('genus', 'boundary_loops', 'components')
kept = 'yes' if all(a[k] == b[k] for k in keys) else 'NO (' + ', '.join(f'{k} {a[k]}->{b[k]}' for k in keys if a[k] != b[k]) + ')'
c = j['clean_up']
own = j.get('self_intersections_at_input_crossings', 0)
crossing = f\"{j['self_intersections']}\" + (f\" ({own} the input's)\" if own else '')
print(f\"| $name | {j['input_faces']} | $n | {j['base_faces']} | $J | {j['flipped_triangles']} | {j['degenerate_triangles']} | \"
      f\"{crossing} | {c['moved_points']} | {100*j['rms_relative']:.4f}% | {100*j['hausdorff_relative']:.3f}% | {kept} | \"
      f\"{j['seconds']:.2f} |\")" "$json" "$topo_in" "$topo_out"
    done
  done
done
