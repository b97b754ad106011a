#!/bin/sh
# Regenerates the table and the pictures of docs/REMESH.md: remeshes the public scans
# of ../shared/data/scans (or $SCANS) at J = 5 over about 300 base faces and renders
# each result with the viewer (headless, under xvfb-run when there is no display).
#
#   scripts/remesh_docs.sh [BUILD_DIR]   (default: build; needs osdmra and the viewer)
set -eu
build=${1:-build}
scans=${SCANS:-../shared/data/scans}
echo "| mesh | input vertices | input faces | base faces | levels | output faces | feature edges | RMS | Hausdorff | flipped | zero-area | crossing pairs | time (s) |"
echo "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
for name in stanford-bunny spot rocker-arm fandisk; do
  out=/tmp/osdmra-remesh-$name.obj
  json=$("$build/osdmra" remesh "$scans/$name.obj" --base-faces 300 --levels 5 -o "$out" --json)
  python3 - "$name" "$json" <<'PY'
import json, sys
n, j = sys.argv[1], json.loads(sys.argv[2])
print(f"| {n} | {j['input_vertices']:,} | {j['input_faces']:,} | {j['base_faces']} | {j['levels']} | "
      f"{j['faces']:,} | {j['feature_edges']} | {100*j['rms_relative']:.4f}% | "
      f"{100*j['hausdorff_relative']:.3f}% | {j['flipped_triangles']} | {j['degenerate_triangles']} | "
      f"{j['self_intersections']} | {j['seconds']:.2f} |")
PY
  if [ -x "$build/viewer/osdmra-viewer" ]; then
    if [ -z "${DISPLAY:-}" ]; then
      xvfb-run -a -s "-screen 0 1280x1024x24" "$build/viewer/osdmra-viewer" "$out" \
        --scheme linear --budget 20000 --view iso --size 1200x600 \
        --screenshot "docs/images/remesh-$name.png" >/dev/null
    else
      "$build/viewer/osdmra-viewer" "$out" --scheme linear --budget 20000 --view iso \
        --size 1200x600 --screenshot "docs/images/remesh-$name.png" >/dev/null
    fi
  fi
done
