// The distortion measure of the simplification (distortion.h): closed forms.
#include <gtest/gtest.h>

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "osdmra/remesh/distortion.h"

using namespace osdmra::remeshing;

TEST(Distortion, LayFlatKeepsLengths) {
  const Vec3 a(1, 2, 3), b(2, 4, 1), c(-1, 0, 5);
  const auto p = layFlat(a, b, c);
  EXPECT_NEAR((p[1] - p[0]).norm(), (b - a).norm(), 1e-12);
  EXPECT_NEAR((p[2] - p[0]).norm(), (c - a).norm(), 1e-12);
  EXPECT_NEAR((p[2] - p[1]).norm(), (c - b).norm(), 1e-12);
  EXPECT_GT(cross2(p[1] - p[0], p[2] - p[0]), 0);
}

TEST(Distortion, SimilaritiesHaveNoAnisotropy) {
  const std::array<Vec3, 3> t{Vec3(0, 0, 1), Vec3(1, 0.2, 1), Vec3(0.3, 0.9, 1.5)};
  const auto flat = layFlat(t[0], t[1], t[2]);
  const double angle = 0.7, scale = 3.5;
  std::array<Vec2, 3> image;
  for (int i = 0; i < 3; ++i)
    image[i] = scale * Vec2(std::cos(angle) * flat[i].x() - std::sin(angle) * flat[i].y(),
                            std::sin(angle) * flat[i].x() + std::cos(angle) * flat[i].y()) +
               Vec2(4, -2);
  EXPECT_NEAR(anisotropy(t, image), 1.0, 1e-12);
}

