#!/bin/sh
# The robustness table of docs/REMESH.md: remeshes the public scans of
# ../shared/data/scans (or $SCANS) over 150, 300 and 600 base faces at J = 4 and 5 and
# prints what is left of each (flipped, zero-area and crossing triangles) with the
# distances and the time of remesh().
#
#   scripts/remesh_sweep.sh [BUILD_DIR]   (default: build)
set -eu
build=${1:-build}
scans=${SCANS:-../shared/data/scans}
out=$(mktemp /tmp/osdmra-sweep-XXXXXX.obj)
trap 'rm -f "$out"' EXIT
echo "| mesh | base faces asked | base faces | levels | flipped | zero-area | crossing pairs | RMS | Hausdorff | time (s) |"
echo "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
for name in stanford-bunny spot rocker-arm fandisk; do
  for n in 150 300 600; do
    for J in 4 5; do
      "$build/osdmra" remesh "$scans/$name.obj" --base-faces "$n" --levels "$J" -o "$out" --json |
        python3 -c "
import json, sys
j = json.load(sys.stdin)
print(f\"| $name | $n | {j['base_faces']} | $J | {j['flipped_triangles']} | {j['degenerate_triangles']} | \"
      f\"{j['self_intersections']} | {100*j['rms_relative']:.4f}% | {100*j['hausdorff_relative']:.3f}% | \"
      f\"{j['seconds']:.2f} |\")"
    done
  done
done
