// The resampling (resample.h): every grid point lies on the input where the
// parameterisation puts it, grid points on shared base edges are shared, and sampling a
// distorted but bijective parameterisation comes out without a fold.
#include <gtest/gtest.h>

#include <cmath>

#include "osdmra/geometry/normals.h"
#include "osdmra/geometry/self_intersection.h"
#include "osdmra/remesh/base_flips.h"
#include "osdmra/remesh/features.h"
#include "osdmra/remesh/resample.h"
#include "osdmra/remesh/simplify.h"
#include "osdmra/subdivision/shapes.h"
#include "support.h"

using namespace osdmra;
using namespace osdmra::remeshing;
using namespace osdmra::test;

namespace {

// An n x n grid of the unit square, each cell cut along a diagonal, its vertices moved
// by `warp` (a bijection of the square onto a region of the plane z = 0).
template <class Warp>
TriMesh warpedSquare(int n, Warp warp) {
  TriMesh m;
  m.V.resize((n + 1) * (n + 1), 3);
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) {
      const Eigen::Vector2d p = warp(double(i) / n, double(j) / n);
      m.V.row(i * (n + 1) + j) << p.x(), p.y(), 0;
    }
  m.F.resize(2 * n * n, 3);
  int f = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const int a = i * (n + 1) + j, b = a + n + 1, c = b + 1, d = a + 1;
      m.F.row(f++) << a, b, c;
      m.F.row(f++) << a, c, d;
    }
  return m;
}

// The square squeezed twentyfold towards x = 0 and sheared by a wave in y: the input's
// triangles range over a factor 20 in width and are anisotropic everywhere.
Eigen::Vector2d squeezeAndShear(double x, double y) {
  const double X = (std::exp(3 * x) - 1) / (std::exp(3.0) - 1);
  return {X, y + 0.15 * std::sin(2 * 3.14159265358979 * X) * std::sin(3.14159265358979 * y)};
}

struct Sampling {
  TriMesh input;
  Simplification s;
  Resampled grid;
};

Sampling resampled(const TriMesh& input, int baseFaces, int levels,
                   GridMap map = GridMap::straightened) {
  Sampling r{input, {}, {}};
  const Features features = detectFeatures(input, 70.0);
  r.s = simplify(input, features, baseFaces);
  const Connectivity conn(input.F, static_cast<int>(input.V.rows()));
  r.grid = resample(input, conn, features.list, r.s, BaseCharts(r.s.base), levels, map);
  return r;
}

const GridMap kMaps[] = {GridMap::straightened, GridMap::exact};

}  // namespace

TEST(Resample, GridPointsLieOnTheInputWhereTheyWereSampled) {
  for (GridMap map : kMaps) {
    SCOPED_TRACE(static_cast<int>(map));
    const Sampling r = resampled(subdivide(shapes::torus(), 3, Scheme::Loop, 0.01, 5), 60, 3, map);
    const TriMesh& m = r.grid.mesh;
    validate(m, "resampled");
    ASSERT_EQ(m.F.rows(), r.s.base.F.rows() * 64);
    ASSERT_EQ(r.grid.where.size(), static_cast<std::size_t>(m.V.rows()));
    // Shared edge points make it the base's topology, without cracks.
    EXPECT_EQ(topology(m), topology(r.input));
    for (Eigen::Index v = 0; v < m.V.rows(); ++v) {
      const SurfacePoint& w = r.grid.where[v];
      ASSERT_GE(w.triangle, 0);
      Eigen::RowVector3d x = Eigen::RowVector3d::Zero();
      for (int k = 0; k < 3; ++k) x += w.bary[k] * r.input.V.row(r.input.F(w.triangle, k));
      EXPECT_LT((x - m.V.row(v)).norm(), 1e-12) << "vertex " << v;
    }
    // The base vertices come first and are input vertices.
    for (Eigen::Index v = 0; v < r.s.base.V.rows(); ++v) EXPECT_EQ(m.V.row(v), r.s.base.V.row(v));
  }
}

