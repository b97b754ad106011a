// Parallel loops over contiguous chunks, for the few linear passes that dominate on
// large inputs (the recovery of subdivision connectivity). Results never depend on
// the number of threads: callers write disjoint ranges, and concatenate what chunks
// produce in chunk order.
#pragma once

#include <algorithm>
#include <exception>
#include <thread>
#include <vector>

namespace osdmra {

/// How many chunks to cut `n` items into: one per hardware thread (at most 8), and
/// a single one below `grain` items, where threads would cost more than they save.
inline int numChunks(long long n, long long grain = 1 << 15) {
  const long long threads =
      std::clamp(static_cast<long long>(std::thread::hardware_concurrency()), 1LL, 8LL);
  return static_cast<int>(std::clamp(n / grain, 1LL, threads));
}

/// First item of chunk `c` of `chunks` over [0, n).
inline int chunkBegin(int n, int chunks, int c) {
  return static_cast<int>(static_cast<long long>(n) * c / chunks);
}

/// Calls f(chunk, begin, end) for each of `chunks` even chunks of [0, n), each on its
/// own thread (the first on the caller's), and returns when all have finished. The
/// first chunk's exception, if any, is rethrown.
template <class F>
void forChunks(int n, int chunks, F&& f) {
  std::vector<std::exception_ptr> errors(chunks);
  auto run = [&](int c) {
    try {
      f(c, chunkBegin(n, chunks, c), chunkBegin(n, chunks, c + 1));
    } catch (...) {
      errors[c] = std::current_exception();
    }
  };
  std::vector<std::thread> threads;
  for (int c = 1; c < chunks; ++c) threads.emplace_back(run, c);
  run(0);
  for (std::thread& t : threads) t.join();
  for (const std::exception_ptr& e : errors)
    if (e) std::rethrow_exception(e);
}

}  // namespace osdmra
