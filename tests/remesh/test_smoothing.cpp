// The parameterisation's charts and smoothing (charts.h, smoothing.h): every input
// triangle keeps a positively oriented place in every chart that sees it, the smoothing
// lowers the distortion, and vertices that must stay (base vertices, the boundary,
// feature lines) stay.
#include <gtest/gtest.h>

#include <cmath>

#include "osdmra/remesh/charts.h"
#include "osdmra/remesh/distortion.h"
#include "osdmra/remesh/features.h"
#include "osdmra/remesh/simplify.h"
#include "osdmra/remesh/smoothing.h"
#include "osdmra/subdivision/shapes.h"
#include "support.h"

using namespace osdmra;
using namespace osdmra::remeshing;
using namespace osdmra::test;

namespace {

struct Parameterised {
  TriMesh input;
  Features features;
  Simplification s;
};

Parameterised simplified(const TriMesh& input, int baseFaces) {
  Parameterised p{input, detectFeatures(input, 70.0), {}};
  p.s = simplify(p.input, p.features, baseFaces);
  return p;
}

// Every input triangle's anisotropy between its corners' places, in the chart of each
// base face that holds one of its corners and reaches the others.
struct Distortion {
  int folds = 0;     // images oriented clockwise or degenerate
  double worst = 1;  // over the others
  double mean = 0;
};

Distortion distortionOf(const Parameterised& p, const BaseCharts& charts) {
  Distortion d;
  int count = 0;
  for (Eigen::Index t = 0; t < p.input.F.rows(); ++t)
    for (int k = 0; k < 3; ++k) {
      const int x = p.input.F(t, k);
      if (p.s.baseOf[x] >= 0) continue;
      std::array<Vec2, 3> image;
      std::array<Vec3, 3> corners;
      bool charted = true;
      for (int c = 0; c < 3; ++c) {
        corners[c] = p.input.V.row(p.input.F(t, c)).transpose();
        charted =
            charted && placeInputVertex(charts, p.s, p.s.params[x].face, p.input.F(t, c), image[c]);
      }
      if (!charted) continue;
      const double a = anisotropy(corners, image);
      if (!(a < INFINITY)) {
        ++d.folds;
        continue;
      }
      d.worst = std::max(d.worst, a);
      d.mean += a;
      ++count;
    }
  d.mean /= count;
  return d;
}

// The parameterisation's stretch (smoothing.h): over the input triangles charted in the
// chart of their first free corner's face, surface area times the squared Frobenius
// norm of the map from the chart to the surface; and how far, at most, the input
// vertices' places lie from `reference` (in their faces' charts).
double stretchOf(const Parameterised& p, const BaseCharts& charts) {
  double total = 0;
  for (Eigen::Index t = 0; t < p.input.F.rows(); ++t) {
    int face = -1;
    for (int k = 0; k < 3 && face < 0; ++k)
      if (p.s.baseOf[p.input.F(t, k)] < 0) face = p.s.params[p.input.F(t, k)].face;
    if (face < 0) continue;
    std::array<Vec2, 3> image;
    bool charted = true;
    for (int c = 0; c < 3; ++c)
      charted = charted && placeInputVertex(charts, p.s, face, p.input.F(t, c), image[c]);
    if (!charted) continue;
    Eigen::Matrix2d q;
    q << image[1] - image[0], image[2] - image[0];
    Eigen::Matrix<double, 3, 2> e;
    e.col(0) = (p.input.V.row(p.input.F(t, 1)) - p.input.V.row(p.input.F(t, 0))).transpose();
    e.col(1) = (p.input.V.row(p.input.F(t, 2)) - p.input.V.row(p.input.F(t, 0))).transpose();
    total += 0.5 * e.col(0).cross(e.col(1)).norm() * (e * q.inverse()).squaredNorm();
  }
  return total;
}

double farthestFrom(const Parameterised& p, const BaseCharts& charts,
                    const std::vector<Param>& reference) {
  double farthest = 0;
  for (Eigen::Index x = 0; x < p.input.V.rows(); ++x) {
    if (p.s.baseOf[x] >= 0) continue;
    Vec2 now, then;
    if (!charts.place(reference[x].face, p.s.params[x], now) ||
        !charts.place(reference[x].face, reference[x], then))
      continue;
    farthest = std::max(farthest, (now - then).norm());
  }
  return farthest;
}

}  // namespace

// A point of a face's chart located is that point: place and locate are inverse.
TEST(Charts, LocateUndoesPlace) {
  const TriMesh base = subdivide(shapes::icosahedron(), 1, Scheme::Loop);
  const BaseCharts charts(base);
  for (int f = 0; f < static_cast<int>(base.F.rows()); f += 7)
    for (const Param p : {Param{f, {0.2, 0.3, 0.5}}, Param{(f + 1) % 80, {0.6, 0.3, 0.1}}}) {
      Vec2 at;
      if (!charts.place(f, p, at)) continue;
      Param back;
      ASSERT_TRUE(charts.locate(f, at, back));
      Vec2 again;
      ASSERT_TRUE(charts.place(f, back, again));
      EXPECT_LT((again - at).norm(), 1e-12);
    }
  // A face's own chart is the face laid flat, with its lengths.
  const Laid& own = charts.own(3);
  EXPECT_NEAR((own.pos[1] - own.pos[0]).norm(),
              (base.V.row(base.F(3, 1)) - base.V.row(base.F(3, 0))).norm(), 1e-12);
}