// A base vertex that is no input vertex (a split at a point of the input, base_flips.h)
// is placed through the map as a grid point is: on the input, shared by its faces'
// grids, and through the exact map where the split put it.
TEST(Resample, AnAddedBaseVertexIsPlacedAsAGridPointIs) {
  const TriMesh input = shapes::torus(16, 8);
  const Features features = detectFeatures(input, 70.0);
  Simplification s = simplify(input, features, 40);
  BaseFlipOptions options;
  options.levels = 3;
  options.input = &input;
  options.maxSplits = 6;
  options.splitAtPoints = true;
  splitFoldingFaces(s, std::vector<int>(s.base.F.rows(), 1), options);
  ASSERT_FALSE(s.added.empty());
  const Connectivity conn(input.F, static_cast<int>(input.V.rows()));
  for (GridMap map : kMaps) {
    SCOPED_TRACE(static_cast<int>(map));
    const Resampled grid = resample(input, conn, features.list, s, BaseCharts(s.base), 3, map);
    validate(grid.mesh, "resampled");
    EXPECT_EQ(topology(grid.mesh), topology(input));
    for (Eigen::Index v = 0; v < grid.mesh.V.rows(); ++v) {
      const SurfacePoint& w = grid.where[v];
      ASSERT_GE(w.triangle, 0);
      Eigen::RowVector3d x = Eigen::RowVector3d::Zero();
      for (int k = 0; k < 3; ++k) x += w.bary[k] * input.V.row(input.F(w.triangle, k));
      EXPECT_LT((x - grid.mesh.V.row(v)).norm(), 1e-12) << "vertex " << v;
    }
    if (map != GridMap::exact) continue;
    for (const auto& added : s.added)
      EXPECT_LT((grid.mesh.V.row(added.base) - s.base.V.row(added.base)).norm(), 1e-9);
  }
}

// The exact map is the removals' inverse itself: a grid point inside a base face lies
// where traceToInput puts its grid parameter.
TEST(Resample, TheExactMapIsTheInverseOfTheRemovals) {
  const int levels = 3, N = 1 << levels;
  const Sampling r =
      resampled(subdivide(shapes::torus(), 3, Scheme::Loop, 0.01, 5), 60, levels, GridMap::exact);
  const TriMesh& m = r.grid.mesh;
  // Each interior grid point (i, j) of base face f, at the place traceToInput gives its
  // parameter, is a vertex of the face's triangles.
  int checked = 0;
  for (Eigen::Index f = 0; f < r.s.base.F.rows(); ++f)
    for (int i = 1; i < N; ++i)
      for (int j = 1; i + j < N; ++j) {
        const SurfacePoint w = traceToInput(r.s.history, static_cast<int>(f),
                                            {double(N - i - j) / N, double(i) / N, double(j) / N});
        Eigen::RowVector3d x = Eigen::RowVector3d::Zero();
        for (int k = 0; k < 3; ++k) x += w.bary[k] * r.input.V.row(r.input.F(w.triangle, k));
        bool found = false;
        for (Eigen::Index q = f * N * N; q < (f + 1) * N * N && !found; ++q)
          for (int k = 0; k < 3 && !found; ++k) found = (m.V.row(m.F(q, k)) - x).norm() < 1e-12;
        EXPECT_TRUE(found) << "face " << f << " grid point " << i << ", " << j;
        ++checked;
      }
  EXPECT_GT(checked, 0);
}

TEST(Resample, ADistortedButBijectiveChartComesOutWithoutAFold) {
  const TriMesh input = warpedSquare(40, squeezeAndShear);
  for (GridMap map : kMaps)
    for (int levels : {3, 4}) {
      SCOPED_TRACE(levels);
      SCOPED_TRACE(static_cast<int>(map));
      const Sampling r = resampled(input, 24, levels, map);
      const TriMesh& m = r.grid.mesh;
      EXPECT_EQ(topology(m), topology(input));
      // In the plane of the input, every grid triangle keeps the orientation of the
      // input's (+z) and has area; with the boundary on the boundary, that makes the
      // grid an embedding.
      for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
        const Eigen::Vector3d a = m.V.row(m.F(f, 0)), b = m.V.row(m.F(f, 1)),
                              c = m.V.row(m.F(f, 2));
        EXPECT_GT((b - a).cross(c - a).z(), 1e-12) << "face " << f;
      }
      for (Eigen::Index v = 0; v < m.V.rows(); ++v) EXPECT_EQ(m.V(v, 2), 0.0);
    }
}

