// The clean-up (cleanup.h), the remesher's safety net: given a resampled surface with a
// fold made on purpose (a grid point dragged across its neighbour), it repairs it and
// says how much it moved; given a clean one, it moves nothing.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <vector>

#include "osdmra/geometry/normals.h"
#include "osdmra/mesh/connectivity.h"
#include "osdmra/remesh/cleanup.h"
#include "osdmra/remesh/features.h"
#include "osdmra/remesh/resample.h"
#include "osdmra/remesh/simplify.h"
#include "osdmra/subdivision/shapes.h"
#include "support.h"

using namespace osdmra;
using namespace osdmra::remeshing;

namespace {

struct Sampled {
  TriMesh input;
  Features features;
  Simplification s;
  Resampled grid;
};

Sampled sampledSphere() {
  Sampled x;
  x.input = subdivide(shapes::icosahedron(), 3, Scheme::Loop);
  x.features = detectFeatures(x.input, 70.0);
  x.s = simplify(x.input, x.features, 60);
  const SurfaceWalker walker(x.input, x.features.list);
  x.grid = resample(x.input, walker.connectivity(), x.features.list, x.s, BaseCharts(x.s.base), 3);
  return x;
}

// The remeshed surface as resampling leaves it, before the clean-up.
Remeshing resampled(const Sampled& x) {
  Remeshing out;
  out.base = x.s.base;
  out.mesh = x.grid.mesh;
  return out;
}

// A free grid point dragged across one of its neighbours, half an edge beyond it (its
// place on the input taken to be the neighbour's): a fold made on purpose.
void dragAcrossNeighbour(Sampled& x, Remeshing& out) {
  const VertexRings rings(out.mesh.F, static_cast<int>(out.mesh.V.rows()));
  int v = static_cast<int>(out.base.V.rows());
  while (!x.grid.free[v]) ++v;
  const int w = rings.ring(v)[0];
  out.mesh.V.row(v) = out.mesh.V.row(w) + 0.5 * (out.mesh.V.row(w) - out.mesh.V.row(v));
  x.grid.where[v] = x.grid.where[w];
}

// The longest edge of a cleaned-up grid against the reach of its ends: the mean edge of
// the grid over each base face around them (base face b holds grid faces b * perBase ..
// (b + 1) * perBase - 1), the larger of the two ends'. The repairs may not stretch an
// edge beyond 16 of those (cleanup.cpp, kLongestRepairedEdge: a repair once lifted a
// point of a scan's remesh onto another part of its surface, 8.9% of its diagonal away).
double longestEdgeAgainstItsReach(const TriMesh& grid, Eigen::Index perBase) {
  std::vector<double> reach(static_cast<std::size_t>(grid.V.rows()), 0.0);
  const auto edge = [&](Eigen::Index f, int k) {
    return (grid.V.row(grid.F(f, k)) - grid.V.row(grid.F(f, (k + 1) % 3))).norm();
  };
  for (Eigen::Index b = 0; b < grid.F.rows() / perBase; ++b) {
    double sum = 0;
    for (Eigen::Index f = b * perBase; f < (b + 1) * perBase; ++f)
      for (int k = 0; k < 3; ++k) sum += edge(f, k);
    for (Eigen::Index f = b * perBase; f < (b + 1) * perBase; ++f)
      for (int k = 0; k < 3; ++k)
        reach[grid.F(f, k)] = std::max(reach[grid.F(f, k)], sum / double(3 * perBase));
  }
  double longest = 0;
  for (Eigen::Index f = 0; f < grid.F.rows(); ++f)
    for (int k = 0; k < 3; ++k)
      longest = std::max(longest,
                         edge(f, k) / std::max(reach[grid.F(f, k)], reach[grid.F(f, (k + 1) % 3)]));
  return longest;
}

}  // namespace

TEST(Cleanup, MovesNothingOnACleanSampling) {
  Sampled x = sampledSphere();
  const SurfaceWalker walker(x.input, x.features.list);
  Remeshing out = resampled(x);
  cleanUp(out, x.input, x.grid.free, x.grid.line, x.grid.where, walker);
  EXPECT_EQ(out.cleanupDefectsBefore, 0);
  EXPECT_EQ(out.cleanupMovedPoints, 0);
  EXPECT_EQ(out.mesh.V, x.grid.mesh.V);
}

