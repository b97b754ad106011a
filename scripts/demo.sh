#!/usr/bin/env bash
# The main job: install what is missing, build osdmra in Release and run
# `osdmra demo` (analyse the bundled mesh, rebuild it, print a summary).
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=${JOBS:-2}

bash scripts/setup.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DOSDMRA_BUILD_TESTS=OFF -DOSDMRA_BUILD_BENCH=OFF >/dev/null
cmake --build build -j"$jobs"
./build/osdmra demo
