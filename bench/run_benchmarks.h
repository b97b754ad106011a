// Google Benchmark's main, for the programs that register their benchmarks at run
// time (one per input mesh found).
#pragma once

#include <benchmark/benchmark.h>

namespace osdmra::bench {

/// Runs the registered benchmarks with the command line's options; the exit status.
inline int runBenchmarks(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}

}  // namespace osdmra::bench
