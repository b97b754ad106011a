#include "osdmra/mesh/detail/edges.h"

#include <algorithm>

namespace osdmra::detail {

std::vector<std::pair<std::uint64_t, int>> halfedgesByEdge(const Faces& F) {
  std::vector<std::pair<std::uint64_t, int>> out(3 * static_cast<std::size_t>(F.rows()));
  for (int h = 0; h < static_cast<int>(out.size()); ++h) {
    const auto u = static_cast<std::uint32_t>(F(h / 3, h % 3)),
               w = static_cast<std::uint32_t>(F(h / 3, (h % 3 + 1) % 3));
    out[h] = {std::uint64_t{std::min(u, w)} << 32 | std::max(u, w), h};
  }
  std::sort(out.begin(), out.end());
  return out;
}

std::size_t runEnd(const std::vector<std::pair<std::uint64_t, int>>& sorted, std::size_t i) {
  std::size_t end = i + 1;
  while (end < sorted.size() && sorted[end].first == sorted[i].first) ++end;
  return end;
}

}  // namespace osdmra::detail
