// validate() and boundingBoxDiagonal(): every defect is rejected with a message
// that names the source and the offending element.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <utility>

#include "osdmra/base/error.h"
#include "osdmra/mesh/mesh.h"
#include "osdmra/subdivision/shapes.h"
#include "support.h"

using namespace osdmra;
using namespace osdmra::test;

namespace {

/// The message validate() throws, or "" (and a test failure) if it accepts.
std::string rejection(const TriMesh& m, const std::string& source = "mesh.obj") {
  return errorOf([&] { validate(m, source); });
}

}  // namespace

TEST(Validate, AcceptsClosedAndOpenManifolds) {
  EXPECT_NO_THROW(validate(cornerTetrahedron(), "tet"));
  EXPECT_NO_THROW(validate(unitSquare(), "square"));
  TriMesh withNormals = unitSquare();
  withNormals.N = Points::Zero(4, 3);
  EXPECT_NO_THROW(validate(withNormals, "square"));
}

TEST(Validate, RejectsEmptyMeshes) {
  expectContains(rejection(TriMesh{}, "empty.off"), {"empty.off: ", "no faces"});
  TriMesh points = unitSquare();
  points.F.resize(0, 3);
  expectContains(rejection(points, "points.ply"), {"points.ply: ", "no faces", "4 vertices"});
}

TEST(Validate, RejectsIndexOutOfRange) {
  TriMesh m = cornerTetrahedron();
  m.F(2, 1) = 7;
  expectContains(rejection(m), {"mesh.obj: ", "face 2, corner 1", "index 7", "out of range"});
  m.F(2, 1) = -1;
  expectContains(rejection(m), {"face 2, corner 1", "index -1"});
}

TEST(Validate, RejectsRepeatedVertex) {
  TriMesh m = cornerTetrahedron();
  m.F.row(1) << 0, 3, 3;
  expectContains(rejection(m), {"mesh.obj: ", "face 1 (0, 3, 3)", "vertex 3 twice"});
}

TEST(Validate, RejectsNonFiniteCoordinates) {
  TriMesh m = cornerTetrahedron();
  m.V(2, 1) = std::numeric_limits<double>::quiet_NaN();
  expectContains(rejection(m), {"mesh.obj: ", "vertex 2", "non-finite", "nan"});
  m.V(2, 1) = 0;
  m.V(3, 0) = -std::numeric_limits<double>::infinity();
  expectContains(rejection(m), {"vertex 3", "-inf"});
}

TEST(Validate, RejectsIsolatedVertex) {
  TriMesh m = cornerTetrahedron();
  m.V.conservativeResize(5, 3);
  m.V.row(4) << 2, 2, 2;
  expectContains(rejection(m), {"mesh.obj: ", "vertex 4", "not used by any face"});
}

TEST(Validate, RejectsMismatchedNormals) {
  TriMesh m = cornerTetrahedron();
  m.N = Points::Zero(3, 3);
  expectContains(rejection(m), {"3 normals for 4 vertices"});
}

TEST(Validate, RejectsNonManifoldEdge) {
  // Three sheets hinged on edge (0, 1): consistently oriented pairs cannot fix it.
  const TriMesh m = makeMesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}},
                             {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}});
  const std::string msg = rejection(m, "fin.ply");
  expectContains(msg, {"fin.ply: ", "face 0 (0, 1, 2)", "edge (0, 1)", "shared by 3 faces",
                       "non-manifold edge"});
  // All three faces are listed with their direction, so a user can tell this from
  // an orientation problem.
  expectContains(msg, {"0 (0->1)", "1 (1->0)", "2 (0->1)"});
}

TEST(Validate, RejectsFlippedFaceAndNamesTheCulprit) {
  TriMesh m = cornerTetrahedron();
  m.F.row(3) << 1, 3, 2;  // reversed: disagrees with all three neighbours
  const std::string msg = rejection(m, "tet.obj");
  expectContains(
      msg, {"tet.obj: ", "face 3 (1, 3, 2) is oriented inconsistently", "reverse its winding"});
}

