// T-junctions zipped (t_junctions.h): an edge with vertices of the other side lying on
// it is split at them, so that the crack closes and the surface stays the same.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "osdmra/base/error.h"
#include "osdmra/mesh/t_junctions.h"
#include "osdmra/subdivision/shapes.h"
#include "support.h"

using namespace osdmra;
using namespace osdmra::test;

TEST(TJunctions, AVertexOnANeighboursEdgeClosesTheCrack) {
  // Two unit squares side by side, meshed apart: the right one has a vertex (6) in the
  // middle of the edge x = 1 that the left one's triangle (0, 1, 3) spans whole.
  TriMesh m =
      makeMesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {2, 0, 0}, {2, 1, 0}, {1, 0.5, 0}},
               {{0, 1, 3}, {0, 3, 2}, {1, 4, 6}, {4, 5, 6}, {6, 5, 3}});
  // The crack's ends are pinched: validate() refuses the mesh as it is.
  EXPECT_THROW(validate(m, "cracked"), Error);
  const double a = surfaceArea(m);
  EXPECT_EQ(zipTJunctions(m), 1);
  EXPECT_NO_THROW(validate(m, "zipped"));
  EXPECT_EQ(topology(m).boundaryLoops, 1);
  EXPECT_EQ(m.F.rows(), 6);
  EXPECT_NEAR(surfaceArea(m), a, 1e-15);
  EXPECT_EQ(zipTJunctions(m), 0);  // nothing left to zip
}

TEST(TJunctions, AFaceWithJunctionsOnTwoEdgesIsSplitAlongBoth) {
  // A triangle (0, 1, 2) with two neighbours meshed finer: each puts a vertex in the
  // middle of one of its edges.
  TriMesh m = makeMesh({{0, 0, 0},
                        {2, 0, 0},
                        {0, 2, 0},
                        {1, 0, 0},    // 3: middle of (0, 1)
                        {0, 1, 0},    // 4: middle of (2, 0)
                        {1, -1, 0},   // 5: below (0, 1)
                        {-1, 1, 0}},  // 6: left of (2, 0)
                       {{0, 1, 2}, {0, 5, 3}, {3, 5, 1}, {0, 4, 6}, {4, 2, 6}});
  EXPECT_THROW(validate(m, "cracked twice"), Error);
  const double a = surfaceArea(m);
  EXPECT_EQ(zipTJunctions(m), 2);
  EXPECT_NO_THROW(validate(m, "zipped"));
  EXPECT_EQ(topology(m).boundaryLoops, 1);
  EXPECT_NEAR(surfaceArea(m), a, 1e-15);
}

TEST(TJunctions, ABoundaryWithoutAnyIsLeftAsItIs) {
  // A disc's straight runs of boundary have no vertex strictly inside another's edge.
  TriMesh m = subdivide(shapes::disc(), 2, Scheme::Linear);
  const TriMesh before = m;
  EXPECT_EQ(zipTJunctions(m), 0);
  EXPECT_EQ(m.F, before.F);
}
