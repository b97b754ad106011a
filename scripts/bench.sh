#!/usr/bin/env bash
# Benchmarks: builds Release with the benchmarks into build-bench, runs
# build-bench/bench/osdmra_bench (osdmra against OpenSubdiv on displaced octahedra,
# J = 5..9), measures the peak memory of `osdmra analyze` on the level-9 surface,
# and prints the tables of docs/BENCHMARKS.md (markdown) from the results.
#
#   scripts/bench.sh                          everything (about 10 minutes on 2 cores)
#   scripts/bench.sh --benchmark_filter=J:9$  extra arguments go to osdmra_bench
#
# Environment: BUILD_DIR (default build-bench, relative to the repository root),
# JOBS (build parallelism, default 2), REPS (repetitions of each benchmark, default
# 5; the tables use the median), OUT (results directory, default
# $BUILD_DIR/results), SKIP_BUILD=1, SKIP_BENCH=1 (re-use OUT/bench.json),
# SKIP_MEMORY=1. The level-9 input and the .mra go to /tmp/oct9.ply, /tmp/x.mra.
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=${JOBS:-2}
reps=${REPS:-5}
build=${BUILD_DIR:-build-bench}
out=${OUT:-$build/results}
mkdir -p "$out"

if [[ -z "${SKIP_BUILD:-}" ]]; then
  echo "== build (Release, OSDMRA_BUILD_BENCH=ON) in $build" >&2
  cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DOSDMRA_BUILD_BENCH=ON \
    -DOSDMRA_BUILD_TESTS=OFF -DOSDMRA_BUILD_VIEWER=OFF -DOSDMRA_SANITIZE= >/dev/null
  cmake --build "$build" -j"$jobs" --target osdmra_bench osdmra_cli
fi

# The machine and the code measured.
{
  echo "date: $(date -u '+%Y-%m-%d %H:%M:%S UTC')"
  echo "nproc: $(nproc)"
  echo "cpu: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//')" \
    "(family $(grep -m1 'cpu family' /proc/cpuinfo | cut -d: -f2 | tr -d ' ')," \
    "model $(grep -m1 '^model[[:space:]]*:' /proc/cpuinfo | cut -d: -f2 | tr -d ' '))" \
    "$(lscpu 2>/dev/null | awk -F: '/Hypervisor vendor/ {gsub(/ /, "", $2); print "on " $2}')"
  echo "caches: $(lscpu 2>/dev/null | awk -F: '/L2 cache|L3 cache/ {gsub(/^ +/, "", $2); printf "%s %s; ", $1, $2}')"
  echo "memory: $(awk '/MemTotal/ {printf "%.1f GiB", $2 / 1048576}' /proc/meminfo)"
  echo "kernel: $(uname -sr)"
  echo "compiler: $(c++ --version | head -n1)"
  echo "code: $(git describe --always --dirty 2>/dev/null || echo unknown)," \
    "sources sha256 $(cat osdmra/*.h osdmra/*.cpp | sha256sum | cut -c1-16)"
  echo "load before: $(cut -d' ' -f1-3 /proc/loadavg)"
} | tee "$out/machine.txt" >&2

if [[ -z "${SKIP_BENCH:-}" ]]; then
  echo "== osdmra_bench (repetitions $reps)" >&2
  "$build"/bench/osdmra_bench --benchmark_format=json \
    --benchmark_out="$out/bench.json" --benchmark_out_format=json \
    --benchmark_repetitions="$reps" "$@" >"$out/bench.stdout.json"
  echo "load after: $(cut -d' ' -f1-3 /proc/loadavg)" | tee -a "$out/machine.txt" >&2
fi

if [[ -z "${SKIP_MEMORY:-}" ]]; then
  echo "== peak memory of osdmra analyze on the level-9 octahedron" >&2
  cat >/tmp/octahedron.obj <<'EOF'
# regular octahedron, counter-clockwise seen from outside
v 1 0 0
v -1 0 0
v 0 1 0
v 0 -1 0
v 0 0 1
v 0 0 -1
f 1 3 5
f 3 2 5
f 2 4 5
f 4 1 5
f 3 1 6
f 2 3 6
f 4 2 6
f 1 4 6
EOF
  "$build"/osdmra subdivide /tmp/octahedron.obj --levels 9 --displace 0.02 --seed 3 \
    -o /tmp/oct9.ply --quiet >&2
  /usr/bin/time -v "$build"/osdmra analyze /tmp/oct9.ply -o /tmp/x.mra --quiet --json \
    >"$out/analyze.json" 2>"$out/analyze.time.txt"
  grep -E 'Maximum resident|Elapsed|User time|System time' "$out/analyze.time.txt" >&2
