// Spatial order (spatial_order.h): a permutation that keeps the surface, and a function
// of the surface alone, whatever the numbering it is given in.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <set>
#include <vector>

#include "osdmra/mesh/spatial_order.h"
#include "osdmra/subdivision/shapes.h"
#include "support.h"

using namespace osdmra;
using namespace osdmra::test;

namespace {

// The faces as triples of corner positions, each rotated to start at its smallest
// corner (orientation kept): equal for two numberings of one surface.
std::set<std::array<std::array<double, 3>, 3>> faceSet(const TriMesh& m) {
  std::set<std::array<std::array<double, 3>, 3>> out;
  for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
    std::array<std::array<double, 3>, 3> t;
    for (int k = 0; k < 3; ++k) t[k] = {m.V(m.F(f, k), 0), m.V(m.F(f, k), 1), m.V(m.F(f, k), 2)};
    std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
    out.insert(t);
  }
  return out;
}

}  // namespace

TEST(SpatialOrder, MortonOrderIsAPermutationThatFollowsTheZCurve) {
  Points p(5, 3);
  p << 1, 1, 1,  // the far corner: last
      0, 0, 0,   // the near corner: first
      1, 0, 0,   // x is the lowest bit of each triple
      0, 1, 0,   //
      0, 0, 1;
  const std::vector<Eigen::Index> order = mortonOrder(p);
  EXPECT_EQ(order, (std::vector<Eigen::Index>{1, 2, 3, 4, 0}));
  EXPECT_TRUE(mortonOrder(Points(0, 3)).empty());
}

TEST(SpatialOrder, PointsInOneCellAreOrderedByTheirCoordinates) {
  // The second and third lie in the grid's first cell with the first: ordered by x, in
  // whichever rows they come.
  Points p(4, 3);
  p << 1e-9, 0, 0,  //
      1, 1, 1,      //
      0, 0, 0,      //
      2e-9, 0, 0;
  Points q = p.colwise().reverse();
  auto positions = [](const Points& points) {
    std::vector<double> x;
    for (Eigen::Index i : mortonOrder(points)) x.push_back(points(i, 0));
    return x;
  };
  EXPECT_EQ(positions(p), (std::vector<double>{0, 1e-9, 2e-9, 1}));
  EXPECT_EQ(positions(q), positions(p));
}

TEST(SpatialOrder, KeepsTheSurfaceAndIgnoresTheNumbering) {
  const TriMesh m = subdivide(shapes::torus(), 2, Scheme::Loop, 0.01, 3);
  const TriMesh ordered = inSpatialOrder(m);
  validate(ordered, "ordered");
  EXPECT_EQ(topology(ordered), topology(m));
  EXPECT_EQ(faceSet(ordered), faceSet(m));
  // Faces sorted by their corners, each starting at its smallest; vertices along the
  // curve, so that a face's corners are mostly near each other in the numbering.
  for (Eigen::Index f = 0; f < ordered.F.rows(); ++f) {
    EXPECT_LT(ordered.F(f, 0), ordered.F(f, 1));
    EXPECT_LT(ordered.F(f, 0), ordered.F(f, 2));
    if (f > 0) {
      EXPECT_LE(ordered.F(f - 1, 0), ordered.F(f, 0));
    }
  }
  for (std::uint64_t seed : {1, 2, 3}) {
    const TriMesh again = inSpatialOrder(shuffle(m, seed));
    EXPECT_EQ(again.V, ordered.V) << "seed " << seed;
    EXPECT_EQ(again.F, ordered.F) << "seed " << seed;
  }
}

TEST(SpatialOrder, NormalsFollowTheirVertices) {
  TriMesh m = shapes::icosahedron();
  m.N = m.V.rowwise().normalized();
  const TriMesh ordered = inSpatialOrder(m);
  ASSERT_EQ(ordered.N.rows(), m.N.rows());
  EXPECT_TRUE(ordered.N.isApprox(ordered.V.rowwise().normalized()));
}
