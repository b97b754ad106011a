// Local frames of the coefficients (codec/local_frames.h): orthonormal, the normal of
// a flat region is its plane's, the along-edge tangent follows the edge, and
// toWorld inverts toLocal; the bend is 0 where the surface is flat and the spread of
// the face normals around an edge's ends elsewhere.
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

TEST(LocalFrames, BendIsZeroWhereFlatAndTheNormalsSpreadElsewhere) {
  const TriMesh square = test::unitSquare(0.5);
  const Hierarchy flat(square.F, static_cast<int>(square.V.rows()), 1);
  EXPECT_LT(edgeFrames(flat, 0, square.V).bend.cwiseAbs().maxCoeff(), 1e-15);
  // The octahedron's vertex normals are the axes and its face normals (+-1, +-1, +-1)
  // / sqrt 3: every corner's normals are acos(1 / sqrt 3) apart.
  const TriMesh octahedron = shapes::byName("octahedron");
  const Hierarchy h(octahedron.F, static_cast<int>(octahedron.V.rows()), 1);
  const LocalFrames f = edgeFrames(h, 0, octahedron.V);
  ASSERT_EQ(f.bend.size(), 12);
  for (Eigen::Index e = 0; e < f.bend.size(); ++e)
    EXPECT_NEAR(f.bend[e], std::sqrt(2 - 2 / std::sqrt(3.0)), 1e-14) << e;
  // Bent further (one tip pulled out), the edges at the tip bend more.
  Points pulled = octahedron.V;
  pulled.row(0) *= 3;
  const LocalFrames g = edgeFrames(h, 0, pulled);
  for (Eigen::Index e = 0; e < g.bend.size(); ++e) {
    const auto [a, b] = h.parentEdge(0, static_cast<int>(e));
    if (a == 0 || b == 0) {
      EXPECT_GT(g.bend[e], f.bend[e] + 0.1) << e;
    }
  }
}

}  // namespace
}  // namespace osdmra
