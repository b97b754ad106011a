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

std::array<std::array<std::int64_t, 3>, 2> FaceGrid::span(const Eigen::Vector3d& lo,
                                                          const Eigen::Vector3d& hi) const {
  std::array<std::array<std::int64_t, 3>, 2> s{};
  for (int c = 0; c < 3; ++c) {
    s[0][c] = cellIndex(lo[c] / cell_);
    s[1][c] = cellIndex(hi[c] / cell_);
  }
  return s;
}

std::array<std::array<std::int64_t, 3>, 2> FaceGrid::span(const std::array<int, 3>& t) const {
  const Eigen::Vector3d a = V_.row(t[0]).transpose(), b = V_.row(t[1]).transpose(),
                        c = V_.row(t[2]).transpose();
  return span(a.cwiseMin(b).cwiseMin(c), a.cwiseMax(b).cwiseMax(c));
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
      for (std::int64_t z = s[0][2]; z <= s[1][2]; ++z) {
        if (2 * (cells_ + 1) > slotKey_.size()) grow();
        const std::uint64_t k = key(x, y, z);
        const std::size_t i = slot(k);
        if (slotKey_[i] == kEmpty) {
          slotKey_[i] = k;
          slotHead_[i] = -1;
          slotFrozen_[i] = {0, 0};
          ++cells_;
        }
        entries_.push_back({id, slotHead_[i]});
        slotHead_[i] = static_cast<int>(entries_.size()) - 1;
      }
}

std::size_t FaceGrid::slot(std::uint64_t key) const {
  const std::size_t mask = slotKey_.size() - 1;
  // Fibonacci hashing spreads the packed coordinates over the table: the product's top
  // bits, which depend on all of the key's (its middle bits ignored z, and a column of
  // cells probed one long run).
  std::size_t i = static_cast<std::size_t>((key * 0x9E3779B97F4A7C15ull) >> slotShift_);
  while (slotKey_[i] != kEmpty && slotKey_[i] != key) i = (i + 1) & mask;
  return i;
}

void FaceGrid::grow() {
  std::vector<std::uint64_t> keys(std::max<std::size_t>(64, 2 * slotKey_.size()), kEmpty);
  std::vector<int> heads(keys.size(), -1);
  std::vector<std::array<int, 2>> ranges(keys.size(), {0, 0});
  keys.swap(slotKey_);
  slotShift_ = 64;
  for (std::size_t size = slotKey_.size(); size > 1; size /= 2) --slotShift_;
  heads.swap(slotHead_);
  ranges.swap(slotFrozen_);
  for (std::size_t j = 0; j < keys.size(); ++j)
    if (keys[j] != kEmpty) {
      const std::size_t i = slot(keys[j]);
      slotKey_[i] = keys[j];
      slotHead_[i] = heads[j];
      slotFrozen_[i] = ranges[j];
    }
}

void FaceGrid::freeze() {
  std::vector<int> laid;
  laid.reserve(frozen_.size() + entries_.size());
  for (std::size_t i = 0; i < slotKey_.size(); ++i) {
    if (slotKey_[i] == kEmpty) continue;
    const int first = static_cast<int>(laid.size());
    const auto [from, count] = slotFrozen_[i];
    laid.insert(laid.end(), frozen_.begin() + from, frozen_.begin() + from + count);
    for (int e = slotHead_[i]; e >= 0; e = entries_[static_cast<std::size_t>(e)][1])
      laid.push_back(entries_[static_cast<std::size_t>(e)][0]);
    slotFrozen_[i] = {first, static_cast<int>(laid.size()) - first};
    slotHead_[i] = -1;
  }
  frozen_.swap(laid);
  entries_.clear();
}

void FaceGrid::near(const std::array<int, 3>& t, std::vector<int>& out) const {
  const Eigen::Vector3d a = V_.row(t[0]).transpose(), b = V_.row(t[1]).transpose(),
                        c = V_.row(t[2]).transpose();
  near(a.cwiseMin(b).cwiseMin(c), a.cwiseMax(b).cwiseMax(c), out);
}

void FaceGrid::near(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                    std::vector<int>& out) const {
  out.clear();
  ++stamp_;
  auto add = [&](int id) {
    if (seen_[static_cast<std::size_t>(id)] == stamp_) return;
    seen_[static_cast<std::size_t>(id)] = stamp_;
    out.push_back(id);
  };
  const auto s = span(lo, hi);
  if (huge(s)) {
    for (int id : all_) add(id);
    return;
  }
  for (int id : huge_) add(id);
  for (std::int64_t x = s[0][0]; x <= s[1][0]; ++x)
    for (std::int64_t y = s[0][1]; y <= s[1][1]; ++y)
      for (std::int64_t z = s[0][2]; z <= s[1][2]; ++z) {
        if (slotKey_.empty()) return;
        const std::size_t i = slot(key(x, y, z));
        if (slotKey_[i] == kEmpty) continue;
        const auto [from, count] = slotFrozen_[i];
        for (int j = from; j < from + count; ++j) add(frozen_[static_cast<std::size_t>(j)]);
        for (int e = slotHead_[i]; e >= 0; e = entries_[static_cast<std::size_t>(e)][1])
          add(entries_[static_cast<std::size_t>(e)][0]);
      }
}

}  // namespace osdmra
