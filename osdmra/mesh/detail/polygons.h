// Polygons read as fans of triangles (io.h, ReadOptions::triangulate), unfolded where
// the fan folds. Internal: not installed.
#pragma once

#include <cstddef>
#include <vector>

namespace osdmra::detail {

/// A polygon of `corners` corners read as the fan from its first corner: faces
/// `first` .. first + corners - 3 of a reader's flat face list.
struct PolygonFan {
  std::size_t first;
  int corners;
};

/// Polygons with more corners keep their fan: ear clipping costs corners^3.
constexpr int kMaxEarClipped = 64;

/// Each fan with a triangle clockwise in its polygon's plane (Newell's normal: the
/// polygon is not star-shaped from its first corner, as an L-shaped face is not) is
/// replaced by the polygon's ear clipping there, as many triangles, when it has one.
/// `V` and `F` are a reader's flat coordinates and corner indices, F's indices valid.
void unfoldPolygonFans(const std::vector<double>& V, std::vector<int>& F,
                       const std::vector<PolygonFan>& fans);

}  // namespace osdmra::detail
