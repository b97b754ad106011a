#!/usr/bin/env bash
# Regenerates the comparison table of docs/LOD.md (issue 14): osdmra's levels of detail
# (both schemes; importance or rate-distortion selection; vertices on the truncated
# surface or least-squares fitted; importance in the domain's or the surface's metric)
# beside meshoptimizer and CGAL's Garland-Heckbert simplifier, at the paper's budgets
# and 1%, 3%, 10% of each input's triangles, on the bundled head and on J = 5 remeshes
# (about 300 base faces) of five public scans, whose distance to the scan is reported
# apart.
#
#   scripts/lod_compare.sh [--update-docs]
#
# Environment: BUILD_DIR (default build-bench; configured with OSDMRA_BUILD_BENCH=ON;
# CGAL is used when libcgal-dev is installed), SCANS (default ../shared/data/scans),
# OUT (default $BUILD_DIR/lod-compare), SKIP_BUILD=1, SAMPLES (default 100000),
# SKIP_RUN=1 (re-use OUT's tables: only the summary and the docs are remade).
# With --update-docs the tables replace the section between the lod-compare markers
# of docs/LOD.md. JOBS (default 2): inputs measured at once. 1 h 40 min on 2 cores with
# nothing else running (2026-12-03), hours more beside other work (lod --remesh's eight
# remeshings per row, several at once, are most of it).
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/run_parts.sh
build=${BUILD_DIR:-build-bench}
scans=${SCANS:-../shared/data/scans}
out=${OUT:-$build/lod-compare}
samples=${SAMPLES:-100000}
mkdir -p "$out"

if [[ -z "${SKIP_BUILD:-}" ]]; then
  cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DOSDMRA_BUILD_BENCH=ON \
    -DOSDMRA_BUILD_TESTS=OFF -DOSDMRA_BUILD_VIEWER=OFF >/dev/null
  cmake --build "$build" -j2 --target osdmra_cli osdmra_lod_compare
fi

# The remeshes, and their distance to the scans.
inputs=(data/igea-oct6.obj)
if [[ -z "${SKIP_RUN:-}" ]]; then
echo "| scan | remesh faces | base faces | RMS to the scan | Hausdorff to the scan |" >"$out/remesh.md"
echo "|---|---:|---:|---:|---:|" >>"$out/remesh.md"
for name in stanford-bunny spot rocker-arm fandisk elephant; do
  mesh="$out/$name-J5.obj"
  json=$("$build/osdmra" remesh "$scans/$name.obj" --base-faces 300 --levels 5 -o "$mesh" --json)
  python3 - "$name" "$json" >>"$out/remesh.md" <<'PY'
import json, sys
n, j = sys.argv[1], json.loads(sys.argv[2])
print(f"| {n} | {j['faces']:,} | {j['base_faces']} | {j['rms_relative']:.3e} | {j['hausdorff_relative']:.3e} |")
PY
  inputs+=("$mesh")
done

# One process per input, JOBS (default 2) at a time.
run_parts "$out/full.md" "$build/bench/osdmra_lod_compare" --samples "$samples" -- "${inputs[@]}"
fi

# Summary: per input and budget, the paper's configuration, the default, the levels
# placement (fitted positions looked up: re-extraction as fast as the default's), the
# best osdmra row cut from the input's hierarchy (by RMS to the input), the input
# remeshed again over bases of the budget (lod --remesh's remeshings), what lod --remesh
# keeps (the closer of that and its trial of the input's own hierarchy, lod's default
# linear rd closest; lod ranks its trials with 20,000 samples a side, the table with
# SAMPLES), meshoptimizer and CGAL, and the ratios.
python3 - "$out/full.md" "$out/remesh.md" >"$out/summary.md" <<'PY'
import sys, collections
rows = collections.OrderedDict()
for line in open(sys.argv[1]):
    c = [x.strip() for x in line.strip().strip('|').split('|')]
    if len(c) < 8 or not c[2].isdigit():
        continue
    inp, method, budget, tris, rms, haus = c[0], c[1], int(c[2]), int(c[3]), float(c[4]), float(c[5])
    rows.setdefault((inp, budget), {})[method] = (tris, rms, haus)
print("| input | budget | paper (linear, importance, surface) | library default (linear, rd, surface) | levels (linear, rd, levels) | best from the input's hierarchy | remeshed (lod --remesh's remeshings) | lod --remesh (the closer of linear rd closest and remeshed) | meshoptimizer | CGAL GH | levels / meshopt | best / meshopt | best / CGAL | lod --remesh / meshopt | lod --remesh / CGAL |")
print("|---|---:|---|---|---|---|---|---|---|---|---:|---:|---:|---:|---:|")
fmt = lambda t: f"{t[1]:.2e} / {t[2]:.2e}"
ratio = lambda a, b: f"{a[1] / b[1]:.2f}" if a and b else ""
for (inp, budget), m in rows.items():
    osd = {k: v for k, v in m.items() if k.startswith("osdmra") and k != "osdmra remeshed"}
    best = min(osd.items(), key=lambda kv: kv[1][1])
    paper = m.get("osdmra linear importance surface")
    default = m.get("osdmra linear rd surface")
    levels = m.get("osdmra linear rd levels")
    again = m.get("osdmra remeshed")
    closest = m.get("osdmra linear rd closest")
    lod = min((t for t in (again, closest) if t), key=lambda t: t[1], default=None)
    mo = m.get("meshoptimizer")
    gh = m.get("CGAL Garland-Heckbert")
    print(f"| {inp} | {budget:,} | {fmt(paper) if paper else ''} | {fmt(default) if default else ''} | "
          f"{fmt(levels) if levels else ''} | {best[0][7:]}: {fmt(best[1])} | "
          f"{f'{again[0]:,}: ' + fmt(again) if again else ''} | {fmt(lod) if lod else ''} | "
          f"{fmt(mo) if mo else ''} | {fmt(gh) if gh else ''} | {ratio(levels, mo)} | "
          f"{ratio(best[1], mo)} | {ratio(best[1], gh)} | {ratio(lod, mo)} | {ratio(lod, gh)} |")
print()
print("Remeshes (`osdmra remesh SCAN --base-faces 300 --levels 5`), distances to the scan, relative to its diagonal:")
print()
print(open(sys.argv[2]).read())
PY
cat "$out/summary.md"

if [[ "${1:-}" == "--update-docs" ]]; then
  {
    echo "\`scripts/lod_compare.sh --update-docs\`, $(date -u '+%Y-%m-%d %H:%M UTC'). RMS /" \
      "Hausdorff: sampled symmetric distances to the input mesh, relative to its" \
      "bounding-box diagonal."
    echo
    cat "$out/summary.md"
    echo
    echo "Every row (ms: one extraction or simplification; Loop rows also give the" \
      "distance to the input's limit surface, which Loop levels of detail approximate):"
    echo
    echo "<details><summary>full table</summary>"
    echo
    cat "$out/full.md"
    echo
    echo "</details>"
  } | python3 scripts/doc_section.py docs/LOD.md lod-compare
fi
