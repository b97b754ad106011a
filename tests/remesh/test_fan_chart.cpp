// A triangle laid about a base vertex (fan_chart.h): one shape from the chart of every
// face around the vertex, a cone's or a saddle's, where the breadth-first charts cut the
// vertex's faces apart at a place that depends on the face.
#include <gtest/gtest.h>

#include <cmath>

#include "osdmra/remesh/charts.h"
#include "osdmra/remesh/fan_chart.h"

using namespace osdmra;
using namespace osdmra::remeshing;

namespace {

// Five faces (0, i, i + 1) around vertex 0 at height h over a ring of five vertices,
// the ring's vertices at heights `ring` in turn (a cone for h > 0 and a flat ring, a
// saddle for a ring going up and down), and one face (2, 1, 6) hanging off the ring,
// not around vertex 0.
TriMesh fanOfFive(double h, double ring) {
  TriMesh m;
  m.V.resize(7, 3);
  m.V.row(0) << 0, 0, h;
  for (int i = 0; i < 5; ++i) {
    const double a = 2 * kPi * i / 5;
    m.V.row(1 + i) << std::cos(a), std::sin(a), i % 2 == 0 ? ring : -ring;
  }
  m.V.row(6) << 1.2, -0.6, 0;
  m.F.resize(6, 3);
  for (int i = 0; i < 5; ++i) m.F.row(i) << 0, 1 + i, 1 + (i + 1) % 5;
  m.F.row(5) << 2, 1, 6;
  return m;
}

double angleSumAt0(const TriMesh& m) {
  double sum = 0;
  for (int i = 0; i < 5; ++i)
    sum += angleBetween(m.V.row(m.F(i, 1)) - m.V.row(0), m.V.row(m.F(i, 2)) - m.V.row(0));
  return sum;
}

Laid laidFlat(const TriMesh& m, int f) {
  return {{m.F(f, 0), m.F(f, 1), m.F(f, 2)},
          layFlat(m.V.row(m.F(f, 0)).transpose(), m.V.row(m.F(f, 1)).transpose(),
                  m.V.row(m.F(f, 2)).transpose())};
}

// The triangle laid about vertex 0 (corner 0 of each of its faces) in the chart of each
// of its five faces.
std::vector<std::array<Vec2, 3>> fromEveryFace(const TriMesh& m,
                                               const std::array<BasePoint, 3>& corners) {
  const Connectivity conn(m.F, static_cast<int>(m.V.rows()));
  std::vector<std::array<Vec2, 3>> images;
  for (int f = 0; f < 5; ++f) {
    std::array<Vec2, 3> image;
    EXPECT_TRUE(layAboutCorner(m, conn, f, 0, laidFlat(m, f), corners, image)) << "face " << f;
    images.push_back(image);
  }
  return images;
}

// Two images are the same shape when their sides are (both counter-clockwise).
void expectSameShape(const std::array<Vec2, 3>& a, const std::array<Vec2, 3>& b) {
  for (int k = 0; k < 3; ++k)
    EXPECT_NEAR((a[k] - a[(k + 1) % 3]).norm(), (b[k] - b[(k + 1) % 3]).norm(), 1e-12);
  EXPECT_GT(cross2(b[1] - b[0], b[2] - b[0]), 0);
}

BasePoint at(int face, double b0, double b1, double b2) {
  return {-1, {face, {b0, b1, b2}}};
}

}  // namespace

TEST(FanChart, OneShapeFromEveryFaceAroundACone) {
  const TriMesh m = fanOfFive(1.0, 0.0);
  ASSERT_LT(angleSumAt0(m), 1.5 * kPi);  // far from flat: where the charts cut matters
  // Corners in the first, third and fourth faces around vertex 0: across the cut of the
  // charts laid from the fifth face, whose neighbours are the first and the fourth.
  const std::array<BasePoint, 3> corners = {at(0, 0.2, 0.4, 0.4), at(2, 0.3, 0.35, 0.35),
                                            at(3, 0.25, 0.5, 0.25)};
  const auto images = fromEveryFace(m, corners);
  for (const auto& image : images) expectSameShape(images[0], image);
  // The third face's breadth-first chart lays the first, second, third and fourth faces
  // one after the other without a cut between: there the two charts agree point for point.
  const BaseCharts charts(m);
  for (int k = 0; k < 3; ++k) {
    Vec2 p;
    ASSERT_TRUE(charts.place(2, corners[k].param, p));
    EXPECT_NEAR((p - images[2][k]).norm(), 0, 1e-12) << "corner " << k;
  }
}

