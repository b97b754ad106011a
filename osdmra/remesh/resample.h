// Step 2 of remesh.h: the base mesh's faces split J times, every grid point placed on
// the input through the parameterisation the simplification tracked.
//
// Every grid point is mapped to the input by the parameterisation made straight on every
// input triangle (charts.h): the input triangle whose corners' places hold it in its
// base face's chart, at the same barycentric coordinates. That map is affine on each
// input triangle with the distortion the simplification bounded, so a grid triangle
// inside one input triangle keeps its orientation. The search starts where the exact
// inverse of the removals puts the point (simplify.h's traceToInput, a bijection), and
// keeps that place where the charts cannot hold the triangles around. An input
// triangle whose corners lie in base faces apart (not one face, nor two sharing an edge)
// is laid about the corner of the face its corners surround (fan_chart.h), so that it
// has one image from every face around that corner, not one per chart. Grid
// points on feature and boundary base edges are sampled along the input's line itself
// (the chain of input feature or boundary edges the base edge stands for), at their
// parameter along it; a point on a base edge between two faces, where one face's charts
// do not reach it, is placed through the other face's. The grid is laid out first; the
// points on base edges, independent of each other, are then placed on every core. Then,
// around each base vertex where a grid triangle at one of its corners spans more than a
// half turn of the input and comes out turned over (as it does wherever its corners lie
// on the corner's sides, on a cone not far from flat), the grid points next to the vertex
// are placed again in its input one-ring at angles spread apart (spreadAround). Last,
// each base face's interior, level by level with its folds mended where each level makes
// them (grid_refinement.h; the faces independent of each other, on every core), around
// the points on its sides as they were placed.
#pragma once

#include <vector>

#include "osdmra/base/progress.h"
#include "osdmra/geometry/surface_walk.h"
#include "osdmra/mesh/connectivity.h"
#include "osdmra/remesh/charts.h"
#include "osdmra/remesh/simplify.h"

namespace osdmra::remeshing {

struct Resampled {
  /// M^levels over the base: the base vertices first, then the grid points, faces
  /// base face by base face (4^levels each, in grid order).
  TriMesh mesh;
  std::vector<SurfacePoint> where;  ///< each vertex's place on the input
  std::vector<char> free;           ///< grid points not on a base vertex, feature or boundary
  std::vector<long long> line;      ///< for points on base edges: the edge; -1 elsewhere
  /// Steps the grid's refinement took in base faces' domains to mend folds
  /// (grid_refinement.h).
  int refinementMoves = 0;
};

/// The map that takes a grid point from its base face to the input. Both are
/// bijections; which one samples with fewer folds depends on the input (remesh()
/// samples the exact one where the straightened one folds, and keeps it where it folds
/// nothing; and cleans up the other map's grid too where the first one's clean-up leaves
/// defects).
enum class GridMap {
  /// The parameterisation made straight on every input triangle: affine on each, with
  /// the distortion the simplification bounded. Best where input triangles are small
  /// against the grid's (dense scans).
  straightened,
  /// The exact inverse of the removals (traceToInput), piecewise linear over their
  /// retriangulations. Best where input triangles are large against the grid's and
  /// straddle base edges (decimated and CAD-like inputs), whose corners the charts of
  /// the straightened map see only through unfolded neighbours.
  exact,
};

/// How far apart, at most, resample() spreads the grid points next to a base vertex
/// around it (in the input's angles) where a grid triangle at one of its corners spans
/// more than a half turn of the input and is turned over: 0.9 pi, a margin under the
/// half turn.
constexpr double kSpreadTo = 0.9 * kPi;

/// The widest gap between consecutive angles (counter-clockwise, the last to the first)
/// of points around a vertex whose angles sum to `total`.
double widestGap(const std::vector<double>& angles, double total);

/// Angles in [0, total) of points around a vertex (counter-clockwise, in order), spread
/// so that no gap between consecutive ones is wider than `most`: the wider gaps cut to
/// it, the excess shared among the others in proportion to their room under it, the
/// points then turned together so that they move by nothing on average. Returned
/// unchanged when no gap is wider, when it cannot be done (size * most <= total), or
/// when the angles are not in order around the vertex.
std::vector<double> spreadAround(const std::vector<double>& angles, double total, double most);

/// Resamples the simplification of `input` (whose connectivity is `inputConn` and
/// feature edges `inputFeatures`) at `levels` rounds of 1-to-4 splitting.
Resampled resample(const TriMesh& input, const Connectivity& inputConn,
                   const std::vector<std::array<int, 2>>& inputFeatures, const Simplification& s,
                   const BaseCharts& charts, int levels, GridMap map = GridMap::straightened,
                   const Progress& progress = {}, bool refine = true);

}  // namespace osdmra::remeshing
