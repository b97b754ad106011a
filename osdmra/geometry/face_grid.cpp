#include "osdmra/geometry/face_grid.h"

#include <algorithm>
#include <cmath>

#include "osdmra/base/error.h"

namespace osdmra {

FaceGrid::FaceGrid(const Points& V, double cell) : V_(V), cell_(cell) {
  if (!(cell > 0) || !std::isfinite(cell))
    throw Error("FaceGrid: the cell size must be positive and finite");
}

namespace {
// floor(x) as an integer, clamped far inside int64's range (a cell index beyond it
// would be undefined to convert; such coordinates only wrap in key()).
std::int64_t cellIndex(double x) {
  constexpr double kLimit = 4.0e18;
  return static_cast<std::int64_t>(std::clamp(std::floor(x), -kLimit, kLimit));
}
}  // namespace

std::array<std::array<std::int64_t, 3>, 2> FaceGrid::span(const std::array<int, 3>& t) const {
  std::array<std::array<std::int64_t, 3>, 2> s{};
  for (int c = 0; c < 3; ++c) {
    const double lo = std::min({V_(t[0], c), V_(t[1], c), V_(t[2], c)});
    const double hi = std::max({V_(t[0], c), V_(t[1], c), V_(t[2], c)});
    s[0][c] = cellIndex(lo / cell_);
    s[1][c] = cellIndex(hi / cell_);
  }
  return s;
}

// Coordinates wrap at 2^21 cells a side: faces far apart may share a key, which only
// adds candidates for the caller's exact test.
std::uint64_t FaceGrid::key(std::int64_t x, std::int64_t y, std::int64_t z) {
  const std::uint64_t m = (std::uint64_t{1} << 21) - 1;
  return (static_cast<std::uint64_t>(x) & m) | (static_cast<std::uint64_t>(y) & m) << 21 |
         (static_cast<std::uint64_t>(z) & m) << 42;
}

bool FaceGrid::huge(const std::array<std::array<std::int64_t, 3>, 2>& s) {
  for (int c = 0; c < 3; ++c)
    if (s[1][c] - s[0][c] > kMaxSpan) return true;
  return false;
}

void FaceGrid::insert(int id, const std::array<int, 3>& t) {
  if (id >= static_cast<int>(seen_.size())) seen_.resize(static_cast<std::size_t>(id) + 1, -1);
  all_.push_back(id);
  const auto s = span(t);
  if (huge(s)) {
    huge_.push_back(id);
    return;
  }
  for (std::int64_t x = s[0][0]; x <= s[1][0]; ++x)
    for (std::int64_t y = s[0][1]; y <= s[1][1]; ++y)
      for (std::int64_t z = s[0][2]; z <= s[1][2]; ++z) cells_[key(x, y, z)].push_back(id);
}

void FaceGrid::near(const std::array<int, 3>& t, std::vector<int>& out) const {
  out.clear();
  ++stamp_;
  auto add = [&](int id) {
    if (seen_[static_cast<std::size_t>(id)] == stamp_) return;
    seen_[static_cast<std::size_t>(id)] = stamp_;
    out.push_back(id);
  };
  const auto s = span(t);
  if (huge(s)) {
    for (int id : all_) add(id);
    return;
  }
  for (int id : huge_) add(id);
  for (std::int64_t x = s[0][0]; x <= s[1][0]; ++x)
    for (std::int64_t y = s[0][1]; y <= s[1][1]; ++y)
      for (std::int64_t z = s[0][2]; z <= s[1][2]; ++z) {
        const auto it = cells_.find(key(x, y, z));
        if (it == cells_.end()) continue;
        for (int id : it->second) add(id);
      }
}

}  // namespace osdmra