// On a curved closed surface and on a squeezed flat square: the smoothing folds no
// input triangle in a chart that sees it, lowers the mean distortion and keeps the
// largest within the bound (on the square, whose parameterisation is the plane's
// identity, there is none and stays none), and base, boundary and feature vertices
// have not moved.
TEST(Smoothing, LowersTheDistortionWithoutAFold) {
  std::vector<TriMesh> inputs = {subdivide(shapes::torus(), 3, Scheme::Loop, 0.01, 5)};
  {
    // The unit square, squeezed towards x = 0: a planar input meshed unevenly.
    TriMesh square = subdivide(unitSquare(), 5, Scheme::Linear);
    for (Eigen::Index v = 0; v < square.V.rows(); ++v)
      square.V(v, 0) = (std::exp(3 * square.V(v, 0)) - 1) / (std::exp(3.0) - 1);
    inputs.push_back(square);
  }
  for (const TriMesh& input : inputs) {
    Parameterised p = simplified(input, 24);
    const BaseCharts charts(p.s.base);
    const Distortion before = distortionOf(p, charts);
    const std::vector<Param> placesBefore = p.s.params;
    const Connectivity conn(input.F, static_cast<int>(input.V.rows()));
    std::vector<char> pinned(input.V.rows(), 0);
    for (const auto& [a, b] : p.features.list) pinned[a] = pinned[b] = 1;
    SmoothingOptions options;
    options.anisotropy = kStages[p.s.stage].anisotropy;
    const SmoothingReport report = smoothParameters(input, conn, charts, pinned, p.s, options);
    const Distortion after = distortionOf(p, charts);
    EXPECT_LE(after.folds, before.folds);
    EXPECT_LE(after.worst, std::max(before.worst, options.anisotropy));
    if (before.worst < 1 + 1e-6) {  // the plane: its affine map is the least stretched
      EXPECT_EQ(before.folds, 0);
      EXPECT_LT(after.worst, 1 + 1e-6);
    } else {
      EXPECT_GT(report.moves, 0);
      EXPECT_LT(after.mean, before.mean);
    }
    for (Eigen::Index x = 0; x < input.V.rows(); ++x)
      if (p.s.baseOf[x] >= 0 || pinned[x] || conn.isBoundaryVertex(static_cast<int>(x))) {
        EXPECT_EQ(p.s.params[x].face, placesBefore[x].face) << "vertex " << x;
        EXPECT_EQ(p.s.params[x].bary, placesBefore[x].bary) << "vertex " << x;
      }
  }
}

// A flat square parameterised over its base, then its places warped inside each base
// face (b + b0 b1 b2 (2, -1, -1): continuous, as it vanishes on the base's edges, and
// folding nothing): the smoothing lowers the stretch it added and brings the places
// back towards the affine map a flat input has, which is the stretch's minimum.
TEST(Smoothing, UndoesAWarpOfAFlatParameterisation) {
  Parameterised p = simplified(subdivide(unitSquare(), 4, Scheme::Linear), 16);
  const BaseCharts charts(p.s.base);
  const std::vector<Param> flat = p.s.params;
  const double stretchFlat = stretchOf(p, charts);
  for (Eigen::Index x = 0; x < p.input.V.rows(); ++x) {
    if (p.s.baseOf[x] >= 0) continue;
    auto& b = p.s.params[x].bary;
    const double w = b[0] * b[1] * b[2];
    b = {b[0] + 2 * w, b[1] - w, b[2] - w};
  }
  const double warpedBy = farthestFrom(p, charts, flat);
  const double stretchWarped = stretchOf(p, charts);
  ASSERT_GT(warpedBy, 0.005);
  ASSERT_EQ(distortionOf(p, charts).folds, 0);
  ASSERT_GT(stretchWarped, stretchFlat * (1 + 1e-3));
  const Connectivity conn(p.input.F, static_cast<int>(p.input.V.rows()));
  std::vector<char> pinned(p.input.V.rows(), 0);
  SmoothingOptions options;
  options.sweeps = 20;
  const SmoothingReport report = smoothParameters(p.input, conn, charts, pinned, p.s, options);
  EXPECT_GT(report.moves, 0);
  // 20 sweeps took the stretch the warp added from 0.234 to 0.009, the farthest place
  // from 0.051 to 0.027 of the square's side.
  EXPECT_LT(stretchOf(p, charts) - stretchFlat, 0.1 * (stretchWarped - stretchFlat));
  EXPECT_LT(farthestFrom(p, charts, flat), 0.6 * warpedBy);
  EXPECT_EQ(distortionOf(p, charts).folds, 0);
}
