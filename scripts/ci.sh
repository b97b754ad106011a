#!/usr/bin/env bash
# Continuous integration: install what is missing, then build and run the whole
# test suite twice -- in Release, and with AddressSanitizer + UndefinedBehavior-
# Sanitizer. Stops at the first failure with a non-zero exit code.
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=${JOBS:-2}  # the CI machine has 2 cores

bash scripts/setup.sh

echo "== Release build"
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DOSDMRA_BUILD_TESTS=ON -DOSDMRA_BUILD_BENCH=OFF \
  -DOSDMRA_SANITIZE= >/dev/null
cmake --build build -j"$jobs"
echo "== Release tests"
ctest --test-dir build --output-on-failure -j"$jobs"

# -O1 -g rather than Debug: several times faster under the sanitizers, still
# exact stack traces; no NDEBUG, so assertions (ours and Eigen's) stay on.
echo "== ASan + UBSan build"
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g" \
  -DOSDMRA_BUILD_TESTS=ON -DOSDMRA_BUILD_BENCH=OFF -DOSDMRA_SANITIZE=address,undefined >/dev/null
cmake --build build-asan -j"$jobs"
echo "== ASan + UBSan tests"
export ASAN_OPTIONS=detect_leaks=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
ctest --test-dir build-asan --output-on-failure -j"$jobs"
