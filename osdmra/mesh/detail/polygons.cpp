#include "osdmra/mesh/detail/polygons.h"

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>

namespace osdmra::detail {

namespace {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;

double cross2(const Vec2& a, const Vec2& b) {
  return a.x() * b.y() - a.y() * b.x();
}

// Whether p lies in triangle (a, b, c), counter-clockwise, or on its boundary.
bool inside(const Vec2& p, const Vec2& a, const Vec2& b, const Vec2& c) {
  return cross2(b - a, p - a) >= 0 && cross2(c - b, p - b) >= 0 && cross2(a - c, p - c) >= 0;
}

// Ear clipping of the counter-clockwise polygon q (positions 0..n-1); empty when some
// step finds no ear (the polygon crosses itself).
std::vector<std::array<int, 3>> earClip(const std::vector<Vec2>& q) {
  std::vector<int> left(q.size());
  for (std::size_t i = 0; i < q.size(); ++i) left[i] = static_cast<int>(i);
  std::vector<std::array<int, 3>> out;
  while (left.size() > 3) {
    const std::size_t m = left.size();
    bool clipped = false;
    for (std::size_t i = 0; i < m && !clipped; ++i) {
      const int a = left[(i + m - 1) % m], b = left[i], c = left[(i + 1) % m];
      if (cross2(q[b] - q[a], q[c] - q[b]) <= 0) continue;  // reflex or flat
      bool empty = true;
      for (int x : left)
        if (x != a && x != b && x != c && inside(q[x], q[a], q[b], q[c])) empty = false;
      if (!empty) continue;
      out.push_back({a, b, c});
      left.erase(left.begin() + static_cast<std::ptrdiff_t>(i));
      clipped = true;
    }
    if (!clipped) return {};
  }
  out.push_back({left[0], left[1], left[2]});
  return out;
}

}  // namespace

void unfoldPolygonFans(const std::vector<double>& V, std::vector<int>& F,
                       const std::vector<PolygonFan>& fans) {
  for (const PolygonFan& fan : fans) {
    const int n = fan.corners;
    if (n <= 3 || n > kMaxEarClipped) continue;
    std::vector<int> corner(static_cast<std::size_t>(n));
    corner[0] = F[3 * fan.first];
    corner[1] = F[3 * fan.first + 1];
    for (int k = 0; k + 2 < n; ++k) corner[k + 2] = F[3 * (fan.first + k) + 2];
    std::vector<Vec3> p;
    for (int c : corner) p.emplace_back(V[3 * c], V[3 * c + 1], V[3 * c + 2]);
    Vec3 normal = Vec3::Zero();  // Newell's: robust for a non-convex polygon
    for (int i = 0; i < n; ++i) normal += p[i].cross(p[(i + 1) % n]);
    if (!(normal.norm() > 0)) continue;
    const Vec3 u = normal.unitOrthogonal(), v = normal.normalized().cross(u);
    std::vector<Vec2> q;
    for (const Vec3& x : p) q.emplace_back(x.dot(u), x.dot(v));
    bool folds = false;
    for (int k = 1; k + 1 < n; ++k) folds = folds || cross2(q[k] - q[0], q[k + 1] - q[0]) <= 0;
    if (!folds) continue;
    const std::vector<std::array<int, 3>> triangles = earClip(q);
    if (triangles.empty()) continue;  // the polygon crosses itself: its fan stays
    for (std::size_t t = 0; t < triangles.size(); ++t)
      for (int k = 0; k < 3; ++k) F[3 * (fan.first + t) + k] = corner[triangles[t][k]];
  }
}

}  // namespace osdmra::detail
