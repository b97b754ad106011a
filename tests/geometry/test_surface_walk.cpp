// Straight walks on a surface (surface_walk.h): on a plane a walk is the displacement
// itself, however many faces it crosses; over a cube's edge it unfolds onto the next
// face with its length kept; it stops at the boundary and at stop edges.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "osdmra/geometry/surface_walk.h"
#include "osdmra/subdivision/shapes.h"
#include "support.h"

using namespace osdmra;
using namespace osdmra::test;

namespace {

// The unit cube, each face split in two (outward-facing), refined linearly: many
// small faces on each side, flat, with 90 degree edges.
TriMesh cube(int levels) {
  return subdivide(unitCube(), levels, Scheme::Linear);
}

// The point of `mesh` at position x (a face containing it).
SurfacePoint locate(const TriMesh& mesh, const Eigen::Vector3d& x) {
  for (Eigen::Index t = 0; t < mesh.F.rows(); ++t) {
    std::array<double, 3> b;
    const Eigen::Vector3d a = mesh.V.row(mesh.F(t, 0)), p = mesh.V.row(mesh.F(t, 1)),
                          q = mesh.V.row(mesh.F(t, 2));
    const double offPlane = std::abs((p - a).cross(q - a).normalized().dot(x - a));
    if (offPlane < 1e-12 && barycentricIn(mesh, static_cast<int>(t), x, b) &&
        std::min({b[0], b[1], b[2]}) >= -1e-12)
      return {static_cast<int>(t), b};
  }
  ADD_FAILURE() << "no face holds " << x.transpose();
  return {};
}

// The square [0, 4] x [0, 4] in the plane z = 0, in small triangles.
TriMesh square() {
  TriMesh s = shapes::disc(4);
  s.V.col(2).setZero();
  return subdivide(s, 2, Scheme::Linear);
}

}  // namespace

TEST(SurfaceWalk, OnAPlaneAWalkIsTheDisplacement) {
  const TriMesh plane = square();
  const SurfaceWalker walker(plane);
  const Eigen::Vector3d from(1.05, 1.9, 0);
  for (const Eigen::Vector3d& d : {Eigen::Vector3d(2.3, 1.2, 0), Eigen::Vector3d(-0.95, 1.4, 0),
                                   Eigen::Vector3d(0, -1.5, 0), Eigen::Vector3d(0.01, 0, 0)}) {
    const SurfacePoint end = walker.walk(locate(plane, from), d);
    EXPECT_LT((walker.position(end) - (from + d)).norm(), 1e-12) << d.transpose();
  }
  // Off the plane, only the tangential part counts.
  const SurfacePoint end = walker.walk(locate(plane, from), Eigen::Vector3d(1.2, 0.1, 5.0));
  EXPECT_LT((walker.position(end) - Eigen::Vector3d(2.25, 2.0, 0)).norm(), 1e-12);
}

TEST(SurfaceWalk, UnfoldsOverAnEdgeAndStopsAtStopEdges) {
  const TriMesh c = cube(2);
  const SurfaceWalker walker(c);
  // From the middle of the top, 0.8 towards +x: 0.5 to the edge, then 0.3 down the
  // side x = 1; a slanted walk keeps its angle to the edge.
  const Eigen::Vector3d top(0.5, 0.5, 1);
  SurfacePoint end = walker.walk(locate(c, top), Eigen::Vector3d(0.8, 0, 0));
  EXPECT_LT((walker.position(end) - Eigen::Vector3d(1, 0.5, 0.7)).norm(), 1e-12);
  end = walker.walk(locate(c, Eigen::Vector3d(0.3, 0.4, 1)), Eigen::Vector3d(0.9, 0.2, 0));
  // 0.7 along x reaches the edge at y = 0.4 + 0.7 * 2 / 9; the remaining 2/9 of the
  // step goes 0.2 down and 2/45 along y.
  EXPECT_LT((walker.position(end) -
             Eigen::Vector3d(1, 0.4 + 0.2 * 0.7 / 0.9 + 0.2 * 0.2 / 0.9, 1 - 0.9 * 0.2 / 0.9))
                .norm(),
            1e-12);
  // The cube's edge x = 1, z = 1 as stop edges: the walk ends on it.
  std::vector<std::array<int, 2>> stops;
  for (Eigen::Index t = 0; t < c.F.rows(); ++t)
    for (int k = 0; k < 3; ++k) {
      const int a = c.F(t, k), b = c.F(t, (k + 1) % 3);
      if (c.V(a, 0) == 1 && c.V(a, 2) == 1 && c.V(b, 0) == 1 && c.V(b, 2) == 1)
        stops.push_back({a, b});
    }
  ASSERT_EQ(stops.size(), 2u * 4);  // 4 segments, each seen from both faces
  const SurfaceWalker stopped(c, stops);
  end = stopped.walk(locate(c, top), Eigen::Vector3d(0.8, 0, 0));
  EXPECT_LT((stopped.position(end) - Eigen::Vector3d(1, 0.5, 1)).norm(), 1e-12);
}

TEST(SurfaceWalk, StopsAtTheBoundary) {
  const TriMesh plane = square();
  const SurfaceWalker walker(plane);
  const SurfacePoint end =
      walker.walk(locate(plane, Eigen::Vector3d(2, 1.3, 0)), Eigen::Vector3d(10, 0, 0));
  const Eigen::Vector3d x = walker.position(end);
  EXPECT_LT((x - Eigen::Vector3d(4, 1.3, 0)).norm(), 1e-12);
  // From there, further out goes nowhere.
  const Eigen::Vector3d again = walker.position(walker.walk(end, Eigen::Vector3d(1, 0, 0)));
  EXPECT_LT((again - x).norm(), 1e-12);
}