TEST(Distortion, AStretchIsItsRatio) {
  // The unit right triangle stretched by 3 along x and 0.5 along y: anisotropy 6.
  const std::array<Vec3, 3> t{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  EXPECT_NEAR(anisotropy(t, {Vec2(0, 0), Vec2(3, 0), Vec2(0, 0.5)}), 6.0, 1e-12);
  // A shear x += 2y: singular values of [[1,2],[0,1]] are sqrt(2) +- 1.
  EXPECT_NEAR(anisotropy(t, {Vec2(0, 0), Vec2(1, 0), Vec2(2, 1)}),
              (std::sqrt(2.0) + 1) / (std::sqrt(2.0) - 1), 1e-9);
}

TEST(Distortion, AFoldOrADegenerateImageIsInfinite) {
  const std::array<Vec3, 3> t{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(anisotropy(t, {Vec2(0, 0), Vec2(0, 1), Vec2(1, 0)}), inf);  // turned over
  EXPECT_EQ(anisotropy(t, {Vec2(0, 0), Vec2(1, 1), Vec2(2, 2)}), inf);  // flat
  const std::array<Vec3, 3> sliver{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0)};
  EXPECT_EQ(anisotropy(sliver, {Vec2(0, 0), Vec2(1, 0), Vec2(0, 1)}), inf);
}

// Two triangles of a folded square hinged flat: the square comes back, with its
// lengths, whatever the fold's angle.
TEST(Distortion, HingeUnfoldsAFoldedSquare) {
  for (const double fold : {0.0, 1.0, 2.5}) {
    SCOPED_TRACE(fold);
    osdmra::Points V(4, 3);
    V << 0, 0, 0, 1, 0, 0, 1, std::cos(fold), std::sin(fold), 0, 1, 0;
    // Faces (0, 1, 3) and (1, 2, 3) share the edge 1-3 and are counter-clockwise.
    const Laid first{{0, 1, 3}, layFlat(Vec3(V.row(0)), Vec3(V.row(1)), Vec3(V.row(3)))};
    Laid second;
    ASSERT_TRUE(hinge(V, first, {1, 2, 3}, second));
    EXPECT_EQ(second.pos[0], first.pos[1]);
    EXPECT_EQ(second.pos[2], first.pos[2]);
    EXPECT_NEAR((second.pos[1] - second.pos[0]).norm(), (V.row(2) - V.row(1)).norm(), 1e-12);
    EXPECT_NEAR((second.pos[1] - second.pos[2]).norm(), (V.row(2) - V.row(3)).norm(), 1e-12);
    EXPECT_GT(cross2(second.pos[1] - second.pos[0], second.pos[2] - second.pos[0]), 0);
    EXPECT_FALSE(hinge(V, first, {0, 1, 3}, second));  // the same face: no edge between
  }
}

// A chart over the unit square folded about its diagonal 1-3: corners inside one face,
// inside the two faces about the fold, and a vertex corner, land where the unfolded
// square puts them (laid from the first face), whatever the fold; a corner beyond the
// two faces brings its own face through facesAround, hinged with its lengths kept.
TEST(Distortion, ChartImageUnfoldsTheFacesHoldingTheCorners) {
  for (const double fold : {0.0, 1.0, 2.5}) {
    SCOPED_TRACE(fold);
    osdmra::Points V(5, 3);
    // Corner 2, (1, 1, 0) unfolded, turned by `fold` about the diagonal from 1 to 3.
    const double h = 0.5 * (1 + std::cos(fold));
    V << 0, 0, 0, 1, 0, 0, h, h, -std::sin(fold) / std::sqrt(2.0), 0, 1, 0, 2, 0, 0;
    const std::array<int, 3> a{0, 1, 3}, b{1, 2, 3}, c{1, 4, 2};
    const FacesAround around = [&](int w, std::vector<std::array<int, 3>>& out) {
      for (const auto& f : {a, b, c})
        if (std::count(f.begin(), f.end(), w) == 1) out.push_back(f);
    };
    // Unfolded, the square is [0,1]^2 laid from face a: 0 at the origin, 1 on +x, 3 on +y.
    auto unfolded = [&](int v) -> Vec2 { return v == 2 ? Vec2(1, 1) : Vec2(V(v, 0), V(v, 1)); };
    const std::array<double, 3> third{1 / 3.0, 1 / 3.0, 1 / 3.0};
    auto centre = [&](const std::array<int, 3>& f) -> Vec2 {
      return (unfolded(f[0]) + unfolded(f[1]) + unfolded(f[2])) / 3;
    };
    std::array<Vec2, 3> image;
    // All in face a; then a's centre, b's centre and vertex 0.
    ASSERT_TRUE(chartImage(V,
                           {Placed{false, -1, a, {1, 0, 0}}, Placed{false, -1, a, {0, 1, 0}},
                            Placed{false, -1, a, third}},
                           around, image));
    EXPECT_NEAR((image[0] - Vec2(0, 0)).norm(), 0, 1e-12);
    EXPECT_NEAR((image[1] - Vec2(1, 0)).norm(), 0, 1e-12);
    EXPECT_NEAR((image[2] - centre(a)).norm(), 0, 1e-12);
    ASSERT_TRUE(chartImage(
        V, {Placed{false, -1, a, third}, Placed{false, -1, b, third}, Placed{true, 0, {}, {}}},
        around, image));
    EXPECT_NEAR((image[0] - centre(a)).norm(), 0, 1e-12);
    EXPECT_NEAR((image[1] - centre(b)).norm(), 0, 1e-12);
    EXPECT_NEAR(image[2].norm(), 0, 1e-12);
    // Vertex 4 is in neither a nor b: its face c comes from facesAround, hinged to b.
    // Laid from a, b's corner 2 is at (1, 1); c is b's neighbour about edge 1-2, and
    // folds with b, so vertex 4 lands at distance 1 from 1 and sqrt(2) from 2.
    ASSERT_TRUE(chartImage(
        V, {Placed{false, -1, a, third}, Placed{false, -1, b, third}, Placed{true, 4, {}, {}}},
        around, image));
    EXPECT_NEAR((image[1] - centre(b)).norm(), 0, 1e-12);
    EXPECT_NEAR((image[2] - Vec2(1, 0)).norm(), (V.row(4) - V.row(1)).norm(), 1e-12);
    EXPECT_NEAR((image[2] - Vec2(1, 1)).norm(), (V.row(4) - V.row(2)).norm(), 1e-12);
  }
}

// A flat hexagonal fan laid breadth first from one face: every face joins, each at its
// true place (the fan is flat, so its chart is the plane itself). Laid with vertex ids
// that collide modulo 64 (the filter ruling out faces that share no edge works on
// ids mod 64, and must leave such faces to hinge()), the chart is the same.
TEST(Distortion, LayBreadthFirstLaysAFlatFanWhateverItsVertexIds) {
  osdmra::Points V(7, 3);
  V.row(0) << 0, 0, 0;
  for (int k = 0; k < 6; ++k) V.row(k + 1) << std::cos(k * kPi / 3), std::sin(k * kPi / 3), 0;
  std::vector<std::array<int, 3>> fan;
  for (int k = 0; k < 6; ++k) fan.push_back({0, k + 1, (k + 1) % 6 + 1});
  for (const int stride : {1, 64}) {
    SCOPED_TRACE(stride);
    // Vertex i becomes i * stride: with 64, all seven share one bit.
    osdmra::Points W = osdmra::Points::Zero(6 * stride + 1, 3);
    std::vector<std::array<int, 3>> faces;
    for (int q : {3, 0, 5, 1, 4, 2}) {  // shuffled: the first face is not next to the second
      const auto& f = fan[q];
      faces.push_back({f[0] * stride, f[1] * stride, f[2] * stride});
    }
    for (int i = 0; i < 7; ++i) W.row(i * stride) = V.row(i);
    std::vector<std::size_t> index;
    const std::vector<Laid> laid = layBreadthFirst(W, faces, faces.size(), index);
    ASSERT_EQ(laid.size(), faces.size());
    // The chart is an isometry of the plane: every laid edge keeps its length, and the
    // centre lies at the same place in every face.
    Vec2 centre;
    ASSERT_TRUE(vertexIn(laid, 0, centre));
    for (const Laid& l : laid) {
      EXPECT_GT(cross2(l.pos[1] - l.pos[0], l.pos[2] - l.pos[0]), 0);
      for (int i = 0; i < 3; ++i) {
        const int a = l.face[i], b = l.face[(i + 1) % 3];
        EXPECT_NEAR((l.pos[(i + 1) % 3] - l.pos[i]).norm(), (W.row(a) - W.row(b)).norm(), 1e-12);
        if (a == 0) {
          EXPECT_NEAR((l.pos[i] - centre).norm(), 0, 1e-12);
        }
      }
    }
  }
}

// Measuring a triangle laid flat once gives what measuring it in 3D gives.
TEST(Distortion, AnisotropyFromAFlatTriangleIsTheSame) {
  const std::array<Vec3, 3> t{Vec3(0, 0, 1), Vec3(1, 0.2, 1), Vec3(0.3, 0.9, 1.5)};
  const std::array<Vec2, 3> image{Vec2(0, 0), Vec2(2, 0.1), Vec2(0.4, 0.7)};
  EXPECT_EQ(anisotropyFromFlat(layFlat(t[0], t[1], t[2]), image), anisotropy(t, image));
  EXPECT_GT(anisotropy(t, image), 1);
}

// anisotropySum is k + 1/k for the ratio k of the singular values of the affine map
// between the triangles (computed here by an SVD), and anisotropyFromSum gives k back,
// on maps from nearly conformal to stretched 10^4 times; orientation reversed: infinite.
TEST(Distortion, AnisotropySumIsTheSingularValueRatioPlusItsInverse) {
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> coordinate(-1, 1);
  int checked = 0;
  for (int trial = 0; trial < 200; ++trial) {
    std::array<Vec2, 3> from, to;
    for (auto* t : {&from, &to})
      for (Vec2& p : *t) p = Vec2(coordinate(random), coordinate(random));
    const double stretch = std::pow(10.0, 4.0 * trial / 200);  // up to 10^4 along x
    for (Vec2& p : to) p.x() *= stretch;
    auto edges = [](const std::array<Vec2, 3>& t) {
      Eigen::Matrix2d m;
      m << t[1] - t[0], t[2] - t[0];
      return m;
    };
    // Both counter-clockwise (a random map between random triangles either way).
    if (edges(from).determinant() < 0) std::swap(from[1], from[2]);
    if (edges(to).determinant() < 0) std::swap(to[1], to[2]);
    const Eigen::Matrix2d S = edges(from), T = edges(to);
    if (S.determinant() < 1e-3 || T.determinant() < 1e-3 * stretch) continue;
    const Eigen::JacobiSVD<Eigen::Matrix2d> svd(T * S.inverse());
    const double k = svd.singularValues()[0] / svd.singularValues()[1];
    EXPECT_NEAR(anisotropySum(from, to), k + 1 / k, 1e-9 * (k + 1 / k)) << "trial " << trial;
    EXPECT_NEAR(anisotropyFromSum(anisotropySum(from, to)), k, 1e-9 * k) << "trial " << trial;
    EXPECT_NEAR(anisotropyFromFlat(from, to), k, 1e-9 * k) << "trial " << trial;
    std::swap(to[1], to[2]);  // the image turned over
    EXPECT_EQ(anisotropySum(from, to), std::numeric_limits<double>::infinity());
    ++checked;
  }
  EXPECT_GT(checked, 50);
}