TEST(FanChart, OneShapeAroundASaddleWithTheVertexACorner) {
  const TriMesh m = fanOfFive(0.0, 0.6);
  ASSERT_GT(angleSumAt0(m), 2.1 * kPi);
  // Vertex 0 itself, a point of the second face near the third and one of the fourth
  // near the third: counter-clockwise, under a half turn apart about vertex 0.
  const std::array<BasePoint, 3> corners = {BasePoint{0, {}}, at(1, 0.1, 0.1, 0.8),
                                            at(3, 0.2, 0.7, 0.1)};
  const auto images = fromEveryFace(m, corners);
  for (const auto& image : images) expectSameShape(images[0], image);
  // Distances from the vertex are kept: each corner lies as far from it as on the base.
  const Vec3 p1 = 0.1 * m.V.row(0) + 0.1 * m.V.row(2) + 0.8 * m.V.row(3);
  EXPECT_NEAR((images[4][1] - images[4][0]).norm(), (p1 - m.V.row(0).transpose()).norm(), 1e-12);
}

TEST(FanChart, APointOnTheLastFacesFarEdgeIsOnTheFirstFacesNearOne) {
  // Two corners on edge (0, 1), one given in the first face (0, 1, 2), the other in the
  // fifth (0, 5, 1): counting counter-clockwise from the first face's first edge, one
  // is at no turn and the other a whole turn on, yet both lie on that edge.
  const TriMesh m = fanOfFive(1.0, 0.0);
  const std::array<BasePoint, 3> corners = {at(1, 0.4, 0.3, 0.3), at(0, 0.375, 0.625, 0.0),
                                            at(4, 0.25, 0.0, 0.75)};
  const auto images = fromEveryFace(m, corners);
  for (const auto& image : images) expectSameShape(images[0], image);
  // From the first face, whose chart has both on its own edge: where that edge has them.
  const Laid first = laidFlat(m, 0);
  EXPECT_NEAR((images[0][1] - (0.375 * first.pos[0] + 0.625 * first.pos[1])).norm(), 0, 1e-12);
  EXPECT_NEAR((images[0][2] - (0.25 * first.pos[0] + 0.75 * first.pos[1])).norm(), 0, 1e-12);
}

TEST(FanChart, NeighboursLieOnTheirEdgesAndPointsOffTheFanAreRefused) {
  const TriMesh m = fanOfFive(0.5, 0.0);
  const Connectivity conn(m.F, static_cast<int>(m.V.rows()));
  // Ring vertices 2 and 4 are neighbours of vertex 0: at their distance from it.
  const std::array<BasePoint, 3> corners = {BasePoint{2, {}}, at(2, 0.3, 0.35, 0.35),
                                            BasePoint{5, {}}};
  std::array<Vec2, 3> image;
  ASSERT_TRUE(layAboutCorner(m, conn, 1, 0, laidFlat(m, 1), corners, image));
  const Vec2 apex = laidFlat(m, 1).pos[0];
  EXPECT_NEAR((image[0] - apex).norm(), (m.V.row(2) - m.V.row(0)).norm(), 1e-12);
  EXPECT_NEAR((image[2] - apex).norm(), (m.V.row(5) - m.V.row(0)).norm(), 1e-12);
  // Vertex 2 is on face 1's own first edge out of vertex 0: where face 1 has it.
  EXPECT_NEAR((image[0] - laidFlat(m, 1).pos[1]).norm(), 0, 1e-12);
  // A point of the face hanging off the ring, and vertex 6, are not around vertex 0.
  std::array<BasePoint, 3> off = corners;
  off[1] = at(5, 0.3, 0.3, 0.4);
  EXPECT_FALSE(layAboutCorner(m, conn, 1, 0, laidFlat(m, 1), off, image));
  off[1] = BasePoint{6, {}};
  EXPECT_FALSE(layAboutCorner(m, conn, 1, 0, laidFlat(m, 1), off, image));
}
