// Small planar geometry shared by the remeshing stages: barycentric coordinates,
// orientation and angles of triangles in a chart.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <utility>

namespace osdmra::remeshing {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;
constexpr double kPi = 3.14159265358979323846;

/// The angle between two vectors in space, in [0, pi]: atan2 of |a x b| and a . b, exact
/// near 0 and pi where acos of the normalised dot product is not.
inline double angleBetween(const Vec3& a, const Vec3& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

/// An undirected edge {a, b} as one key.
inline std::uint64_t edgeKey(int a, int b) {
  if (a > b) std::swap(a, b);
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) |
         static_cast<std::uint32_t>(b);
}

/// Barycentric coordinates of p in the planar triangle (a, b, c); NaN-free for
/// degenerate triangles (all three then -1).
inline std::array<double, 3> barycentric(const Vec2& p, const Vec2& a, const Vec2& b,
                                         const Vec2& c) {
  const double det = (b.x() - a.x()) * (c.y() - a.y()) - (c.x() - a.x()) * (b.y() - a.y());
  if (std::abs(det) < 1e-300) return {-1, -1, -1};
  const double l1 = ((p.x() - a.x()) * (c.y() - a.y()) - (c.x() - a.x()) * (p.y() - a.y())) / det;
  const double l2 = ((b.x() - a.x()) * (p.y() - a.y()) - (p.x() - a.x()) * (b.y() - a.y())) / det;
  return {1 - l1 - l2, l1, l2};
}

inline double minOf(const std::array<double, 3>& b) {
  return std::min({b[0], b[1], b[2]});
}

inline double cross2(const Vec2& a, const Vec2& b) {
  return a.x() * b.y() - a.y() * b.x();
}

/// The angle at corner o of the planar triangle (p, q, o).
inline double cornerAngle(const Vec2& p, const Vec2& q, const Vec2& o) {
  const Vec2 e1 = p - o, e2 = q - o;
  return std::atan2(std::abs(cross2(e1, e2)), e1.dot(e2));
}

inline double smallestAngle(const Vec2& a, const Vec2& b, const Vec2& c) {
  return std::min({cornerAngle(b, c, a), cornerAngle(c, a, b), cornerAngle(a, b, c)});
}

inline double largestAngle(const Vec2& a, const Vec2& b, const Vec2& c) {
  return std::max({cornerAngle(b, c, a), cornerAngle(c, a, b), cornerAngle(a, b, c)});
}

}  // namespace osdmra::remeshing