// The same chart bent into a half cylinder: the grid still has no flipped triangle and
// no crossing pair, before any clean-up. (This is the distortion bound's doing: with a
// single stage allowing any anisotropy, StageLimits{1e9, 0.5, 3}, grid triangles here
// face against the input. In the plane, even that does not fold.)
TEST(Resample, ABentDistortedChartComesOutWithoutAFold) {
  TriMesh input = warpedSquare(40, squeezeAndShear);
  for (Eigen::Index v = 0; v < input.V.rows(); ++v) {
    const double angle = 3.14159265358979 * input.V(v, 0);
    input.V.row(v) << std::cos(angle), input.V(v, 1), std::sin(angle);
  }
  const Sampling r = resampled(input, 24, 4);
  const TriMesh& m = r.grid.mesh;
  // Facing with the input triangle under each corner, as Remeshing::flippedTriangles asks.
  for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
    const Eigen::Vector3d a = m.V.row(m.F(f, 0)), b = m.V.row(m.F(f, 1)), c = m.V.row(m.F(f, 2));
    const Eigen::Vector3d n = (b - a).cross(c - a);
    for (int k = 0; k < 3; ++k)
      EXPECT_GT(n.dot(faceNormal(input, r.grid.where[m.F(f, k)].triangle)), 0) << "face " << f;
  }
  EXPECT_EQ(findSelfIntersections(m).count, 0);
}

// The grid points next to a base vertex, spread where a corner would span more than a
// half turn: order kept, no gap over the bound, the gaps still summing to the turn, no
// turn of the whole on average; untouched where nothing is too wide or it cannot be done.
TEST(Resample, SpreadAroundCutsWideCornersKeepingOrder) {
  const double turn = 2 * kPi;
  const std::vector<double> angles = {0.0, 0.1, 0.3, 5.9};  // one gap of 5.6
  ASSERT_GT(widestGap(angles, turn), kPi);
  const std::vector<double> spread = spreadAround(angles, turn, kSpreadTo);
  ASSERT_EQ(spread.size(), angles.size());
  EXPECT_LE(widestGap(spread, turn), kSpreadTo + 1e-12);
  double sum = 0, shift = 0;
  for (std::size_t k = 0; k < spread.size(); ++k) {
    EXPECT_GE(spread[k], 0);
    EXPECT_LT(spread[k], turn);
    const double gap = std::fmod(spread[(k + 1) % 4] - spread[k] + 2 * turn, turn);
    EXPECT_GT(gap, 0);  // in order: every point still follows the one before
    sum += gap;
    double d = std::fmod(spread[k] - angles[k] + 3 * turn, turn);
    if (d > turn / 2) d -= turn;
    shift += d;
  }
  EXPECT_NEAR(sum, turn, 1e-12);
  EXPECT_NEAR(shift, 0, 1e-12);
  // The gaps under the bound grew in proportion to their room under it: 0.1 and 0.2
  // and 0.3 keep their order of size.
  const double g0 = spread[1] - spread[0], g1 = spread[2] - spread[1];
  EXPECT_LT(g0, g1);

  const std::vector<double> even = {0.0, 2.0, 4.0};
  EXPECT_EQ(spreadAround(even, turn, kSpreadTo), even);  // nothing over the bound
  EXPECT_EQ(spreadAround({0.0, 0.1, 0.2}, turn, 2.0), (std::vector<double>{0.0, 0.1, 0.2}))
      << "three gaps of at most 2 cannot close a turn of 6.28";
  EXPECT_EQ(spreadAround({0.0, 4.0, 2.0}, turn, kSpreadTo), (std::vector<double>{0.0, 4.0, 2.0}))
      << "out of order";
  // A saddle (a cone of 2.5 pi) with three points: each gap at most 0.9 pi is possible.
  const double saddle = 2.5 * kPi;
  const std::vector<double> s3 = spreadAround({0.0, 0.5, 1.0}, saddle, kSpreadTo);
  EXPECT_LE(widestGap(s3, saddle), kSpreadTo + 1e-12);
}
