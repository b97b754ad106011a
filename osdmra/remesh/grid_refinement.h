// Step 2 of remesh.h, inside each base face: its grid made as subdivision makes it, level
// by level in the base face's domain, each level's triangles checked for folds where that
// level makes them.
//
// A bijective parameterisation sampled on a uniform grid can still fold the output: where
// the map is sheared strongly at the grid's scale, three points in counter-clockwise order
// in the domain land in clockwise order on the surface. So level l's points start at the
// domain midpoints of level l-1's edges; then every triangle of level l is checked, and a
// point of a folded one moves in the domain, a step towards one of its six neighbours,
// where that folds fewer of its level-l triangles, and only if every domain triangle
// around it stays counter-clockwise. Finer levels are midpoints of the moved points, so
// the domain grid stays an embedding: the grid is the parameterisation composed with a
// piecewise-affine, orientation-preserving warp of the domain, a bijection still. The
// warp stays where the map folds the grid; elsewhere the points are the uniform grid's.
//
// Sampling then folds where no single step mends a fold (a map that turns a region over
// at a scale below the grid's), and the clean-up (cleanup.h) is left those.
#pragma once

#include <Eigen/Core>
#include <array>
#include <functional>
#include <vector>

namespace osdmra::remeshing {

/// How the grid's folds are mended (refineGrid).
struct GridRefinementOptions {
  /// The first level whose folded triangles are mended (1: every level). Mending at the
  /// coarse levels too moved the fewest points over the corpus (docs/REMESH.md).
  int fromLevel = 1;
  /// The steps a point tries, as fractions of the way to each of its six neighbours.
  std::vector<double> steps{0.125, 0.25, 0.5};
  /// Rounds over a level's points, while some point still moves.
  int passes = 5;
};

/// The grid of a base face split `levels` times, N = 2^levels segments a side. Point (i, j),
/// i + j <= N, lies at domain point (u, v) = (i / N, j / N) of the face before any warp,
/// barycentric (1 - u - v, u, v).
struct GridCallbacks {
  /// Places interior point (i, j) (0 < i, 0 < j, i + j < N) at domain point `uv`
  /// (replacing where it was).
  std::function<void(int i, int j, const Eigen::Vector2d& uv)> place;
  /// Whether the triangle of grid points a, b, c (counter-clockwise in the domain), as
  /// placed, is folded. Points on the face's sides are placed before refineGrid() is called.
  std::function<bool(const std::array<int, 2>& a, const std::array<int, 2>& b,
                     const std::array<int, 2>& c)>
      folded;
};

/// Places every interior point of a base face's grid, level by level, mending folds as
/// above. `domain`, if given, receives every point's domain position ((N + 1)^2 entries,
/// row i (N + 1) + j; unused ones where i + j > N). Returns the moves kept.
int refineGrid(int levels, const GridCallbacks& grid, const GridRefinementOptions& options = {},
               std::vector<Eigen::Vector2d>* domain = nullptr);

}  // namespace osdmra::remeshing
