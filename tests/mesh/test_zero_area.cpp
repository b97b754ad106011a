// Zero-area faces mended without changing the surface (zero_area.h): caps flipped or,
// on the boundary, dropped; needles collapsed; the result valid, of the same topology
// and area, every face on the surface it came from.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <map>
#include <vector>

#include "osdmra/mesh/zero_area.h"
#include "osdmra/subdivision/shapes.h"
#include "support.h"

using namespace osdmra;
using namespace osdmra::test;

namespace {

int zeroAreaFaces(const TriMesh& m) {
  int n = 0;
  for (int f = 0; f < m.F.rows(); ++f) n += isZeroAreaFace(m, f);
  return n;
}

}  // namespace

TEST(ZeroArea, CapsOfAFannedPolygonAreFlippedIntoTheSameSurface) {
  TriMesh m = fannedCube(4);
  validate(m, "cube");
  const int caps = zeroAreaFaces(m);
  ASSERT_EQ(caps, 12);  // two per side: (1, 2, 3) and (1, 3, 4) of its loop
  const Points before = m.V;
  const double a = surfaceArea(m);
  const Topology t = topology(m);
  const ZeroAreaRepair r = removeZeroAreaFaces(m);
  EXPECT_EQ(r.flipped, caps);
  EXPECT_EQ(r.dropped + r.collapsed + r.left, 0);
  EXPECT_EQ(zeroAreaFaces(m), 0);
  EXPECT_NO_THROW(validate(m, "mended"));
  EXPECT_EQ(topology(m), t);
  EXPECT_EQ(m.V, before);  // flips move no vertex
  EXPECT_NEAR(surfaceArea(m), a, 1e-12);
  // Every face still lies in one side of the cube (a coordinate at 0 or 1 shared by its
  // three corners): the flips split faces of the same side.
  for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
    bool inSide = false;
    for (int axis = 0; axis < 3; ++axis) {
      const double c = m.V(m.F(f, 0), axis);
      inSide =
          inSide || ((c == 0 || c == 1) && m.V(m.F(f, 1), axis) == c && m.V(m.F(f, 2), axis) == c);
    }
    EXPECT_TRUE(inSide) << "face " << f;
  }
}

// The unit cube with five sides meshed as n x n grids and its top (z = 1) one polygon
// of 4 n points fanned from its corner at the origin, as CAD exports fan: the fan's
// first and last n - 1 triangles lie along the two edges at that corner, two chains of
// caps around one vertex.
static TriMesh cubeWithATopFannedFromACorner(int n) {
  std::map<std::array<long, 3>, int> index;
  std::vector<Eigen::RowVector3d> points;
  auto vertex = [&](const Eigen::RowVector3d& p) {
    const std::array<long, 3> key = {std::lround(p(0) * n), std::lround(p(1) * n),
                                     std::lround(p(2) * n)};
    const auto [it, added] = index.emplace(key, static_cast<int>(points.size()));
    if (added) points.push_back(p);
    return it->second;
  };
  std::vector<std::array<int, 3>> faces;
  const Eigen::RowVector3d x(1, 0, 0), y(0, 1, 0), z(0, 0, 1), o(0, 0, 0);
  // Each grid spans u and v from its origin, counter-clockwise seen from outside.
  const std::array<std::array<Eigen::RowVector3d, 3>, 5> grids = {
      {{o, y, x}, {o, x, z}, {y, z, x}, {o, z, y}, {x, y, z}}};
  for (const auto& [origin, u, v] : grids)
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        auto at = [&](int a, int b) { return vertex(origin + (u * a + v * b) / n); };
        faces.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
        faces.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
      }
  const Eigen::RowVector3d corners[4] = {z, z + x, z + x + y, z + y};
  std::vector<int> loop;
  for (int c = 0; c < 4; ++c)
    for (int s = 0; s < n; ++s)
      loop.push_back(vertex(corners[c] + (corners[(c + 1) % 4] - corners[c]) * s / n));
  for (std::size_t i = 1; i + 1 < loop.size(); ++i)
    faces.push_back({loop[0], loop[i], loop[i + 1]});
  TriMesh m;
  m.V.resize(static_cast<Eigen::Index>(points.size()), 3);
  for (std::size_t i = 0; i < points.size(); ++i) m.V.row(static_cast<Eigen::Index>(i)) = points[i];
  m.F.resize(static_cast<Eigen::Index>(faces.size()), 3);
  for (std::size_t f = 0; f < faces.size(); ++f)
    m.F.row(static_cast<Eigen::Index>(f)) << faces[f][0], faces[f][1], faces[f][2];
  return m;
}