TEST(Validate, RejectsInconsistentPairAndNamesBoth) {
  TriMesh m = unitSquare();
  m.F.row(1) << 0, 3, 2;  // shares edge 0->2 with face 0, same direction
  const std::string msg = rejection(m);
  expectContains(msg, {"face 0 (0, 1, 2)", "face 1 (0, 3, 2)", "edge 2->0"});
  expectContains(msg, {"reverse one of them"});
}

TEST(Validate, RejectsDuplicateFace) {
  TriMesh m = cornerTetrahedron();
  m.F.conservativeResize(5, 3);
  m.F.row(4) = m.F.row(1);
  expectContains(rejection(m), {"face 4 (0, 1, 3) duplicates face 1 (0, 1, 3)"});
  // On an open mesh a duplicate looks like a flipped pair instead; still named.
  const TriMesh twice = makeMesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2}, {1, 2, 0}});
  expectContains(rejection(twice), {"face 1 (1, 2, 0) duplicates face 0 (0, 1, 2)"});
}

TEST(Validate, RejectsBowtieVertex) {
  // Two triangles touching only at vertex 0.
  const TriMesh m =
      makeMesh({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {-1, 0, 0}, {-1, -1, 0}}, {{0, 1, 2}, {0, 3, 4}});
  expectContains(rejection(m, "bowtie.off"), {"bowtie.off: ", "vertex 0 is non-manifold",
                                              "2 separate fans", "face 0", "face 1"});
}

TEST(Validate, RejectsTwoConesSharingAnApex) {
  // Two closed fans (double cone) at vertex 0: manifold edges, non-manifold vertex.
  TriMesh m;
  m.V.resize(7, 3);
  m.V << 0, 0, 0, 1, 0, 1, 0, 1, 1, -1, -1, 1, 1, 0, -1, 0, 1, -1, -1, -1, -1;
  m.F.resize(8, 3);
  // Upper cone (apex 0, ring 1 2 3) closed by cap (1 2 3); lower cone likewise.
  m.F << 0, 2, 1, 0, 3, 2, 0, 1, 3, 1, 2, 3, 0, 4, 5, 0, 5, 6, 0, 6, 4, 4, 6, 5;
  expectContains(rejection(m), {"vertex 0 is non-manifold", "2 separate fans"});
}

TEST(Validate, ReportsTheCauseBeforeItsSymptoms) {
  // The flipped face also breaks its vertices' fans; the face must be reported.
  TriMesh m = cornerTetrahedron();
  m.F.row(3) << 1, 3, 2;
  EXPECT_EQ(rejection(m).find("non-manifold"), std::string::npos) << rejection(m);
}

TEST(BoundingBox, Diagonal) {
  EXPECT_EQ(boundingBoxDiagonal(Points(0, 3)), 0.0);
  EXPECT_DOUBLE_EQ(boundingBoxDiagonal(cornerTetrahedron().V), std::sqrt(3.0));
  Points p(2, 3);
  p << -1, 2, 3, 2, 6, 3;
  EXPECT_DOUBLE_EQ(boundingBoxDiagonal(p), 5.0);
}

namespace {

/// Every face of `m` with its own three vertices, as an STL file turned into OBJ has.
TriMesh soupOf(const TriMesh& m) {
  TriMesh s;
  s.V.resize(3 * m.F.rows(), 3);
  s.F.resize(m.F.rows(), 3);
  for (Eigen::Index f = 0; f < m.F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      s.V.row(3 * f + k) = m.V.row(m.F(f, k));
      s.F(f, k) = static_cast<int>(3 * f + k);
    }
  return s;
}

}  // namespace

