// KeyHash: FNV-1a over a vector of ints, for the caches keyed by canonical encodings
// of local topology (element_gram.cpp, wavelets.cpp). Internal.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace osdmra {

struct KeyHash {
  std::size_t operator()(const std::vector<int>& key) const {
    std::uint64_t h = 1469598103934665603ull;
    for (int x : key) {
      h ^= static_cast<std::uint32_t>(x);
      h *= 1099511628211ull;
    }
    return static_cast<std::size_t>(h);
  }
};

}  // namespace osdmra