// Long fans of caps: 68 along one edge of each side (more rounds than the 64 the
// mending once stopped at, which left 24 caps), and 39 along each of the two edges at
// the corner of a fanned top (two chains around one vertex, which once went one cap a
// round between them). All are flipped, the cube unchanged.
TEST(ZeroArea, LongFansOfCapsAreAllFlipped) {
  for (TriMesh m : {fannedCube(70), cubeWithATopFannedFromACorner(40)}) {
    validate(m, "cube");
    const int caps = zeroAreaFaces(m);
    ASSERT_TRUE(caps == 6 * 68 || caps == 2 * 39) << caps;
    const double a = surfaceArea(m);
    const Topology t = topology(m);
    const ZeroAreaRepair r = removeZeroAreaFaces(m);
    EXPECT_EQ(r.flipped, caps);
    EXPECT_EQ(r.dropped + r.collapsed + r.left, 0);
    EXPECT_EQ(zeroAreaFaces(m), 0);
    EXPECT_NO_THROW(validate(m, "mended"));
    EXPECT_EQ(topology(m), t);
    EXPECT_NEAR(surfaceArea(m), a, 1e-12);
  }
}

TEST(ZeroArea, ACapOnTheBoundaryIsDropped) {
  // A unit square whose bottom edge (0,0)-(1,0) carries a cap over its midpoint m, an
  // interior vertex: dropping the cap makes a-m-b the boundary.
  TriMesh m = makeMesh({{0, 0, 0}, {1, 0, 0}, {0.5, 0, 0}, {0.5, 1, 0}, {0, 1, 0}, {1, 1, 0}},
                       {{0, 1, 2}, {0, 2, 3}, {2, 1, 3}, {0, 3, 4}, {1, 5, 3}});
  validate(m, "square");
  const Topology t = topology(m);
  const ZeroAreaRepair r = removeZeroAreaFaces(m);
  EXPECT_EQ(r.dropped, 1);
  EXPECT_EQ(r.left, 0);
  EXPECT_EQ(m.F.rows(), 4);
  EXPECT_NO_THROW(validate(m, "mended"));
  EXPECT_EQ(topology(m), t);
  EXPECT_NEAR(surfaceArea(m), 1.0, 1e-15);
}

TEST(ZeroArea, NeedlesAreCollapsed) {
  // An edge of a sphere split at one of its ends: the new vertex coincides with that
  // end, and the two faces on the edge between them are needles.
  TriMesh m = subdivide(shapes::icosahedron(), 1, Scheme::Loop);
  const TriMesh original = m;
  const int a = m.F(0, 0), b = m.F(0, 1), n = static_cast<int>(m.V.rows());
  m.V.conservativeResize(n + 1, 3);
  m.V.row(n) = m.V.row(a);
  std::vector<std::array<int, 3>> faces;
  for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
    std::array<int, 3> c = {m.F(f, 0), m.F(f, 1), m.F(f, 2)};
    int i = 0;
    while (i < 3 && !((c[i] == a && c[(i + 1) % 3] == b) || (c[i] == b && c[(i + 1) % 3] == a)))
      ++i;
    if (i == 3) {
      faces.push_back(c);
      continue;
    }
    // Split edge (c[i], c[i+1]) at the new vertex: two faces.
    faces.push_back({c[i], n, c[(i + 2) % 3]});
    faces.push_back({n, c[(i + 1) % 3], c[(i + 2) % 3]});
  }
  m.F.resize(static_cast<Eigen::Index>(faces.size()), 3);
  for (std::size_t f = 0; f < faces.size(); ++f)
    m.F.row(static_cast<Eigen::Index>(f)) << faces[f][0], faces[f][1], faces[f][2];
  validate(m, "split sphere");
  ASSERT_EQ(zeroAreaFaces(m), 2);
  const ZeroAreaRepair r = removeZeroAreaFaces(m);
  EXPECT_EQ(r.collapsed, 1);
  EXPECT_EQ(r.left, 0);
  EXPECT_EQ(zeroAreaFaces(m), 0);
  EXPECT_NO_THROW(validate(m, "mended"));
  EXPECT_EQ(m.V.rows(), original.V.rows());
  EXPECT_EQ(m.F.rows(), original.F.rows());
  EXPECT_EQ(topology(m), topology(original));
  EXPECT_NEAR(surfaceArea(m), surfaceArea(original), 1e-12);
}

TEST(ZeroArea, AMeshWithoutAnyIsLeftAsItIs) {
  TriMesh m = subdivide(shapes::torus(), 1, Scheme::Loop);
  const TriMesh before = m;
  const ZeroAreaRepair r = removeZeroAreaFaces(m);
  EXPECT_EQ(r.flipped + r.dropped + r.collapsed + r.left, 0);
  EXPECT_EQ(m.V, before.V);
  EXPECT_EQ(m.F, before.F);
}