TEST(Cleanup, RepairsAFoldAndSaysSo) {
  Sampled x = sampledSphere();
  const SurfaceWalker walker(x.input, x.features.list);
  Remeshing out = resampled(x);
  dragAcrossNeighbour(x, out);
  cleanUp(out, x.input, x.grid.free, x.grid.line, x.grid.where, walker);
  EXPECT_GT(out.cleanupDefectsBefore, 0);
  EXPECT_GT(out.cleanupMovedPoints, 0);
  EXPECT_EQ(out.flippedTriangles, 0);
  EXPECT_EQ(out.degenerateTriangles, 0);
  EXPECT_EQ(out.selfIntersections, 0);
  EXPECT_LE(longestEdgeAgainstItsReach(out.mesh, out.mesh.F.rows() / out.base.F.rows()), 16.0);
}

// foldedTriangles() counts what the clean-up starts from, as it counts it (remesh()
// chooses the grid to clean up by it): none on a clean sampling; on the fold made above,
// exactly the clean-up's defects before; a grid triangle turned over (two corners
// swapped), one; a grid point moved onto its neighbour, the triangles they share, which
// have no area.
TEST(Cleanup, CountsTheFoldsItStartsFrom) {
  Sampled x = sampledSphere();
  const SurfaceWalker walker(x.input, x.features.list);
  const Connectivity& conn = walker.connectivity();
  EXPECT_EQ(foldedTriangles(x.grid.mesh, x.grid.where, x.input, conn), 0);

  TriMesh turned = x.grid.mesh;
  std::swap(turned.F(5, 1), turned.F(5, 2));
  EXPECT_EQ(foldedTriangles(turned, x.grid.where, x.input, conn), 1);

  TriMesh pinched = x.grid.mesh;
  const int a = pinched.F(7, 0), b = pinched.F(7, 1);
  pinched.V.row(b) = pinched.V.row(a);
  int shared = 0;  // the faces with both a and b as corners
  for (Eigen::Index f = 0; f < pinched.F.rows(); ++f)
    shared += (pinched.F.row(f).array() == a).any() && (pinched.F.row(f).array() == b).any();
  EXPECT_EQ(shared, 2);
  EXPECT_GE(foldedTriangles(pinched, x.grid.where, x.input, conn), shared);

  Remeshing out = resampled(x);
  dragAcrossNeighbour(x, out);
  const long long folds = foldedTriangles(out.mesh, x.grid.where, x.input, conn);
  EXPECT_GT(folds, 0);
  cleanUp(out, x.input, x.grid.free, x.grid.line, x.grid.where, walker);
  EXPECT_EQ(out.cleanupDefectsBefore, folds);
}