TEST(Weld, ASoupBecomesTheMeshItCameFrom) {
  const TriMesh octahedron = makeMesh(
      {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}},
      {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}});
  TriMesh soup = soupOf(octahedron);
  // -0 and +0 are the same position.
  soup.V(0, 1) = -0.0;
  const Welding w = weldBoundaryVertices(soup);
  EXPECT_EQ(w.vertices, 24 - 6);
  EXPECT_EQ(w.faces, 0);
  EXPECT_TRUE(w.refused.empty()) << w.refused;
  ASSERT_EQ(soup.V.rows(), 6);
  ASSERT_EQ(soup.F.rows(), 8);
  EXPECT_NO_THROW(validate(soup, "welded"));
  // Each face keeps its corners' positions, in order.
  for (Eigen::Index f = 0; f < 8; ++f)
    for (int k = 0; k < 3; ++k)
      EXPECT_EQ(Eigen::RowVector3d(soup.V.row(soup.F(f, k))),
                Eigen::RowVector3d(octahedron.V.row(octahedron.F(f, k))))
          << f << " " << k;
}

TEST(Weld, DropsFacesWhoseCornersMergeAndLeavesTheRestAlone) {
  // A square of two triangles with a sliver (0, 2, 2') along its diagonal, all apart:
  // the sliver's two corners at the same point merge and it goes.
  TriMesh m = makeMesh({{0, 0, 0},
                        {1, 0, 0},
                        {1, 1, 0},
                        {0, 0, 0},
                        {1, 1, 0},
                        {0, 1, 0},
                        {0, 0, 0},
                        {1, 1, 0},
                        {1, 1, 0}},
                       {{0, 1, 2}, {3, 4, 5}, {6, 7, 8}});
  const Welding w = weldBoundaryVertices(m);
  EXPECT_EQ(w.faces, 1);
  EXPECT_EQ(m.F.rows(), 2);
  EXPECT_EQ(m.V.rows(), 4);
  // A mesh without coincident boundary vertices is left as it is; so are interior
  // vertices at the same position (two closed tetrahedra, one inside the other's place).
  TriMesh two = cornerTetrahedron();
  const TriMesh one = two;
  two.V.conservativeResize(8, 3);
  two.V.bottomRows(4) = one.V;
  two.F.conservativeResize(8, 3);
  two.F.bottomRows(4) = one.F.array() + 4;
  const TriMesh before = two;
  const Welding none = weldBoundaryVertices(two);
  EXPECT_EQ(none.vertices, 0);
  EXPECT_EQ(two.V, before.V);
  EXPECT_EQ(two.F, before.F);
}

TEST(Weld, RefusesWhatWouldNotBeAManifold) {
  // Three triangles apart, hinged on the same segment: welded, that edge would have
  // three faces. Nothing changes, and the reason is given.
  TriMesh m = makeMesh({{0, 0, 0},
                        {1, 0, 0},
                        {0, 1, 0},
                        {1, 0, 0},
                        {0, 0, 0},
                        {0, -1, 0},
                        {0, 0, 0},
                        {1, 0, 0},
                        {0, 0, 1}},
                       {{0, 1, 2}, {3, 4, 5}, {6, 7, 8}});
  const TriMesh before = m;
  const Welding w = weldBoundaryVertices(m);
  EXPECT_EQ(w.vertices, 0);
  EXPECT_NE(w.refused.find("non-manifold"), std::string::npos) << w.refused;
  EXPECT_EQ(m.V, before.V);
  EXPECT_EQ(m.F, before.F);
}

TEST(SplitNonManifold, ABowtieBecomesTwoFansAtTheSamePoint) {
  // Two triangles touching only at vertex 0 (the bowtie validate() refuses).
  TriMesh m =
      makeMesh({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {-1, 0, 0}, {-1, -1, 0}}, {{0, 1, 2}, {0, 3, 4}});
  m.N = m.V;  // normals follow their vertex
  EXPECT_EQ(splitNonManifoldVertices(m), 1);
  ASSERT_EQ(m.V.rows(), 6);
  EXPECT_EQ(m.F.row(0), Eigen::RowVector3i(0, 1, 2));
  EXPECT_EQ(m.F.row(1), Eigen::RowVector3i(5, 3, 4));
  EXPECT_EQ(Eigen::RowVector3d(m.V.row(5)), Eigen::RowVector3d(m.V.row(0)));
  EXPECT_EQ(Eigen::RowVector3d(m.N.row(5)), Eigen::RowVector3d(m.N.row(0)));
  EXPECT_NO_THROW(validate(m, "split"));
  // A manifold is left alone, and so is what splitting cannot mend (an edge of three
  // faces), which validate() goes on to report.
  EXPECT_EQ(splitNonManifoldVertices(m), 0);
  TriMesh book = makeMesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}},
                          {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}});
  EXPECT_EQ(splitNonManifoldVertices(book), 0);
  EXPECT_EQ(book.V.rows(), 5);
}

