// Untangling a planar triangulation with its outer points fixed (untangle.h), as the
// clean-up does with a disk of the grid that Tutte's embedding folds: known deepest points
// (a square's centre, a triangle's incentre), fans turned over and mended, an embedded
// fan left bit for bit, and a fan with no kernel refused.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "osdmra/remesh/untangle.h"

using namespace osdmra::remeshing;

namespace {

// The constraints "left of every edge by t" of a counter-clockwise polygon.
void leftOfEdges(const std::vector<Vec2>& polygon, std::vector<Vec2>& n, std::vector<double>& c) {
  for (std::size_t j = 0; j < polygon.size(); ++j) {
    const Vec2 p = polygon[j], d = polygon[(j + 1) % polygon.size()] - p;
    n.push_back(Vec2(-d.y(), d.x()) / d.norm());
    c.push_back(n.back().dot(p));
  }
}

// A hexagon of the triangular lattice, two rings around its centre (19 points): the
// inner seven move, each with its six neighbours counter-clockwise; the outer twelve
// are fixed.
PlanarFans latticeHexagon() {
  PlanarFans fans;
  std::vector<std::array<int, 2>> axial;
  for (int q = -2; q <= 2; ++q)
    for (int r = -2; r <= 2; ++r)
      if (std::abs(q + r) <= 2) {
        axial.push_back({q, r});
        fans.points.emplace_back(q + 0.5 * r, 0.5 * std::sqrt(3.0) * r);
      }
  auto index = [&](int q, int r) {
    for (std::size_t i = 0; i < axial.size(); ++i)
      if (axial[i][0] == q && axial[i][1] == r) return static_cast<int>(i);
    return -1;
  };
  const int around[6][2] = {{1, 0}, {0, 1}, {-1, 1}, {-1, 0}, {0, -1}, {1, -1}};
  for (std::size_t i = 0; i < axial.size(); ++i) {
    const auto [q, r] = axial[i];
    if (std::abs(q) > 1 || std::abs(r) > 1 || std::abs(q + r) > 1) continue;
    fans.movers.push_back(static_cast<int>(i));
    for (const auto& d : around) fans.ring.push_back(index(q + d[0], r + d[1]));
    fans.ringStart.push_back(static_cast<int>(fans.ring.size()));
    fans.closed.push_back(1);
  }
  return fans;
}

bool isMover(const PlanarFans& fans, int v) {
  for (int m : fans.movers)
    if (m == v) return true;
  return false;
}

}  // namespace

TEST(Untangle, DeepestPointOfASquareAndATriangle) {
  std::vector<Vec2> n;
  std::vector<double> c;
  leftOfEdges({{-1, -1}, {1, -1}, {1, 1}, {-1, 1}}, n, c);
  Vec2 best;
  double t = 0;
  ASSERT_TRUE(deepestPoint(n, c, 1.0, best, t));
  EXPECT_NEAR(best.norm(), 0.0, 1e-12);
  EXPECT_NEAR(t, 1.0, 1e-12);

  // The 3-4-5 right triangle: incentre (1, 1), inradius (3 + 4 - 5) / 2 = 1.
  n.clear();
  c.clear();
  leftOfEdges({{0, 0}, {4, 0}, {0, 3}}, n, c);
  ASSERT_TRUE(deepestPoint(n, c, 4.0, best, t));
  EXPECT_NEAR((best - Vec2(1, 1)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(t, 1.0, 1e-12);
}

// A regular hexagon's fan around its centre: the kernel is the hexagon, its deepest
// point the centre, at the apothem from every edge; a fan with an edge of no length has
// no kernel to speak of.
TEST(Untangle, DeepestPointOfAFan) {
  std::vector<Vec2> around;
  for (int j = 0; j < 6; ++j) around.emplace_back(std::cos(j * kPi / 3), std::sin(j * kPi / 3));
  Vec2 best;
  double t = 0;
  ASSERT_TRUE(deepestInFan(around, true, best, t));
  EXPECT_NEAR(best.norm(), 0.0, 1e-12);
  EXPECT_NEAR(t, std::sqrt(3.0) / 2, 1e-12);
  around[3] = around[2];
  EXPECT_FALSE(deepestInFan(around, true, best, t));
}

TEST(Untangle, AnEmbeddedTriangulationIsLeftBitForBit) {
  PlanarFans fans = latticeHexagon();
  ASSERT_EQ(fans.movers.size(), 7u);
  EXPECT_TRUE(embedded(fans));
  const std::vector<Vec2> before = fans.points;
  long long budget = 1000;
  EXPECT_TRUE(untangle(fans, 32, budget));
  EXPECT_EQ(fans.points, before);
}

// The inner points mirrored across the x axis turn the triangles around them over; the
// untangling makes every fan counter-clockwise again and leaves the outer points alone.
TEST(Untangle, MendsATangledDisk) {
  PlanarFans fans = latticeHexagon();
  const std::vector<Vec2> fixed = fans.points;
  for (int v : fans.movers)
    fans.points[v] = Vec2(1.3 * fans.points[v].x(), -0.6 * fans.points[v].y());
  fans.points[fans.movers[3]] += Vec2(0.9, 0.2);  // and the centre (axial 0, 0) pushed aside
  ASSERT_FALSE(embedded(fans));
  const std::vector<Vec2> tangled = fans.points;
  long long budget = 0;  // nothing to spend: refused, nothing moved
  EXPECT_FALSE(untangle(fans, 32, budget));
  EXPECT_EQ(fans.points, tangled);
  budget = 1000;
  EXPECT_TRUE(untangle(fans, 32, budget));
  EXPECT_TRUE(embedded(fans));
  EXPECT_LT(budget, 1000);  // each point placed spent some
  for (std::size_t v = 0; v < fans.points.size(); ++v) {
    if (!isMover(fans, static_cast<int>(v))) {
      EXPECT_EQ(fans.points[v], fixed[v]);
    }
  }
}

// A point whose fixed ring runs clockwise has no place where its triangles are all
// counter-clockwise: refused, within the rounds given, its ring untouched.
TEST(Untangle, RefusesAFanWithNoKernel) {
  PlanarFans fans;
  fans.points = {{0.2, 0.1}, {0, 0}, {0, 1}, {1, 0}};  // the ring (0,0) -> (0,1) -> (1,0)
  fans.movers = {0};
  fans.ring = {1, 2, 3};
  fans.ringStart = {0, 3};
  fans.closed = {1};
  ASSERT_FALSE(embedded(fans));
  long long budget = 1000;
  EXPECT_FALSE(untangle(fans, 32, budget));
  EXPECT_EQ(fans.points[1], Vec2(0, 0));
  EXPECT_EQ(fans.points[2], Vec2(0, 1));
  EXPECT_EQ(fans.points[3], Vec2(1, 0));
}
