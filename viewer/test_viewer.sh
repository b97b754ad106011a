#!/bin/sh
# Headless test of osdmra-viewer (registered with ctest from viewer/CMakeLists.txt).
#
#   test_viewer.sh VIEWER IMAGE_CHECK MESH OUTDIR CLI
#
# Renders MESH at two budgets and in smooth mode under a virtual X server, then
# checks the PNGs: both exist, they differ, and the head covers a sensible part of
# each. The steps whose analysis is slow (fitting every level, remeshing) take MESH's
# level 4 (2,048 faces of 32,768), made by the osdmra tool CLI: the same head, and a
# test that stays quick under the sanitizers. Exits 77 (ctest: skipped) when xvfb-run
# is not installed.
set -eu

if [ "${1:-}" != "--inside-xvfb" ]; then
  if ! command -v xvfb-run >/dev/null 2>&1; then
    echo "SKIP: xvfb-run is not installed (Debian: apt-get install xvfb xauth)"
    exit 77
  fi
  # One X server for every render.
  exec xvfb-run -a -s "-screen 0 1280x1024x24" sh "$0" --inside-xvfb "$@"
fi
shift
viewer=$1 check=$2 mesh=$3 out=$4 cli=$5
rm -rf "$out"
mkdir -p "$out"

step() { echo "+ $*"; "$@"; }

step "$cli" analyze "$mesh" --wavelets lazy -o "$out/head.mra" >/dev/null
step "$cli" synthesize "$out/head.mra" --level 4 -o "$out/head4.obj"

step "$viewer" "$mesh" --budget 500 --screenshot "$out/budget-500.png" --size 800x400
step "$viewer" "$mesh" --budget 16098 --screenshot "$out/budget-16098.png" --size 800x400
# Smooth mode: the viewer checks glGetError after drawing and fails on any error.
step "$viewer" "$mesh" --budget 4054 --smooth --tess 2 --layout lod --screenshot "$out/smooth.png" \
  --size 400x400
step "$viewer" "$mesh" --budget 2000 --scheme linear --color level --wireframe --view iso \
  --screenshot "$out/linear-level.png" --size 800x400

# Fitted once per level (--placement levels); an unknown placement is refused.
step "$viewer" "$out/head4.obj" --budget 800 --scheme linear --placement levels \
  --screenshot "$out/levels.png" --size 800x400
if "$viewer" "$mesh" --placement bogus --screenshot "$out/bogus.png" 2>"$out/bogus.err"; then
  echo "FAIL: --placement bogus accepted"; exit 1
fi
grep -q 'placement must be' "$out/bogus.err" || { echo "FAIL: no placement message"; exit 1; }

# Through the remesher (--remesh): the head is remeshed over its own new base, its
# distance to the input measured with --samples a side.
step "$viewer" "$out/head4.obj" --remesh --base-faces 100 --levels 3 --budget 1500 --samples 5000 \
  --screenshot "$out/remesh.png" --size 800x400 >"$out/remesh.txt"
grep -q 'remeshed over 100 base faces' "$out/remesh.txt" || { echo "FAIL: no remeshing report"; exit 1; }
if "$viewer" "$mesh" --remesh --samples -1 --screenshot "$out/bad-samples.png" 2>"$out/samples.err"; then
  echo "FAIL: --samples -1 accepted"; exit 1
fi
grep -q -- '--samples' "$out/samples.err" || { echo "FAIL: no --samples message"; exit 1; }
if "$viewer" "$mesh" --remesh --seed -1 --screenshot "$out/bad-seed.png" 2>"$out/seed.err"; then
  echo "FAIL: --seed -1 accepted"; exit 1
fi
grep -q -- '--seed' "$out/seed.err" || { echo "FAIL: no --seed message"; exit 1; }

# The slider benchmark: runs, reports JSON with a frame time per step (2K-2 steps).
step "$viewer" "$mesh" --bench-slider 3 --size 400x200 --json >"$out/bench.json"
grep -q '"steps": 4,' "$out/bench.json" || { echo "FAIL: bench-slider output"; exit 1; }
grep -q '"frame_ms": {"median": ' "$out/bench.json" || { echo "FAIL: no frame times"; exit 1; }

for image in budget-500 budget-16098 smooth linear-level levels remesh; do
  step "$check" coverage "$out/$image.png" 0.10 0.90
done
# Only the right (level of detail) pane may differ; 500 triangles against 16,098
# changes a few percent of the pixels.
step "$check" differ "$out/budget-500.png" "$out/budget-16098.png" 0.01

# Errors: a bad mesh and no display both fail with a message and leave no file.
if "$viewer" "$out/missing.obj" --screenshot "$out/bad.png" 2>"$out/bad.err"; then
  echo "FAIL: a missing mesh was accepted"; exit 1
fi
grep -q '^osdmra-viewer: ' "$out/bad.err" || { echo "FAIL: no error message"; exit 1; }
if env -u DISPLAY "$viewer" "$mesh" --screenshot "$out/nodisplay.png" 2>"$out/nodisplay.err"; then
  echo "FAIL: rendered without a display"; exit 1
fi
grep -q '^osdmra-viewer: ' "$out/nodisplay.err" || { echo "FAIL: no error message"; exit 1; }
for f in bad.png nodisplay.png bad-samples.png bad-seed.png; do
  [ ! -e "$out/$f" ] || { echo "FAIL: $f was written"; exit 1; }
done
echo "viewer test passed"
