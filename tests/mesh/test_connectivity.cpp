// The mesh traversal utility: VertexRings must agree with Connectivity's rings and
// find the same defects, whatever the face order and however many corners a vertex has.
#include <gtest/gtest.h>

#include <random>

#include "osdmra/mesh/connectivity.h"
#include "osdmra/subdivision/shapes.h"
#include "support.h"

using namespace osdmra;
using namespace osdmra::test;

namespace {

void expectSameRings(const Faces& F, int n) {
  const Connectivity c(F, n);
  const VertexRings r(F, n);
  for (int v = 0; v < n; ++v) {
    SCOPED_TRACE("vertex " + std::to_string(v));
    ASSERT_EQ(r.isManifoldVertex(v), c.isManifoldVertex(v));
    ASSERT_EQ(r.isBoundaryVertex(v), c.isBoundaryVertex(v));
    ASSERT_EQ(std::vector<int>(r.ring(v).begin(), r.ring(v).end()),
              std::vector<int>(c.ring(v).begin(), c.ring(v).end()));
  }
  EXPECT_EQ(r.numEdgesIfManifold(), c.numEdges());
  EXPECT_EQ(r.firstNonManifoldVertex, -1);
  EXPECT_EQ(r.firstIsolatedVertex, -1);
}

// A fan of k triangles around vertex 0, closed (a cone over a k-gon, capped by a
// second apex) or open (a disc sector).
Faces fan(int k, bool closed) {
  Faces F(closed ? 2 * k : k - 1, 3);
  int f = 0;
  for (int i = 0; i < (closed ? k : k - 1); ++i) F.row(f++) << 0, 1 + i, 1 + (i + 1) % k;
  if (closed)
    for (int i = 0; i < k; ++i) F.row(f++) << k + 1, 1 + (i + 1) % k, 1 + i;
  return F;
}

}  // namespace

TEST(VertexRings, AgreeWithConnectivityOnEveryShape) {
  for (const auto& [name, base] : shapes::all()) {
    SCOPED_TRACE(name);
    const TriMesh m = subdivide(base, 2, Scheme::Linear);
    Faces F = m.F;
    const int n = static_cast<int>(m.V.rows());
    expectSameRings(F, n);
    // Face order decides where a closed ring starts, for both.
    std::mt19937 rng(3);
    for (Eigen::Index f = F.rows() - 1; f > 0; --f) F.row(f).swap(F.row(rng() % (f + 1)));
    expectSameRings(F, n);
  }
}

TEST(VertexRings, ManyCornersAtOneVertex) {
  // Past the small-fan path: sorted search, same rings.
  for (int k : {3, 15, 16, 17, 40, 1000}) {
    SCOPED_TRACE(k);
    expectSameRings(fan(k, true), k + 2);
    expectSameRings(fan(k, false), k + 1);
    // Several fans meeting at vertex 0 (two open sectors sharing it).
    Faces two(2 * (k - 1), 3);
    two << fan(k, false), (fan(k, false).array() + k).matrix();
    two.bottomRows(k - 1).col(0).setZero();
    const VertexRings r(two, 2 * k + 1);
    EXPECT_EQ(r.firstNonManifoldVertex, 0);
    EXPECT_EQ(r.ring(0).size(), 0);
  }
}

TEST(VertexRings, Defects) {
  const TriMesh oct = shapes::octahedron();
  // A face of opposite winding: its vertices see a neighbour twice on one side.
  {
    Faces F = oct.F;
    std::swap(F(0, 1), F(0, 2));
    const VertexRings r(F, 6);
    EXPECT_GE(r.firstNonManifoldVertex, 0);
    EXPECT_FALSE(r.isManifoldVertex(F(0, 0)));
  }
  // An edge with three faces.
  {
    Faces F(oct.F.rows() + 1, 3);
    F << oct.F, Eigen::RowVector3i(oct.F(0, 0), oct.F(0, 1), 6);
    const VertexRings r(F, 7);
    EXPECT_GE(r.firstNonManifoldVertex, 0);
  }
  // An isolated vertex.
  {
    const VertexRings r(oct.F, 7);
    EXPECT_EQ(r.firstIsolatedVertex, 6);
    EXPECT_EQ(r.firstNonManifoldVertex, -1);
  }
}

// Built from known face edges (a subdivision level's), Connectivity is the one built
// from the faces alone, in any edge numbering; a face list those edges do not show
// consistently oriented (a flipped face) gets the general construction, defect and all.
TEST(Connectivity, FromFaceEdgesIsTheSame) {
  for (const auto& [name, m] : shapes::all()) {
    SCOPED_TRACE(name);
    const int n = static_cast<int>(m.V.rows());
    const Connectivity general(m.F, n);
    const int E = general.numEdges();
    Connectivity::FaceEdgeList FE(m.F.rows());
    for (int h = 0; h < 3 * general.numFaces(); ++h)
      FE[h / 3][h % 3] = E - 1 - general.edge(h);  // another numbering
    expectSameConnectivity(Connectivity(m.F, n, FE, E), general);
    Faces flipped = m.F;
    std::swap(flipped(0, 1), flipped(0, 2));
    Connectivity::FaceEdgeList flippedFE = FE;
    flippedFE[0] = {FE[0][2], FE[0][1], FE[0][0]};  // (v0, v2), (v2, v1), (v1, v0)
    const Connectivity flippedGeneral(flipped, n);
    EXPECT_GE(flippedGeneral.firstFlippedFace, 0);
    expectSameConnectivity(Connectivity(flipped, n, flippedFE, E), flippedGeneral);
  }
}
