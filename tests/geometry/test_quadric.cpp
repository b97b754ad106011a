// Garland-Heckbert quadrics (quadric.h): a quadric's value is the weighted sum of the
// squared distances to its planes, exactly; sums and scalings add planes.
#include <gtest/gtest.h>

#include "osdmra/geometry/quadric.h"
#include "osdmra/subdivision/shapes.h"
#include "support.h"

using namespace osdmra;

TEST(Quadric, IsTheWeightedSumOfSquaredDistancesToItsPlanes) {
  Quadric q;
  const Eigen::Vector3d n1 = Eigen::Vector3d(1, 2, 2) / 3, n2(0, 0, 1);
  const Eigen::Vector3d at1(1, 0, 0), at2(0, 0, -2);
  q.addPlane(n1, at1, 2.0);
  q.addPlane(n2, at2, 0.5);
  for (const Eigen::Vector3d& p : {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(3, -1, 4),
                                   Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(-2, 5, -2)}) {
    const double d1 = n1.dot(p - at1), d2 = n2.dot(p - at2);
    EXPECT_NEAR(q(p), 2.0 * d1 * d1 + 0.5 * d2 * d2, 1e-12);
  }
  Quadric sum;
  sum.add(q, 3.0);
  EXPECT_NEAR(sum(Eigen::Vector3d(3, -1, 4)), 3.0 * q(Eigen::Vector3d(3, -1, 4)), 1e-12);
}

TEST(Quadric, VertexQuadricsVanishOnTheirOwnFacesPlanes) {
  // Every plane of a vertex's quadric goes through the vertex: zero there. The weights
  // (the trace of A, each normal being of unit length) are a third of each face's area
  // on each corner, so they sum to the area of the surface.
  const TriMesh cube = test::unitCube();
  const std::vector<Quadric> q = vertexQuadrics(cube);
  ASSERT_EQ(q.size(), static_cast<std::size_t>(cube.V.rows()));
  double areaSum = 0;
  for (Eigen::Index v = 0; v < cube.V.rows(); ++v) {
    const Eigen::Vector3d p = cube.V.row(v);
    EXPECT_NEAR(q[v](p), 0.0, 1e-12);
    areaSum += q[v].A.trace();  // the weights: each plane's normal has unit length
  }
  EXPECT_NEAR(areaSum, 6.0, 1e-12);  // the cube's area, shared out by thirds
}