fi

# Tables (markdown) from the JSON: medians over the repetitions, CPU time.
python3 - "$out" <<'EOF'
import json, os, re, sys

out = sys.argv[1]
runs = json.load(open(os.path.join(out, "bench.json")))["benchmarks"]
median = {}
for r in runs:
    if r.get("run_type") == "aggregate" and r.get("aggregate_name") == "median":
        median[r["run_name"]] = r
    elif r.get("run_type") == "iteration" and r.get("repetitions", 1) == 1:
        median[r["run_name"]] = r

def ms(name):
    r = median.get(name)
    return None if r is None else r["cpu_time"] * {"ns": 1e-6, "us": 1e-3, "ms": 1, "s": 1e3}[r["time_unit"]]

def fmt(x, digits=3):
    if x is None:
        return "-"
    return f"{x:.{digits}g}" if x < 100 else f"{x:.0f}"

levels = sorted({int(m.group(1)) for n in median for m in [re.search(r"/J:(\d+)$", n)] if m})
if not levels:
    sys.exit("no results in bench.json")
verts = {J: int(median[f"Hierarchy/J:{J}"]["vertices"]) for J in levels if f"Hierarchy/J:{J}" in median}
ops = []
for n in median:
    base = re.sub(r"/J:\d+$", "", n)
    if base not in ops:
        ops.append(base)

print("### Times per level (median CPU ms)\n")
print("| benchmark | " + " | ".join(f"J={J} ({verts.get(J, '?')} v)" for J in levels) + " |")
print("|---|" + "---:|" * len(levels))
for op in ops:
    print(f"| {op} | " + " | ".join(fmt(ms(f"{op}/J:{J}")) for J in levels) + " |")

def ratio(a, b):
    return None if a is None or b is None or b == 0 else a / b

print("\n### Loop, quasi r=1: ratios\n")
checks = [("synthesis / OpenSubdiv interpolation", "Synthesize/loop/quasi_r1", "OsdInterpolate", 3),
          ("analysis / OpenSubdiv interpolation", "Analyze/loop/quasi_r1", "OsdInterpolate", 6),
          ("precompute / analysis", "Precompute/loop/quasi_r1", "Analyze/loop/quasi_r1", 2)]
print("| ratio | target | " + " | ".join(f"J={J}" for J in levels) + " | at J=%d |" % levels[-1])
print("|---|---:|" + "---:|" * len(levels) + "---|")
for label, a, b, target in checks:
    rs = [ratio(ms(f"{a}/J:{J}"), ms(f"{b}/J:{J}")) for J in levels]
    last = rs[-1]
    verdict = "-" if last is None else ("meets" if last <= target else f"misses by {last / target:.2f}x")
    print(f"| {label} | <= {target} | " + " | ".join(fmt(r, 3) for r in rs) + f" | {verdict} |")

lo, hi = levels[0], levels[-1]
print(f"\n### Time per finest-level vertex (median CPU ns), J={lo} vs J={hi}\n")
print(f"| benchmark | J={lo} | J={hi} | J={hi} / J={lo} | linear (<= 1.3x) |")
print("|---|---:|---:|---:|---|")
for op in ops:
    a, b = median.get(f"{op}/J:{lo}"), median.get(f"{op}/J:{hi}")
    if a is None or b is None:
        continue
    x, y = a["time_per_vertex"] * 1e9, b["time_per_vertex"] * 1e9
    print(f"| {op} | {fmt(x)} | {fmt(y)} | {y / x:.2f} | {'yes' if y / x <= 1.3 else 'no'} |")

tfile = os.path.join(out, "analyze.time.txt")
if os.path.exists(tfile):
    text = open(tfile).read()
    m = re.search(r"Maximum resident set size \(kbytes\): (\d+)", text)
    info = json.load(open(os.path.join(out, "analyze.json")))
    n = info["vertices"]
    rss = int(m.group(1)) * 1024
    print("\n### Peak memory of `osdmra analyze` (level-9 octahedron, loop, quasi r=1)\n")
    print(f"| vertices | peak RSS (bytes) | bytes / vertex | target |")
    print("|---:|---:|---:|---|")
    print(f"| {n} | {rss} | {rss / n:.0f} | <= 600: {'meets' if rss / n <= 600 else f'misses by {rss / n / 600:.2f}x'} |")
    s = info["seconds"]
    print(f"\nanalyze stages (s): read {s['read']:.3f}, precompute {s['precompute']:.3f}, "
          f"analysis {s['analysis']:.3f}, synthesis {s['synthesis']:.3f}")
EOF
