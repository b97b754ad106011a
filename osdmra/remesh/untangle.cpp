#include "osdmra/remesh/untangle.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

namespace osdmra::remeshing {

bool deepestPoint(const std::vector<Vec2>& n, const std::vector<double>& c, double extent,
                  Vec2& best, double& bestT) {
  bestT = -std::numeric_limits<double>::infinity();
  const int nc = static_cast<int>(n.size());
  for (int i = 0; i < nc; ++i)
    for (int j = i + 1; j < nc; ++j)
      for (int k = j + 1; k < nc; ++k) {
        // The three tight: A (x, y, t) = (c[i], c[j], c[k]), by Cramer's rule (an optimum
        // is where three independent constraints meet: a singular triple is skipped).
        const Eigen::Vector3d a(n[i].x(), n[i].y(), -1), b(n[j].x(), n[j].y(), -1),
            d(n[k].x(), n[k].y(), -1);
        const Eigen::Vector3d bd = b.cross(d), da = d.cross(a), ab = a.cross(b);
        const double det = a.dot(bd);
        if (!(std::abs(det) > 1e-12)) continue;
        const Eigen::Vector3d sol = (c[i] * bd + c[j] * da + c[k] * ab) / det;
        if (!sol.allFinite() || !(sol.z() > bestT)) continue;
        bool feasible = true;
        for (int q = 0; q < nc && feasible; ++q)
          feasible = n[q].dot(sol.head<2>()) - sol.z() >= c[q] - 1e-12 * extent;
        if (!feasible) continue;
        bestT = sol.z();
        best = sol.head<2>();
      }
  return std::isfinite(bestT);
}

namespace {

// The outer edges p -> q of a fan around the origin (`around`: its outer points,
// counter-clockwise, relative to the centre; `closed`: the last to the first an edge
// too) as constraints n . x - t >= c (left of every edge by t: the fan's triangles
// counter-clockwise where t > 0), and the fan's extent. Returns how far left of the
// nearest the origin is (-infinity where an edge has no length).
double fanConstraints(const std::vector<Vec2>& around, bool closed, std::vector<Vec2>& n,
                      std::vector<double>& c, double& extent) {
  const int size = static_cast<int>(around.size());
  const int edges = closed ? size : size - 1;
  n.clear();
  c.clear();
  extent = 0;
  double depth = std::numeric_limits<double>::infinity();
  for (int j = 0; j < edges; ++j) {
    const Vec2 p = around[j], q = around[(j + 1) % size];
    extent = std::max(extent, p.norm());
    const Vec2 d = q - p;
    if (!(d.norm() > 0)) return -std::numeric_limits<double>::infinity();
    n.push_back(Vec2(-d.y(), d.x()) / d.norm());
    c.push_back(n.back().dot(p));
    depth = std::min(depth, -c.back());
  }
  return depth;
}

// The deepest point of the fan's kernel within its extent (an open fan's kernel is not
// bounded), from fanConstraints().
bool deepestWithin(std::vector<Vec2>& n, std::vector<double>& c, double extent, Vec2& best,
                   double& bestT) {
  for (const Vec2& axis : {Vec2(1, 0), Vec2(-1, 0), Vec2(0, 1), Vec2(0, -1)}) {
    n.push_back(-axis);
    c.push_back(-extent);
  }
  return deepestPoint(n, c, extent, best, bestT);
}

// movers[i]'s fan, relative to it.
void fanOf(const PlanarFans& fans, std::size_t i, std::vector<Vec2>& around) {
  const Vec2 x = fans.points[fans.movers[i]];
  around.clear();
  for (int j = fans.ringStart[i]; j < fans.ringStart[i + 1]; ++j)
    around.push_back(fans.points[fans.ring[j]] - x);
}

}  // namespace

bool deepestInFan(const std::vector<Vec2>& around, bool closed, Vec2& best, double& bestT) {
  std::vector<Vec2> n;
  std::vector<double> c;
  double extent = 0;
  if (!std::isfinite(fanConstraints(around, closed, n, c, extent))) return false;
  return deepestWithin(n, c, extent, best, bestT);
}

bool embedded(const PlanarFans& fans) {
  std::vector<Vec2> around, n;
  std::vector<double> c;
  double extent = 0;
  for (std::size_t i = 0; i < fans.movers.size(); ++i) {
    fanOf(fans, i, around);
    if (!(fanConstraints(around, fans.closed[i], n, c, extent) > 0)) return false;
  }
  return true;
}

bool untangle(PlanarFans& fans, int rounds, long long& budget) {
  std::vector<Vec2> around, n;
  std::vector<double> c;
  for (int round = 0; round < rounds; ++round) {
    bool folded = false, deeper = false;
    for (std::size_t i = 0; i < fans.movers.size(); ++i) {
      double extent = 0;
      fanOf(fans, i, around);
      const double depth = fanConstraints(around, fans.closed[i], n, c, extent);
      if (depth > 0) continue;
      folded = true;
      if (!std::isfinite(depth)) continue;
      if (budget-- <= 0) return false;
      Vec2 best;
      double bestT = 0;
      if (!deepestWithin(n, c, extent, best, bestT) || !(bestT > depth + 1e-12 * extent)) continue;
      fans.points[fans.movers[i]] += best;
      deeper = true;
    }
    if (!folded) return true;
    if (!deeper) return false;
  }
  return embedded(fans);
}

}  // namespace osdmra::remeshing