TEST(DuplicateFaces, CopiesInEitherOrientationGoAndTheFirstStays) {
  // The octahedron with face 2 repeated as it is and face 5 turned over: each copy makes
  // its three edges non-manifold, which validate() refuses; dropped, the octahedron is
  // back, face for face.
  const TriMesh octahedron = makeMesh(
      {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}},
      {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}});
  TriMesh m = octahedron;
  m.F.conservativeResize(10, 3);
  m.F.row(8) = octahedron.F.row(2);
  m.F.row(9) << 2, 5, 1;  // face 5, (1, 2, 5), the other way round
  EXPECT_THROW(validate(m, "with copies"), Error);
  EXPECT_EQ(removeDuplicateFaces(m), 2);
  EXPECT_EQ(m.F, octahedron.F);
  EXPECT_NO_THROW(validate(m, "without copies"));
  // Nothing else goes: not a face sharing two corners, nor one of a malformed mesh.
  EXPECT_EQ(removeDuplicateFaces(m), 0);
  TriMesh bad = m;
  bad.F(0, 1) = bad.F(0, 0);
  bad.F.row(1) = bad.F.row(0);
  EXPECT_EQ(removeDuplicateFaces(bad), 0);
  EXPECT_EQ(bad.F.rows(), 8);
}

TEST(Weld, ASoupWhosePinchesWeldingMakesIsWeldedThenSplit) {
  // The bowtie above as a soup: welding joins the two triangles at vertex 0 too; that
  // pinch is split again, so the welding is accepted.
  TriMesh m = makeMesh({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 0, 0}, {-1, 0, 0}, {-1, -1, 0}},
                       {{0, 1, 2}, {3, 4, 5}});
  const Welding w = weldBoundaryVertices(m);
  EXPECT_EQ(w.vertices, 1);
  EXPECT_TRUE(w.refused.empty()) << w.refused;
  EXPECT_EQ(splitNonManifoldVertices(m), 1);
  EXPECT_NO_THROW(validate(m, "welded and split"));
}

TEST(CutNonManifoldEdges, AFinComesOffTheSurfaceItWasStuckTo) {
  // The unit cube with a fin: a face on its edge (0, 1), a third face there. Cut open,
  // the cube keeps its faces and vertices and the fin is a face of its own.
  TriMesh m = unitCube();
  m.V.conservativeResize(9, 3);
  m.V.row(8) << 0.5, -1, -1;
  m.F.conservativeResize(13, 3);
  m.F.row(12) << 0, 1, 8;
  EXPECT_THROW(validate(m, "finned cube"), Error);
  const TriMesh cube = unitCube();
  EXPECT_EQ(cutNonManifoldEdges(m), 1);
  EXPECT_NO_THROW(validate(m, "cut"));
  EXPECT_EQ(m.F.topRows(12), cube.F);
  EXPECT_EQ(m.V.topRows(8), cube.V);
  ASSERT_EQ(m.V.rows(), 11);  // the fin's copies of vertices 0 and 1
  EXPECT_EQ(m.V.row(9), cube.V.row(0));
  EXPECT_EQ(m.V.row(10), cube.V.row(1));
  EXPECT_EQ(topology(m).components, 2);
  EXPECT_EQ(topology(m).boundaryLoops, 1);
  // Nothing else to cut: a second call changes nothing.
  const TriMesh once = m;
  EXPECT_EQ(cutNonManifoldEdges(m), 0);
  EXPECT_EQ(m.F, once.F);
}

