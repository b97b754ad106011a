// Normals (normals.h) against closed forms: a flat mesh has the plane's normal
// everywhere, a face normal is twice the area along the unit normal, area-weighted
// sums point out of a closed convex mesh and cancel over a closed surface, and unit
// normals are unit or, where nothing stands behind them, zero.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <random>

#include "osdmra/geometry/normals.h"
#include "osdmra/mesh/connectivity.h"
#include "osdmra/subdivision/shapes.h"
#include "support.h"

using namespace osdmra;
using namespace osdmra::test;

namespace {

// Heron's formula: the area from the side lengths alone, independent of any cross
// product (stable form, sides sorted a >= b >= c).
double heronArea(const Eigen::Vector3d& p, const Eigen::Vector3d& q, const Eigen::Vector3d& r) {
  double s[3] = {(q - p).norm(), (r - q).norm(), (p - r).norm()};
  std::sort(s, s + 3, [](double x, double y) { return x > y; });
  const double a = s[0], b = s[1], c = s[2];
  return 0.25 *
         std::sqrt(std::max(0.0, (a + (b + c)) * (c - (a - b)) * (c + (a - b)) * (a + (b - c))));
}

Eigen::Vector3d corner(const TriMesh& m, Eigen::Index f, int k) {
  return m.V.row(m.F(f, k)).transpose();
}

}  // namespace

TEST(Normals, FlatMeshesFaceTheirPlane) {
  // The unit square, and a 4 x 4 disc flattened onto z = 0 and refined: every face
  // and vertex normal is exactly (0, 0, 1), the faces being counter-clockwise from +z.
  TriMesh disc = shapes::disc(4);
  disc.V.col(2).setZero();
  for (const TriMesh& m : {unitSquare(), subdivide(disc, 2, Scheme::Linear)}) {
    for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
      const Eigen::Vector3d n = faceNormal(m, f);
      EXPECT_EQ(n.x(), 0.0);
      EXPECT_EQ(n.y(), 0.0);
      EXPECT_GT(n.z(), 0.0);
    }
    const Points N = vertexNormals(m);
    ASSERT_EQ(N.rows(), m.V.rows());
    for (Eigen::Index v = 0; v < N.rows(); ++v)
      EXPECT_EQ(N.row(v), Eigen::RowVector3d(0, 0, 1)) << "vertex " << v;
  }
  // Each half of the unit square has area 1/2: its face normal is (0, 0, 1).
  const TriMesh square = unitSquare(0.25);
  EXPECT_EQ(faceNormal(square, 0), Eigen::Vector3d(0, 0, 1));
  EXPECT_EQ(faceNormal(square, 1), Eigen::Vector3d(0, 0, 1));
}

TEST(Normals, FaceNormalIsTwiceTheAreaAlongTheRightHandedNormal) {
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  TriMesh m;
  m.V.resize(300, 3);
  m.F.resize(100, 3);
  for (Eigen::Index i = 0; i < m.V.rows(); ++i) m.V.row(i) << u(rng), u(rng), u(rng);
  for (Eigen::Index f = 0; f < m.F.rows(); ++f) m.F.row(f) << 3 * f, 3 * f + 1, 3 * f + 2;
  for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
    const Eigen::Vector3d a = corner(m, f, 0), b = corner(m, f, 1), c = corner(m, f, 2);
    const Eigen::Vector3d n = faceNormal(m, f);
    const double area = heronArea(a, b, c);
    EXPECT_NEAR(n.norm(), 2 * area, 1e-12 * (1 + area)) << "face " << f;
    // Perpendicular to the face, and (a, b, c) counter-clockwise seen from its tip.
    EXPECT_NEAR(n.dot(b - a), 0.0, 1e-12 * n.norm() * (b - a).norm());
    EXPECT_NEAR(n.dot(c - a), 0.0, 1e-12 * n.norm() * (c - a).norm());
    Eigen::Matrix3d frame;
    frame << b - a, c - a, n;
    EXPECT_GT(frame.determinant(), 0.0) << "face " << f;
  }
  // A degenerate face has a zero normal.
  const TriMesh line = makeMesh({{0, 0, 0}, {1, 1, 1}, {3, 3, 3}}, {{0, 1, 2}});
  EXPECT_EQ(faceNormal(line, 0), Eigen::Vector3d::Zero());
}

TEST(Normals, SumsAreTheFaceNormalsAroundEachVertex) {
  for (const char* name : {"disc", "valences", "torus"}) {
    SCOPED_TRACE(name);
    const TriMesh m = subdivide(shapes::byName(name), 1, Scheme::Loop, 0.1, 3);
    const Connectivity c(m.F, static_cast<int>(m.V.rows()));
    const Points sums = vertexNormalSums(m);
    ASSERT_EQ(sums.rows(), m.V.rows());
    for (int v = 0; v < c.numVertices(); ++v) {
      Eigen::Vector3d expected = Eigen::Vector3d::Zero();
      for (int h : c.fan(v)) expected += faceNormal(m, h / 3);
      EXPECT_LT((sums.row(v).transpose() - expected).norm(), 1e-14 * (1 + expected.norm()));
    }
    // Over a closed surface the area vectors cancel (the divergence theorem).
    if (c.numBoundaryLoops() == 0) {
      double scale = 0;
      for (Eigen::Index f = 0; f < m.F.rows(); ++f) scale += faceNormal(m, f).norm();
      EXPECT_LT(sums.colwise().sum().norm(), 1e-13 * scale);
    }
  }
}

