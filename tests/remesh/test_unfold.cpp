// Step 0 of remesh.h (unfold.h): a fold of the input, a sliver turned over onto its
// neighbours, is taken out by moving its corner a short way on the surface; one that
// only a long move would take out, and a mesh without folds, are left as they are.
#include <gtest/gtest.h>

#include <algorithm>

#include "osdmra/geometry/normals.h"
#include "osdmra/remesh/features.h"
#include "osdmra/remesh/remesh.h"
#include "osdmra/remesh/unfold.h"
#include "osdmra/subdivision/shapes.h"
#include "support.h"

using namespace osdmra;
using namespace osdmra::remeshing;
using namespace osdmra::test;

namespace {

// The triangle a = (0,0), b = (2,0), c = (1, top) in the plane z = 0, split at s = (1,
// -0.01): s lies just across the side ab, so face (a, b, s) is a sliver turned over.
TriMesh turnedOverSliver(double top) {
  return makeMesh({{0, 0, 0}, {2, 0, 0}, {1, top, 0}, {1, -0.01, 0}},
                  {{0, 1, 3}, {1, 2, 3}, {2, 0, 3}});
}

int folds(const TriMesh& m) {
  const std::vector<char> corners = foldCorners(m, Connectivity(m.F, static_cast<int>(m.V.rows())));
  return static_cast<int>(std::count(corners.begin(), corners.end(), 1));
}

}  // namespace

TEST(Unfold, TakesOutASliverTurnedOverWithinTheSurface) {
  TriMesh m = turnedOverSliver(1.0);
  ASSERT_LT(faceNormal(m, 0).z(), 0);  // turned over
  ASSERT_EQ(folds(m), 3);
  const Points given = m.V;
  const UnfoldReport r = unfoldInput(m);
  EXPECT_EQ(r.foldCorners, 3);
  EXPECT_EQ(r.foldCornersLeft, 0);
  EXPECT_EQ(folds(m), 0);
  for (Eigen::Index f = 0; f < m.F.rows(); ++f) EXPECT_GT(faceNormal(m, f).z(), 0) << f;
  // Only s moved (a, b and c are on the boundary), and within the plane: the surface is
  // where it was.
  EXPECT_EQ(r.movedVertices, 1);
  for (int v = 0; v < 3; ++v) EXPECT_EQ(m.V.row(v), given.row(v)) << v;
  EXPECT_EQ(m.V(3, 2), 0.0);
  EXPECT_GT(m.V(3, 1), 0.0);
  // Within a tenth of its edges' mean length (about 1.0 here).
  const double move = (m.V.row(3) - given.row(3)).norm();
  EXPECT_LE(move, kUnfoldReach * 1.01);
  EXPECT_NEAR(r.largestMove, move / boundingBoxDiagonal(given), 1e-12);
}

TEST(Unfold, LeavesAFoldOnlyALongMoveWouldTakeOut) {
  // With c = (1, 2), the centroid of s's neighbours is 0.68 away: a quarter of that is
  // more than a tenth of s's edges' mean length, so s stays where it is.
  TriMesh m = turnedOverSliver(2.0);
  const Points given = m.V;
  const UnfoldReport r = unfoldInput(m);
  EXPECT_EQ(r.foldCorners, 3);
  EXPECT_EQ(r.foldCornersLeft, 3);
  EXPECT_EQ(r.movedVertices, 0);
  EXPECT_EQ(m.V, given);
}

TEST(Unfold, LeavesAMeshWithoutFoldsExactlyAsItIs) {
  for (TriMesh m : {shapes::icosahedron(), unitCube(), cornerTetrahedron()}) {
    const TriMesh given = m;
    const UnfoldReport r = unfoldInput(m);
    EXPECT_EQ(r.foldCorners, 0);
    EXPECT_EQ(r.movedVertices, 0);
    EXPECT_EQ(m.V, given.V);
    EXPECT_EQ(m.F, given.F);
  }
}

TEST(Unfold, RemeshSamplesTheInputUnfoldedAndMeasuresAgainstItAsGiven) {
  // A flat plate of 8 x 8 cells 2 wide and 0.5 high, two triangles each, the first face of
  // the cell at (4, 4) split at a point just across its bottom side (a sliver turned over,
  // as in the tests above).
  const int n = 8;
  TriMesh m;
  m.V.resize((n + 1) * (n + 1) + 1, 3);
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) m.V.row(j * (n + 1) + i) << 2.0 * i, 0.5 * j, 0;
  const int s = (n + 1) * (n + 1);
  m.V.row(s) << 2.0 * 4 + 1.3, 0.5 * 4 - 0.01, 0;
  std::vector<std::array<int, 3>> faces;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
      if (i == 4 && j == 4) {
        faces.push_back({a, b, s});
        faces.push_back({b, d, s});
        faces.push_back({d, a, s});
      } else {
        faces.push_back({a, b, d});
      }
      faces.push_back({a, d, c});
    }
  m.F.resize(static_cast<Eigen::Index>(faces.size()), 3);
  for (std::size_t f = 0; f < faces.size(); ++f)
    m.F.row(static_cast<Eigen::Index>(f)) << faces[f][0], faces[f][1], faces[f][2];
  ASSERT_EQ(folds(m), 3);

  RemeshOptions options;
  options.baseFaces = 16;
  options.levels = 3;
  const Remeshing r = remesh(m, options);
  EXPECT_EQ(r.unfold.foldCorners, 3);
  EXPECT_EQ(r.unfold.foldCornersLeft, 0);
  EXPECT_EQ(r.unfold.movedVertices, 1);
  EXPECT_GT(r.unfold.largestMove, 0);
  EXPECT_EQ(r.flippedTriangles, 0);
  EXPECT_EQ(r.selfIntersections, 0);
  EXPECT_EQ(r.cleanupMovedPoints, 0);
  // The plate stays flat: the unfolding moved s within it.
  EXPECT_EQ(r.mesh.V.col(2).cwiseAbs().maxCoeff(), 0.0);

  options.unfoldInput = false;
  const Remeshing without = remesh(m, options);
  EXPECT_EQ(without.unfold.foldCorners, 0);  // not looked for
  EXPECT_EQ(without.unfold.movedVertices, 0);
}