TEST(OrientConsistently, ReversedFacesAgreeWithTheirNeighboursAgain) {
  const TriMesh sphere = subdivide(shapes::icosahedron(), 2, Scheme::Loop);
  TriMesh m = sphere;
  int reversed = 0;
  for (Eigen::Index f = 0; f < m.F.rows(); f += 7, ++reversed) std::swap(m.F(f, 1), m.F(f, 2));
  EXPECT_THROW(validate(m, "mixed"), Error);
  EXPECT_EQ(orientConsistently(m), reversed);
  EXPECT_EQ(m.F, sphere.F);  // most faces kept theirs, so the sphere's outward winding
  EXPECT_EQ(orientConsistently(m), 0);
  // Most faces reversed: the component takes their winding.
  TriMesh inverted = sphere;
  for (Eigen::Index f = 0; f < inverted.F.rows(); ++f)
    if (f % 7 != 0) std::swap(inverted.F(f, 1), inverted.F(f, 2));
  orientConsistently(inverted);
  EXPECT_NO_THROW(validate(inverted, "inverted"));
  for (Eigen::Index f = 0; f < inverted.F.rows(); ++f)
    EXPECT_EQ(inverted.F.row(f),
              Eigen::RowVector3i(sphere.F(f, 0), sphere.F(f, 2), sphere.F(f, 1)));
}

TEST(OrientConsistently, AMoebiusStripIsLeftAsItIs) {
  TriMesh m = moebiusStrip(8);
  const TriMesh before = m;
  EXPECT_EQ(orientConsistently(m), 0);
  EXPECT_EQ(m.F, before.F);
  EXPECT_THROW(validate(m, "Moebius strip"), Error);
}

TEST(RepeatedCorners, FacesNamingAVertexTwiceGoAndTheRestStay) {
  TriMesh m = cornerTetrahedron();
  const Faces faces = m.F;
  m.F.conservativeResize(7, 3);
  m.F.row(4) << 1, 1, 2;  // a segment
  m.F.row(5) << 3, 3, 3;  // a point
  m.F.row(6) << 0, 9, 9;  // out of range: kept for validate() to name
  EXPECT_EQ(removeFacesWithRepeatedCorners(m), 2);
  ASSERT_EQ(m.F.rows(), 5);
  EXPECT_EQ(m.F.topRows(4), faces);
  EXPECT_EQ(m.F.row(4), Eigen::RowVector3i(0, 9, 9));
  m.F.conservativeResize(4, 3);
  EXPECT_EQ(removeFacesWithRepeatedCorners(m), 0);
  EXPECT_NO_THROW(validate(m, "tetrahedron"));
}

TEST(SmallComponents, DebrisGoesAndTheSurfaceStays) {
  // A sphere with three loose triangles beside it.
  const TriMesh sphere = subdivide(shapes::icosahedron(), 1, Scheme::Loop);
  TriMesh m = sphere;
  const int n = static_cast<int>(m.V.rows()), faces = static_cast<int>(m.F.rows());
  m.V.conservativeResize(n + 9, 3);
  m.F.conservativeResize(faces + 3, 3);
  for (int t = 0; t < 3; ++t) {
    for (int c = 0; c < 3; ++c) m.V.row(n + 3 * t + c) << 5 + t, c == 1, c == 2;
    m.F.row(faces + t) << n + 3 * t, n + 3 * t + 1, n + 3 * t + 2;
  }
  const std::vector<int> component = componentOfFaces(m.F, static_cast<int>(m.V.rows()));
  EXPECT_EQ(component.front(), 0);
  EXPECT_EQ(component.back(), 3);
  EXPECT_EQ(removeSmallComponents(m, 1), 0);  // nothing is smaller than one face
  EXPECT_EQ(removeSmallComponents(m, 4), 3);
  EXPECT_EQ(m.V, sphere.V);
  EXPECT_EQ(m.F, sphere.F);
}
