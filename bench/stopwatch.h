// Wall-clock timing of one step, for the comparison programs that time their peers
// themselves (lod_compare, codec_rd).
#pragma once

#include <chrono>

namespace osdmra::bench {

using Clock = std::chrono::steady_clock;

/// Seconds elapsed since t.
inline double secondsSince(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

}  // namespace osdmra::bench
