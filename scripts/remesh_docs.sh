#!/bin/sh
# The pictures of docs/REMESH.md: three public scans of ../shared/data/scans (or $SCANS)
# remeshed at J = 4 over 300 base faces, drawn by the viewer as wireframe over shading
# (headless, under xvfb-run when there is no display). The table comes from
# scripts/remesh_sweep.sh.
#
#   scripts/remesh_docs.sh [BUILD_DIR]   (default: build; needs osdmra and the viewer)
set -eu
build=${1:-build}
scans=${SCANS:-../shared/data/scans}
for file in fertility.off camelhead.off elephant.obj; do
  name=${file%.*}
  out=/tmp/osdmra-remesh-$name.obj
  "$build/osdmra" remesh "$scans/$file" --base-faces 300 --levels 4 -o "$out" >/dev/null
  set -- "$build/viewer/osdmra-viewer" "$out" --scheme linear --layout lod --budget 10000000 --view iso \
    --wireframe --size 1200x800 --screenshot "docs/images/remesh-$name.png"
  if [ -z "${DISPLAY:-}" ]; then
    xvfb-run -a -s "-screen 0 1280x1024x24" "$@" >/dev/null
  else
    "$@" >/dev/null
  fi
  echo "docs/images/remesh-$name.png"
done
