// Local frames of the coefficients (codec/local_frames.h): orthonormal, the normal of
// a flat region is its plane's, the along-edge tangent follows the edge, and
// toWorld inverts toLocal.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "osdmra/codec/local_frames.h"
#include "osdmra/subdivision/shapes.h"
#include "support.h"

namespace osdmra {
namespace {

TEST(LocalFrames, OrthonormalAndRightHanded) {
  const TriMesh base = shapes::byName("torus");
  const Hierarchy h(base.F, static_cast<int>(base.V.rows()), 2);
  const TriMesh surface = subdivide(base, 1, Scheme::Loop, 0.05, 3);
  const LocalFrames f = edgeFrames(h, 1, surface.V);
  ASSERT_EQ(f.normal.rows(), h.numVertices(2) - h.numVertices(1));
  for (Eigen::Index e = 0; e < f.normal.rows(); ++e) {
    const Eigen::RowVector3d n = f.normal.row(e), t = f.along.row(e), c = f.across.row(e);
    EXPECT_NEAR(n.norm(), 1, 1e-12);
    EXPECT_NEAR(t.norm(), 1, 1e-12);
    EXPECT_NEAR(n.dot(t), 0, 1e-12);
    EXPECT_NEAR((n.cross(t) - c).norm(), 0, 1e-12);
  }
}

TEST(LocalFrames, FlatRegionsHaveThePlaneNormalAndEdgeTangents) {
  // The unit square lies in z = 0.5 facing +z: every normal is +z and the along-edge
  // tangent is the edge's direction.
  const TriMesh base = test::unitSquare(0.5);
  const Hierarchy h(base.F, static_cast<int>(base.V.rows()), 1);
  const LocalFrames f = edgeFrames(h, 0, base.V);
  for (Eigen::Index e = 0; e < f.normal.rows(); ++e) {
    const auto [a, b] = h.parentEdge(0, static_cast<int>(e));
    EXPECT_NEAR((f.normal.row(e) - Eigen::RowVector3d(0, 0, 1)).norm(), 0, 1e-12) << e;
    const Eigen::RowVector3d edge = (base.V.row(b) - base.V.row(a)).normalized();
    EXPECT_NEAR((f.along.row(e) - edge).norm(), 0, 1e-12) << e;
  }
}

TEST(LocalFrames, ToWorldInvertsToLocal) {
  const TriMesh base = shapes::byName("octahedron");
  const Hierarchy h(base.F, static_cast<int>(base.V.rows()), 1);
  const LocalFrames f = edgeFrames(h, 0, base.V);
  const Points d = Points::Random(f.normal.rows(), 3);
  EXPECT_LT((toWorld(f, toLocal(f, d)) - d).cwiseAbs().maxCoeff(), 1e-14);
  // Degenerate control points (all at one place) still give frames, the same ones on
  // every call: the decoder must be able to repeat the encoder.
  const LocalFrames g = edgeFrames(h, 0, Points::Zero(base.V.rows(), 3));
  EXPECT_LT((toWorld(g, toLocal(g, d)) - d).cwiseAbs().maxCoeff(), 1e-14);
}

}  // namespace
}  // namespace osdmra
