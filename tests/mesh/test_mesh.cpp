// validate() and boundingBoxDiagonal(): every defect is rejected with a message
// that names the source and the offending element.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "osdmra/base/error.h"
#include "osdmra/mesh/mesh.h"
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
