// Untangling a planar triangulation whose outer points are fixed (Freitag and
// Plassmann 2000, "Local optimization-based simplicial mesh untangling and improvement"):
// each point that may move goes, one at a time and in rounds, to the deepest point of
// its ring's kernel, where every triangle around it is as far from turning over as it can
// be. The clean-up (cleanup.h) does it on the surface point by point, and here on the
// flattening of a disk of the grid that Tutte's embedding folds (its boundary, flattened
// from a curved or rough surface, is not convex).
#pragma once

#include <vector>

#include "osdmra/remesh/planar.h"

namespace osdmra::remeshing {

/// The deepest point of a convex region {x : n[q] . x - t >= c[q] for every q}: the
/// largest t and its x (a linear programme in x, y, t whose optimum has three
/// constraints tight, found by trying every triple: the rings it is for are small).
/// `extent` scales the feasibility tolerance. False if there is no finite optimum.
bool deepestPoint(const std::vector<Vec2>& n, const std::vector<double>& c, double extent,
                  Vec2& best, double& bestT);

/// The deepest point of the kernel of a fan around the origin, within the fan's extent:
/// `around` its outer points counter-clockwise, relative to its centre, and with `closed`
/// the last and the first a triangle with it too. False where an outer edge has no
/// length or there is no optimum.
bool deepestInFan(const std::vector<Vec2>& around, bool closed, Vec2& best, double& bestT);

/// Planar points and the fan of triangles around each of those that may move: movers[i]'s
/// neighbours counter-clockwise are ring[ringStart[i]], ..., ring[ringStart[i + 1] - 1]
/// (indices into `points`), and with closed[i] the last and the first make a triangle
/// with it too (an open fan: a point on the boundary).
struct PlanarFans {
  std::vector<Vec2> points;
  std::vector<int> movers;
  std::vector<int> ringStart{0};
  std::vector<int> ring;
  std::vector<char> closed;
};

/// Whether every triangle around every mover is counter-clockwise, of positive area.
bool embedded(const PlanarFans& fans);

/// Moves the movers, one at a time and in rounds, each to the deepest point of its
/// fan's kernel (bounded by the fan's extent) where that makes its worst triangle less
/// bad, until embedded() (true) or a round moves nothing, `rounds` have run or `budget`
/// is spent (false). Each point placed spends 1 of `budget`. Points that are not movers
/// never move.
bool untangle(PlanarFans& fans, int rounds, long long& budget);

}  // namespace osdmra::remeshing
