// Zero-area faces mended without changing the surface (zero_area.h): caps flipped or,
// on the boundary, dropped; needles collapsed; the result valid, of the same topology
// and area, every face on the surface it came from.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
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

// Mends m and expects its `caps` flipped, nothing else done or left, and the mesh valid,
// of the same topology and area.
void expectCapsFlipped(TriMesh& m, int caps) {
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

}  // namespace

TEST(ZeroArea, CapsOfAFannedPolygonAreFlippedIntoTheSameSurface) {
  TriMesh m = fannedCube(4);
  validate(m, "cube");
  const int caps = zeroAreaFaces(m);
  ASSERT_EQ(caps, 12);  // two per side: (1, 2, 3) and (1, 3, 4) of its loop
  const Points before = m.V;
  expectCapsFlipped(m, caps);
  EXPECT_EQ(m.V, before);  // flips move no vertex
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

// Long fans of caps: 68 along one edge of each side (more rounds than the 64 the
// mending once stopped at, which left 24 caps), and 39 along each of the two edges at
// the corner of a fanned top (two chains around one vertex, which once went one cap a
// round between them). All are flipped, the cube unchanged.
TEST(ZeroArea, LongFansOfCapsAreAllFlipped) {
  for (TriMesh m : {fannedCube(70), cubeWithATopFannedFromACorner(40)}) {
    validate(m, "cube");
    const int caps = zeroAreaFaces(m);
    ASSERT_TRUE(caps == 6 * 68 || caps == 2 * 39) << caps;
    expectCapsFlipped(m, caps);
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
