// Closest points, the triangle BVH, surface sampling and the symmetric surface
// distance: hand-computed answers, brute force, and surfaces whose distance is known.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <random>
#include <utility>
#include <vector>

#include "osdmra/base/error.h"
#include "osdmra/geometry/distance.h"
#include "osdmra/mesh/mesh.h"
#include "support.h"

using namespace osdmra;
using namespace osdmra::test;
using Vec3 = Eigen::Vector3d;

namespace {

/// Uniform double in [lo, hi) from one raw word (same on every standard library).
double uniform(std::mt19937_64& rng, double lo, double hi) {
  return lo + (hi - lo) * (static_cast<double>(rng() >> 11) * 0x1.0p-53);
}

Vec3 randomPoint(std::mt19937_64& rng, double lo, double hi) {
  return {uniform(rng, lo, hi), uniform(rng, lo, hi), uniform(rng, lo, hi)};
}

/// Octahedron refined `levels` times by 1-to-4 midpoint splits, every vertex pushed
/// onto the unit sphere: a convex polyhedron inscribed in the sphere.
TriMesh sphere(int levels) {
  std::vector<Vec3> V{{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  std::vector<std::array<int, 3>> F{{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4},
                                    {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  for (int l = 0; l < levels; ++l) {
    std::map<std::pair<int, int>, int> midpoint;
    auto mid = [&](int i, int j) {
      const std::pair<int, int> key{std::min(i, j), std::max(i, j)};
      const auto it = midpoint.find(key);
      if (it != midpoint.end()) return it->second;
      V.push_back((0.5 * (V[i] + V[j])).normalized());
      return midpoint[key] = static_cast<int>(V.size()) - 1;
    };
    std::vector<std::array<int, 3>> next;
    for (const auto& f : F) {
      const int a = mid(f[0], f[1]), b = mid(f[1], f[2]), c = mid(f[2], f[0]);
      next.push_back({f[0], a, c});
      next.push_back({a, f[1], b});
      next.push_back({c, b, f[2]});
      next.push_back({a, b, c});
    }
    F = std::move(next);
  }
  TriMesh m;
  m.V.resize(static_cast<Eigen::Index>(V.size()), 3);
  for (std::size_t i = 0; i < V.size(); ++i) m.V.row(static_cast<Eigen::Index>(i)) = V[i];
  m.F.resize(static_cast<Eigen::Index>(F.size()), 3);
  for (std::size_t f = 0; f < F.size(); ++f)
    m.F.row(static_cast<Eigen::Index>(f)) << F[f][0], F[f][1], F[f][2];
  return m;
}

/// A triangle soup in the unit cube: `n` triangles of random size and orientation
/// (overlapping boxes stress the pruning), some of them slivers and degenerates.
TriMesh soup(int n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  TriMesh m;
  m.V.resize(3 * n, 3);
  m.F.resize(n, 3);
  for (int f = 0; f < n; ++f) {
    const Vec3 c = randomPoint(rng, 0.0, 1.0);
    const double size = uniform(rng, 0.01, 0.15);
    Vec3 a = c + size * randomPoint(rng, -1.0, 1.0), b = c + size * randomPoint(rng, -1.0, 1.0),
         d = c + size * randomPoint(rng, -1.0, 1.0);
    if (f % 50 == 7) d = a + 0.37 * (b - a);   // collinear
    if (f % 50 == 19) b = d = a;               // a point
    if (f % 50 == 31) d = b + 1e-9 * (d - b);  // sliver
    m.V.row(3 * f) = a;
    m.V.row(3 * f + 1) = b;
    m.V.row(3 * f + 2) = d;
    m.F.row(f) << 3 * f, 3 * f + 1, 3 * f + 2;
  }
  return m;
}

struct Brute {
  double distance;
  Vec3 point;
};

/// Corners of every face, three per face, for brute force.
std::vector<Vec3> corners(const TriMesh& m) {
  std::vector<Vec3> c;
  for (Eigen::Index f = 0; f < m.F.rows(); ++f)
    for (int k = 0; k < 3; ++k) c.push_back(m.V.row(m.F(f, k)).transpose());
  return c;
}

Brute bruteForce(const std::vector<Vec3>& c, const Vec3& p) {
  Brute best{std::numeric_limits<double>::infinity(), Vec3::Zero()};
  for (std::size_t i = 0; i < c.size(); i += 3) {
    const Vec3 x = closestPointOnTriangle(p, c[i], c[i + 1], c[i + 2]);
    const double d = (p - x).norm();
    if (d < best.distance) best = {d, x};
  }
  return best;
}

double triangleDistance(const TriMesh& m, int f, const Vec3& p) {
  return (p - closestPointOnTriangle(p, m.V.row(m.F(f, 0)), m.V.row(m.F(f, 1)), m.V.row(m.F(f, 2))))
      .norm();
}

void expectPoint(const Vec3& actual, const Vec3& expected, double tol = 1e-15) {
  EXPECT_LE((actual - expected).norm(), tol)
      << actual.transpose() << " vs " << expected.transpose();
}

}  // namespace

TEST(DistanceTriangle, EveryVoronoiRegion) {
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  struct Case {
    Vec3 p, expected;
  };
  const Case cases[] = {
      {{0.25, 0.25, 2}, {0.25, 0.25, 0}},  // interior, above
      {{0.2, 0.3, -0.5}, {0.2, 0.3, 0}},   // interior, below
      {{0.1, 0.1, 0}, {0.1, 0.1, 0}},      // on the triangle
      {{-1, -1, 1}, {0, 0, 0}},            // vertex a
      {{2, -1, 0}, {1, 0, 0}},             // vertex b
      {{-1, 2, 0.5}, {0, 1, 0}},           // vertex c
      {{0.5, -1, 1}, {0.5, 0, 0}},         // edge ab
      {{-2, 0.5, 0}, {0, 0.5, 0}},         // edge ca
      {{1, 1, 1}, {0.5, 0.5, 0}},          // edge bc
      {{0.75, 0.75, -3}, {0.5, 0.5, 0}},   // edge bc, below
      {{1.5, 0.25, 0}, {1, 0, 0}},         // vertex b, from beyond bc's end
  };
  for (const Case& k : cases) {
    SCOPED_TRACE(testing::Message() << "p = " << k.p.transpose());
    expectPoint(closestPointOnTriangle(k.p, a, b, c), k.expected);
    // The answer does not depend on which corner comes first.
    expectPoint(closestPointOnTriangle(k.p, b, c, a), k.expected);
    expectPoint(closestPointOnTriangle(k.p, c, a, b), k.expected);
  }
}

TEST(DistanceTriangle, DegenerateTriangles) {
  // Collinear corners: the triangle is the segment from (0,0,0) to (2,0,0).
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(2, 0, 0);
  expectPoint(closestPointOnTriangle({1.5, 1, 0}, a, b, c), {1.5, 0, 0});
  expectPoint(closestPointOnTriangle({3, 1, 1}, a, b, c), {2, 0, 0});
  expectPoint(closestPointOnTriangle({-1, 0, 4}, b, c, a), {0, 0, 0});
  // Two corners coincide: a segment.
  expectPoint(closestPointOnTriangle({0.5, 2, 0}, a, a, b), {0.5, 0, 0});
  // All three coincide: a point.
  const Vec3 q(1, 2, 3);
  expectPoint(closestPointOnTriangle({4, 6, 3}, q, q, q), q);
  // A sliver 1e-12 high: the answer is within rounding of its long edge's.
  const Vec3 s(0.5, 1e-12, 0);
  for (const Vec3& p : {Vec3(0.3, 5, 1), Vec3(0.3, -5, 1), Vec3(0.5, 0.5, 0), Vec3(-1, 0, 0)}) {
    const Vec3 x = closestPointOnTriangle(p, a, c, s);
    const Vec3 onLine(std::clamp(p.x(), 0.0, 2.0), 0, 0);
    EXPECT_TRUE(x.allFinite());
    EXPECT_NEAR((p - x).norm(), (p - onLine).norm(), 1e-11) << p.transpose();
  }
}

TEST(DistanceTriangle, NoPointOfTheTriangleIsNearer) {
  // Independent of the routine's own case analysis: the answer lies on the triangle
  // and beats every point of a fine barycentric grid.
  std::mt19937_64 rng(7);
  const int grid = 40;
  for (int trial = 0; trial < 200; ++trial) {
    const Vec3 a = randomPoint(rng, -1, 1), b = randomPoint(rng, -1, 1),
               c = randomPoint(rng, -1, 1), p = randomPoint(rng, -2, 2);
    const Vec3 x = closestPointOnTriangle(p, a, b, c);
    const double d = (p - x).norm();
    // On the triangle: in its plane and with non-negative barycentric coordinates.
    const Vec3 n = (b - a).cross(c - a);
    EXPECT_NEAR(n.normalized().dot(x - a), 0.0, 1e-14);
    const std::array<Vec3, 3> abc{a, b, c};
    for (int k = 0; k < 3; ++k) {
      const Vec3 &u = abc[k], &v = abc[(k + 1) % 3];
      EXPECT_GE((v - u).cross(x - u).dot(n), -1e-14 * (v - u).norm() * (x - u).norm() * n.norm())
          << trial;
    }
    for (int i = 0; i <= grid; ++i)
      for (int j = 0; i + j <= grid; ++j) {
        const Vec3 y = a + (b - a) * (double(i) / grid) + (c - a) * (double(j) / grid);
        EXPECT_LE(d, (p - y).norm() + 1e-14) << trial;
      }
  }
}

namespace {

// Random queries around the unit cube: the hierarchy's answer is the brute force's.
void expectClosestAsBruteForce(const TriMesh& m, const TriangleBvh& bvh, int queries,
                               std::uint64_t seed) {
  const std::vector<Vec3> c = corners(m);
  std::mt19937_64 rng(seed);
  for (int q = 0; q < queries; ++q) {
    const Vec3 p = randomPoint(rng, -0.5, 1.5);
    const ClosestPoint got = bvh.closestPoint(p);
    const Brute want = bruteForce(c, p);
    ASSERT_NEAR(got.distance, want.distance, 1e-12) << q;
    ASSERT_LE((got.point - want.point).norm(), 1e-12) << q;
    ASSERT_GE(got.face, 0);
    ASSERT_LT(got.face, m.F.rows());
    // The face reported is one that attains the distance.
    ASSERT_NEAR(triangleDistance(m, got.face, p), got.distance, 1e-12) << q;
  }
}

}  // namespace

TEST(DistanceBvh, MatchesBruteForce) {
  const TriMesh m = soup(2000, 11);
  const TriangleBvh bvh(m);
  EXPECT_EQ(bvh.numTriangles(), 2000);
  EXPECT_EQ(bvh.depth(), 10);  // 1 + ceil(log2(2000 / 4))
  expectClosestAsBruteForce(m, bvh, 2000, 12);
}

// Large meshes build the hierarchy's two halves on two threads (at least 65,536
// faces); the second half's nodes are appended after the first's with their child
// indices moved. A query then still finds the nearest triangle wherever it lies.
TEST(DistanceBvh, MatchesBruteForceWhenBuiltOnTwoThreads) {
  const TriMesh m = soup(70000, 13);
  const TriangleBvh bvh(m);
  EXPECT_EQ(bvh.depth(), 16);  // 1 + ceil(log2(70000 / 4))
  expectClosestAsBruteForce(m, bvh, 100, 14);
}

TEST(DistanceBvh, SingleTriangleAndCoincidentTriangles) {
  TriMesh one = unitSquare(0.0);
  one.F.conservativeResize(1, 3);
  const TriangleBvh small(one);
  EXPECT_EQ(small.numNodes(), 1);
  const ClosestPoint cp = small.closestPoint({0.9, 0.1, 2});
  EXPECT_EQ(cp.face, 0);
  EXPECT_DOUBLE_EQ(cp.distance, 2.0);

  // 100 copies of one triangle: the median split still terminates with a
  // logarithmic depth, and the lowest face index wins the tie.
  TriMesh same;
  same.V = one.V;
  same.F.resize(100, 3);
  for (int f = 0; f < 100; ++f) same.F.row(f) = one.F.row(0);
  const TriangleBvh copies(same);
  EXPECT_EQ(copies.depth(), 6);  // 1 + ceil(log2(100 / 4))
  EXPECT_EQ(copies.closestPoint({0.9, 0.1, 2}).face, 0);
}

TEST(DistanceBvh, FarAndNonFiniteQueries) {
  const TriangleBvh bvh(unitSquare(0.0));
  // Squared distances overflow: the answer is still a point of some face.
  const ClosestPoint far = bvh.closestPoint({1e200, -1e200, 3e200});
  EXPECT_EQ(far.distance, std::numeric_limits<double>::infinity());
  EXPECT_GE(far.face, 0);
  EXPECT_LT(far.face, 2);
  EXPECT_THROW(bvh.closestPoint({0, std::numeric_limits<double>::quiet_NaN(), 0}), Error);
  EXPECT_THROW(bvh.closestPoint({std::numeric_limits<double>::infinity(), 0, 0}), Error);
}

TEST(DistanceBvh, RejectsBadMeshes) {
  EXPECT_THROW(TriangleBvh{TriMesh{}}, Error);
  TriMesh m = unitSquare(0.0);
  m.F(1, 2) = 4;
  EXPECT_THROW(TriangleBvh{m}, Error);
  m = unitSquare(0.0);
  m.V(2, 1) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(TriangleBvh{m}, Error);
  EXPECT_THROW(samplePoints(m, 10, 1), Error);
  EXPECT_THROW(surfaceDistance(unitSquare(0.0), m), Error);
  EXPECT_THROW(surfaceDistance(TriMesh{}, unitSquare(0.0)), Error);
  EXPECT_THROW(surfaceDistance(unitSquare(0.0), unitSquare(0.0), {0, 1, false}), Error);
  EXPECT_THROW(samplePoints(unitSquare(0.0), -1, 1), Error);
}

TEST(DistanceSampling, AreaUniformAndOnTheSurface) {
  // Quad (0,0), (1,0), (1,1), (0,0.2) of area 0.6: faces of area 0.5 (below y = x)
  // and 0.1 (above it).
  TriMesh m;
  m.V.resize(4, 3);
  m.V << 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 0.2, 0;
  m.F.resize(2, 3);
  m.F << 0, 2, 3, 0, 1, 2;
  const int n = 20000;
  const Points s = samplePoints(m, n, 5, true);
  ASSERT_EQ(s.rows(), n + 4);
  EXPECT_EQ(s.bottomRows(4), m.V);
  int inSmall = 0, left = 0;
  for (int i = 0; i < n; ++i) {
    EXPECT_EQ(s(i, 2), 0.0);
    EXPECT_GE(s(i, 0), 0.0);
    EXPECT_LE(s(i, 0), 1.0);
    EXPECT_GE(s(i, 1), 0.0);
    EXPECT_LE(s(i, 1), 1.0);
    inSmall += s(i, 1) > s(i, 0) ? 1 : 0;
    left += s(i, 0) < 0.5 ? 1 : 0;
  }
  // Expected fractions 0.1 / 0.6 and (0.125 + 0.075) / 0.6 for x < 1/2; binomial
  // standard deviations sqrt(n p (1 - p)) = 53 and 67; allow 5 of them.
  EXPECT_NEAR(inSmall, n / 6.0, 5 * 53);
  EXPECT_NEAR(left, n / 3.0, 5 * 67);
}

TEST(DistanceSampling, Deterministic) {
  const TriMesh m = sphere(2);
  const Points a = samplePoints(m, 1000, 3), b = samplePoints(m, 1000, 3),
               c = samplePoints(m, 1000, 4);
  EXPECT_EQ(a, b);
  EXPECT_NE(a, c);
  EXPECT_EQ(a.rows(), 1000);
}

TEST(DistanceSurface, ParallelSquaresExactly) {
  const TriMesh a = unitSquare(0.0), b = unitSquare(0.25);
  const SurfaceDistance d = surfaceDistance(a, b, {5000, 1, true});
  // Every sample of either square is exactly 0.25 from the other: the sample keeps
  // its z exactly, and the in-plane rounding (~1e-17) vanishes next to 0.25^2.
  EXPECT_EQ(d.rms, 0.25);
  EXPECT_EQ(d.hausdorff, 0.25);
  EXPECT_EQ(d.meanAB, 0.25);
  EXPECT_EQ(d.maxAB, 0.25);
  EXPECT_EQ(d.meanBA, 0.25);
  EXPECT_EQ(d.maxBA, 0.25);
  EXPECT_EQ(d.diagonal, std::sqrt(2.0));  // b's box alone: a flat unit square
  EXPECT_EQ(d.rmsRelative, 0.25 / std::sqrt(2.0));
  EXPECT_EQ(d.hausdorffRelative, 0.25 / std::sqrt(2.0));
}

TEST(DistanceSurface, SphereAgainstScaledCopy) {
  // a is a convex polyhedron inscribed in the unit sphere, b = 1.01 a. Every
  // distance lies in [0.01 h, 0.01], h the smallest distance from the centre to a
  // face plane of a:
  //  - from x on face f of a to b: x is inside b, and the plane of face 1.01 f is
  //    0.01 h_f from x; the nearest boundary point of a convex body is on a face
  //    plane, and each face plane g of b is at least 0.01 h_g from x (x is inside a).
  //  - from y = 1.01 x on b to a: at least 0.01 h_f (y is that far outside face f's
  //    plane) and at most |y - x| = 0.01 |x| <= 0.01. At a vertex of b it is exactly
  //    0.01: the sphere's tangent plane at a vertex supports a, so the vertex of a
  //    is the nearest point.
  // Hence hausdorff = 0.01 (vertices included), and mean / rms within [0.01 h, 0.01].
  const TriMesh a = sphere(4);  // 2048 faces, h = 0.9975
  TriMesh b = a;
  b.V *= 1.01;
  double h = 1.0;
  for (Eigen::Index f = 0; f < a.F.rows(); ++f) {
    const Vec3 p = a.V.row(a.F(f, 0)), q = a.V.row(a.F(f, 1)), r = a.V.row(a.F(f, 2));
    h = std::min(h, (q - p).cross(r - p).normalized().dot(p));
  }
  ASSERT_GT(h, 0.99);
  const double lo = 0.01 * h - 1e-15, hi = 0.01 + 1e-15;
  const SurfaceDistance d = surfaceDistance(a, b, {20000, 1, true});
  EXPECT_NEAR(d.hausdorff, 0.01, 1e-15);
  EXPECT_NEAR(d.maxBA, 0.01, 1e-15);
  for (double x : {d.rms, d.meanAB, d.maxAB, d.meanBA}) {
    EXPECT_GE(x, lo);
    EXPECT_LE(x, hi);
  }
  EXPECT_NEAR(d.diagonal, 1.01 * 2 * std::sqrt(3.0), 1e-14);
  EXPECT_NEAR(d.hausdorffRelative, 0.01 / d.diagonal, 1e-15);
}

TEST(DistanceSurface, MeshAgainstItselfIsZero) {
  const TriMesh m = sphere(3);
  const SurfaceDistance d = surfaceDistance(m, m, {10000, 1, true});
  // A sample is a rounded point of its face: it is off the surface by rounding only.
  EXPECT_LE(d.hausdorff, 1e-15);
  EXPECT_LE(d.rms, 1e-15);
  EXPECT_LE(d.hausdorffRelative, 1e-15);
}

TEST(DistanceSurface, DeterministicAndSeedDependent) {
  const TriMesh a = sphere(3);
  TriMesh b = sphere(2);
  b.V *= 1.02;
  const SurfaceDistance x = surfaceDistance(a, b, {3000, 9, true}),
                        y = surfaceDistance(a, b, {3000, 9, true}),
                        z = surfaceDistance(a, b, {3000, 10, true});
  EXPECT_EQ(x.rms, y.rms);
  EXPECT_EQ(x.hausdorff, y.hausdorff);
  EXPECT_EQ(x.meanAB, y.meanAB);
  EXPECT_EQ(x.meanBA, y.meanBA);
  EXPECT_NE(x.rms, z.rms);
  EXPECT_NEAR(x.rms, z.rms, 0.05 * x.rms);
  EXPECT_NEAR(x.meanAB, z.meanAB, 0.05 * x.meanAB);
}

TEST(DistanceSurface, DegenerateTrianglesStayFinite) {
  // A square plus a collinear face, a point face and a sliver.
  TriMesh a = unitSquare(0.0);
  a.V.conservativeResize(7, 3);
  a.V.row(4) << 2, 0, 0;
  a.V.row(5) << 0.5, 0.5, 1e-300;
  a.V.row(6) << 1, 1, 1e-9;
  a.F.conservativeResize(5, 3);
  a.F.row(2) << 0, 1, 4;  // collinear
  a.F.row(3) << 5, 5, 5;  // a point
  a.F.row(4) << 0, 2, 6;  // a sliver
  const SurfaceDistance d = surfaceDistance(a, unitSquare(0.5), {2000, 1, true});
  for (double x : {d.rms, d.hausdorff, d.meanAB, d.maxAB, d.meanBA, d.maxBA, d.rmsRelative,
                   d.hausdorffRelative})
    EXPECT_TRUE(std::isfinite(x));
  EXPECT_NEAR(d.maxBA, 0.5, 1e-12);
  // (2, 0, 0) is the farthest vertex: sqrt(1 + 0.25).
  EXPECT_NEAR(d.maxAB, std::sqrt(1.25), 1e-12);

  // A surface of zero area: every face degenerate. Sampling falls back to equal
  // face weights; the distances stay finite.
  TriMesh flat;
  flat.V.resize(3, 3);
  flat.V << 0, 0, 0, 1, 0, 0, 2, 0, 0;
  flat.F.resize(1, 3);
  flat.F << 0, 1, 2;
  const SurfaceDistance e = surfaceDistance(flat, unitSquare(0.5), {100, 1, false});
  EXPECT_GE(e.meanAB, 0.5);
  EXPECT_LE(e.maxAB, std::sqrt(1.25) + 1e-15);
  EXPECT_TRUE(std::isfinite(e.rms));

  // A reference of zero diagonal (one point): relative errors are +infinity, or 0
  // for a zero distance, never NaN.
  TriMesh point = flat;
  point.V.setConstant(0.5);
  const SurfaceDistance far = surfaceDistance(unitSquare(0.0), point, {100, 1, true});
  EXPECT_EQ(far.diagonal, 0.0);
  EXPECT_EQ(far.hausdorffRelative, std::numeric_limits<double>::infinity());
  const SurfaceDistance self = surfaceDistance(point, point, {100, 1, true});
  EXPECT_EQ(self.hausdorff, 0.0);
  EXPECT_EQ(self.rmsRelative, 0.0);
  EXPECT_EQ(self.hausdorffRelative, 0.0);
}