TEST(Normals, SumsPointOutOfAClosedConvexMesh) {
  for (const TriMesh& base : {shapes::tetrahedron(), shapes::octahedron(), shapes::icosahedron(),
                              cornerTetrahedron(), unitCube()}) {
    // Refined linearly the mesh stays convex (flat pieces), with many vertices on faces
    // and edges of the polyhedron.
    const TriMesh m = subdivide(base, 2, Scheme::Linear);
    const Eigen::RowVector3d centre = base.V.colwise().mean();
    const Points sums = vertexNormalSums(m);
    for (Eigen::Index v = 0; v < m.V.rows(); ++v)
      EXPECT_GT(sums.row(v).dot(m.V.row(v) - centre), 0.0) << "vertex " << v;
  }
}

TEST(Normals, UnitOrZeroAndScaleFree) {
  // A vertex in no face and the corners of a degenerate face have nothing behind
  // their normal: zero, not NaN.
  TriMesh m = subdivide(shapes::icosahedron(), 1, Scheme::Loop, 0.05, 9);
  const Eigen::Index n = m.V.rows();
  m.V.conservativeResize(n + 4, 3);
  m.V.row(n) << 5, 5, 5;
  m.V.row(n + 1) << 7, 0, 0;
  m.V.row(n + 2) << 8, 0, 0;
  m.V.row(n + 3) << 9, 0, 0;
  m.F.conservativeResize(m.F.rows() + 1, 3);
  m.F.row(m.F.rows() - 1) << n + 1, n + 2, n + 3;
  const Points N = vertexNormals(m);
  ASSERT_EQ(N.rows(), m.V.rows());
  for (Eigen::Index v = 0; v < n; ++v) EXPECT_NEAR(N.row(v).norm(), 1.0, 1e-15) << v;
  for (Eigen::Index v = n; v < n + 4; ++v) EXPECT_EQ(N.row(v), Eigen::RowVector3d::Zero()) << v;
  // Scaling the mesh by s scales the sums by s^2 and leaves the unit normals.
  TriMesh scaled = m;
  scaled.V *= 4.0;
  EXPECT_LT((vertexNormalSums(scaled) - 16.0 * vertexNormalSums(m)).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((vertexNormals(scaled) - N).cwiseAbs().maxCoeff(), 1e-15);
  // The unit normals are the sums' directions.
  const Points sums = vertexNormalSums(m);
  for (Eigen::Index v = 0; v < n; ++v)
    EXPECT_LT((N.row(v) * sums.row(v).norm() - sums.row(v)).norm(), 1e-14 * sums.row(v).norm());
}

TEST(Normals, FaceAnglesSumToPiAndToTheConeAngle) {
  // Every face's three angles sum to pi (a flat triangle's closed form); around a
  // vertex they sum to its cone angle (four equilateral faces around each vertex of the
  // octahedron: 4 pi / 3), and the defects of a closed surface of genus 0 sum to 4 pi
  // (Descartes).
  const TriMesh m = shapes::octahedron();
  std::vector<double> cone(static_cast<std::size_t>(m.V.rows()), 0.0);
  for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
    double sum = 0;
    for (int i = 0; i < 3; ++i) {
      const double a = faceAngle(m, f, i);
      EXPECT_GT(a, 0.0);
      sum += a;
      cone[static_cast<std::size_t>(m.F(f, i))] += a;
    }
    EXPECT_NEAR(sum, M_PI, 1e-14) << "face " << f;
  }
  double defects = 0;
  for (double c : cone) {
    EXPECT_NEAR(c, 4 * M_PI / 3, 1e-13);
    defects += 2 * M_PI - c;
  }
  EXPECT_NEAR(defects, 4 * M_PI, 1e-12);
  // A right angle, and the two acute angles of a right isosceles triangle, exactly
  // where the sides are; and a needle's tiny angle to full relative precision
  // (acos of the normalised dot product loses half the digits there).
  TriMesh t;
  t.V.resize(3, 3);
  t.V << 0, 0, 0, 1, 0, 0, 0, 1, 0;
  t.F.resize(1, 3);
  t.F << 0, 1, 2;
  EXPECT_DOUBLE_EQ(faceAngle(t, 0, 0), M_PI / 2);
  EXPECT_DOUBLE_EQ(faceAngle(t, 0, 1), M_PI / 4);
  EXPECT_DOUBLE_EQ(faceAngle(t, 0, 2), M_PI / 4);
  t.V.row(2) << 1, 1e-9, 0;
  EXPECT_NEAR(faceAngle(t, 0, 0), 1e-9, 1e-24);
}
