#!/usr/bin/env bash
# Continuous integration: install what is missing, then build and run the whole
# test suite twice -- in Release, and with AddressSanitizer + UndefinedBehavior-
# Sanitizer. Stops at the first failure with a non-zero exit code.
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=${JOBS:-2}  # the CI machine has 2 cores

bash scripts/setup.sh

# The tool, the viewer and the test files (not the library they drive) are built at -Og
# in both builds: a third to a half of their compile time at -O3 or under the
# sanitizers, for no measurable test time (the work is in the library); the test files
# six to a unit (tests/CMakeLists.txt, OSDMRA_UNITY_TESTS), about a quarter less.
echo "== Release build"
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DOSDMRA_BUILD_TESTS=ON -DOSDMRA_BUILD_BENCH=OFF \
  -DOSDMRA_SANITIZE= -DOSDMRA_APP_COMPILE_OPTIONS=-Og -DOSDMRA_UNITY_TESTS=ON >/dev/null
cmake --build build -j"$jobs"
echo "== Release tests"
ctest --test-dir build --output-on-failure -j"$jobs"

# -O1 -g1 rather than Debug: several times faster under the sanitizers, still
# exact stack traces (-g1 keeps line tables and inlined frames, what the sanitizers'
# reports use, and drops local-variable info, a third of the compile time); no
# NDEBUG, so assertions (ours and Eigen's) stay on.
# UBSan's null and alignment checks instrument every access through a pointer or
# reference: together they were a third of the compile time under the sanitizers
# (cleanup.cpp 50 -> 35 s, filter_bank.cpp 60 -> 34 s; either alone saves little) and
# kept CI over 20 minutes on 2 cores. ASan still reports any access through a null
# pointer (a SEGV with its stack), and x86-64 loads are not faulted by misalignment;
# every other UBSan check stays on.
echo "== ASan + UBSan build"
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -fno-sanitize=null,alignment" \
  -DOSDMRA_BUILD_TESTS=ON -DOSDMRA_BUILD_BENCH=OFF -DOSDMRA_SANITIZE=address,undefined \
  -DOSDMRA_APP_COMPILE_OPTIONS=-Og -DOSDMRA_UNITY_TESTS=ON >/dev/null
cmake --build build-asan -j"$jobs"
# ctest -j starts the longest tests first when it knows their times: hand it the
# Release run's, so the slow tests do not start last and leave one core idle.
mkdir -p build-asan/Testing/Temporary
cp build/Testing/Temporary/CTestCostData.txt build-asan/Testing/Temporary/ 2>/dev/null || true
echo "== ASan + UBSan tests"
export ASAN_OPTIONS=detect_leaks=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
ctest --test-dir build-asan --output-on-failure -j"$jobs"
