// A uniform grid over triangles, by the cells their bounding boxes meet: which faces
// of a mesh that changes as it is built or simplified lie near a triangle, where a
// bounding volume hierarchy (distance.h) would have to be rebuilt at every change.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "osdmra/mesh/mesh.h"

namespace osdmra {

class FaceGrid {
 public:
  /// Cells of side `cell` (> 0, finite) over positions `V`, which must outlive the
  /// grid. A cell about the size of the faces keeps both a face's cells and a cell's
  /// faces few.
  FaceGrid(const Points& V, double cell);

  /// Adds face `id` with corners `t` (rows of V). Faces are never taken out: a caller
  /// whose faces die skips them as it visits.
  void insert(int id, const std::array<int, 3>& t);

  /// Lays the faces inserted so far out cell by cell, contiguous in memory: later
  /// queries read each cell's faces at once rather than following a list through the
  /// inserts. For a grid filled first and then queried often, with few inserts since.
  void freeze();

  /// The ids of the faces whose cells meet those of triangle t's bounding box, each
  /// once, appended to `out` (cleared first).
  void near(const std::array<int, 3>& t, std::vector<int>& out) const;

  /// The same for the box from `lo` to `hi`.
  void near(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, std::vector<int>& out) const;

 private:
  // The range of cells a triangle's box meets. A face meeting more than kMaxSpan
  // cells a side is kept apart, in every query's answer, rather than in thousands of
  // cells; a query that large returns every face.
  static constexpr int kMaxSpan = 64;
  std::array<std::array<std::int64_t, 3>, 2> span(const Eigen::Vector3d& lo,
                                                  const Eigen::Vector3d& hi) const;
  std::array<std::array<std::int64_t, 3>, 2> span(const std::array<int, 3>& t) const;
  static bool huge(const std::array<std::array<std::int64_t, 3>, 2>& s);
  static std::uint64_t key(std::int64_t x, std::int64_t y, std::int64_t z);
  // The slot of `key` in the open-addressed table: its own, or the empty one where it
  // would go.
  std::size_t slot(std::uint64_t key) const;
  void grow();

  const Points& V_;
  double cell_;
  // Cells in an open-addressed table (linear probing, at most half full), each with a
  // range {first, count} of frozen_ (the faces before the last freeze()) and the head of
  // a list of entries {face, next entry} (those since): one allocation per doubling,
  // not per cell, as the grid is rebuilt often.
  static constexpr std::uint64_t kEmpty = ~std::uint64_t{0};  // key() never makes it
  std::vector<std::uint64_t> slotKey_;
  int slotShift_ = 64;  // 64 - log2(slotKey_.size()): the hash's top bits index a slot
  std::vector<int> slotHead_;
  std::vector<std::array<int, 2>> slotFrozen_;
  std::vector<int> frozen_;
  std::size_t cells_ = 0;
  std::vector<std::array<int, 2>> entries_;
  std::vector<int> huge_, all_;    // faces kept apart; every face (for huge queries)
  mutable std::vector<int> seen_;  // per id: last query's stamp
  mutable int stamp_ = 0;
};

}  // namespace osdmra