// The repairs say how far they are (the callback is also how remesh() abandons a clean-up
// it no longer needs: an exception from it ends the clean-up and reaches the caller).
// A rough torus over 20 base faces folds where neither the first stage nor the repairs
// mend it: the last resort runs. (Noise of 0.045, the torus crossing itself in 35 pairs:
// at 0.02 the folds were at base vertices' corners spanning over a half turn, which the
// resampling now spreads; at 0.03 the repairs left defects until they untangled their
// disks in the plane, and mend them all now.)
TEST(Cleanup, ReportsItsRepairsAndCanBeAbandoned) {
  Sampled x;
  x.input = subdivide(shapes::torus(), 1, Scheme::Loop, 0.045, 5);
  x.features = detectFeatures(x.input, 70.0);
  x.s = simplify(x.input, x.features, 20);
  const SurfaceWalker walker(x.input, x.features.list);
  x.grid = resample(x.input, walker.connectivity(), x.features.list, x.s, BaseCharts(x.s.base), 3);

  Remeshing out = resampled(x);
  std::vector<SurfacePoint> at = x.grid.where;
  std::vector<double> reported;
  int lastResorts = 0;
  cleanUp(
      out, x.input, x.grid.free, x.grid.line, at, walker,
      [&](const char* stage, double f) {
        EXPECT_STREQ(stage, "clean-up");
        reported.push_back(f);
      },
      [&] { ++lastResorts; });
  EXPECT_EQ(lastResorts, 1);
  // Every repair, the last resort's too, kept the edges within their ends' reach (the
  // longest is 3.5 times its ends' mean here).
  EXPECT_LE(longestEdgeAgainstItsReach(out.mesh, out.mesh.F.rows() / out.base.F.rows()), 16.0);
  ASSERT_FALSE(reported.empty());
  EXPECT_TRUE(std::is_sorted(reported.begin(), reported.end()));
  EXPECT_EQ(reported.back(), 1.0);
  EXPECT_TRUE(std::any_of(reported.begin(), reported.end(), [](double f) {
    return f > 0.1 && f < 1;
  })) << "the repairs report as they go";

  struct Stop {};
  Remeshing abandoned = resampled(x);
  at = x.grid.where;
  EXPECT_THROW(cleanUp(abandoned, x.input, x.grid.free, x.grid.line, at, walker,
                       [](const char*, double f) {
                         if (f > 0.1) throw Stop{};
                       }),
               Stop);

  // A clean sampling leaves nothing for the last resort.
  const Sampled sphere = sampledSphere();
  const SurfaceWalker onSphere(sphere.input, sphere.features.list);
  Remeshing clean = resampled(sphere);
  at = sphere.grid.where;
  cleanUp(clean, sphere.input, sphere.grid.free, sphere.grid.line, at, onSphere, {},
          [&] { ++lastResorts; });
  EXPECT_EQ(lastResorts, 1);
}

// A grid point on a sharp edge lies in the triangles of both sides. A grid triangle
// flat on one side with its three corners on the edges (at a cube's corner, where a
// base face has two edges on feature lines) is not flipped because its corners were
// sampled in the other sides' triangles, which it faces at a right angle: a cylinder's
// cap was repaired for nothing so.
TEST(Cleanup, ACornerOnASharpEdgeBelongsToBothSides) {
  const TriMesh cube = test::unitCube();
  const SurfaceWalker walker(cube, {});
  // Where p lies in the cube's triangle facing `side`.
  auto inSide = [&](const Vec3& p, const Vec3& side) {
    for (int t = 0; t < cube.F.rows(); ++t) {
      if (faceNormal(cube, t).normalized().dot(side) < 0.999) continue;
      const Vec3 a = cube.V.row(cube.F(t, 0)), b = cube.V.row(cube.F(t, 1)),
                 c = cube.V.row(cube.F(t, 2));
      const Vec3 n = (b - a).cross(c - a);
      const std::array<double, 3> bary = {(c - b).cross(p - b).dot(n) / n.squaredNorm(),
                                          (a - c).cross(p - c).dot(n) / n.squaredNorm(),
                                          (b - a).cross(p - a).dot(n) / n.squaredNorm()};
      if (*std::min_element(bary.begin(), bary.end()) >= 0) return SurfacePoint{t, bary};
    }
    return SurfacePoint{};
  };
  // On the top (z = 1) at its corner (0, 0, 1), facing up; each corner sampled in a side.
  Remeshing out;
  out.mesh.V.resize(3, 3);
  out.mesh.V << 0, 0, 1, 0.5, 0, 1, 0, 0.5, 1;
  out.mesh.F.resize(1, 3);
  out.mesh.F << 0, 1, 2;
  out.base = out.mesh;
  std::vector<SurfacePoint> where = {inSide(out.mesh.V.row(0), Vec3(-1, 0, 0)),
                                     inSide(out.mesh.V.row(1), Vec3(0, -1, 0)),
                                     inSide(out.mesh.V.row(2), Vec3(-1, 0, 0))};
  for (const SurfacePoint& w : where) ASSERT_GE(w.triangle, 0);
  cleanUp(out, cube, std::vector<char>(3, 0), std::vector<long long>(3, -1), where, walker);
  EXPECT_EQ(out.cleanupDefectsBefore, 0);
  EXPECT_EQ(out.flippedTriangles, 0);
  // Facing down there, it is flipped whichever side's triangles hold its corners.
  out.mesh.F << 0, 2, 1;
  cleanUp(out, cube, std::vector<char>(3, 0), std::vector<long long>(3, -1), where, walker);
  EXPECT_EQ(out.cleanupDefectsBefore, 1);
}
