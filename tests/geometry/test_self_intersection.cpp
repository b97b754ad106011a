// Self-intersection (self_intersection.h) and the box query of the distance BVH it
// rests on: closed surfaces have none, crossing and folded pairs are found, pairs
// sharing an edge are never reported, and the box query matches brute force.
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <random>
#include <vector>

#include "osdmra/base/error.h"
#include "osdmra/geometry/distance.h"
#include "osdmra/geometry/self_intersection.h"
#include "osdmra/subdivision/shapes.h"

using namespace osdmra;

namespace {

TriMesh twoTriangles(const Eigen::Matrix<double, 6, 3>& corners, const Faces& faces) {
  TriMesh m;
  m.V = corners;
  m.F = faces;
  return m;
}

}  // namespace

TEST(SelfIntersection, ClosedSurfacesHaveNone) {
  for (const TriMesh& base : {shapes::icosahedron(), shapes::torus(), shapes::slab(2)}) {
    const TriMesh m = subdivide(base, 3, Scheme::Loop);
    const SelfIntersections s = findSelfIntersections(m);
    EXPECT_EQ(s.count, 0);
    EXPECT_TRUE(s.pairs.empty());
  }
}

TEST(SelfIntersection, CrossingPairWithoutCommonVertex) {
  Eigen::Matrix<double, 6, 3> v;
  v << 0, 0, 0, 2, 0, 0, 0, 2, 0,          // in the plane z = 0
      0.5, 0.5, -1, 0.5, 0.5, 1, 3, 3, 0;  // pierces it at (0.5, 0.5, 0)
  Faces f(2, 3);
  f << 0, 1, 2, 3, 4, 5;
  const SelfIntersections s = findSelfIntersections(twoTriangles(v, f));
  EXPECT_EQ(s.count, 1);
  ASSERT_EQ(s.pairs.size(), 1u);
  EXPECT_EQ(s.pairs[0], (std::array<int, 2>{0, 1}));
  // Moved off: none.
  v.row(3) << 5, 5, -1;
  v.row(4) << 5, 5, 1;
  EXPECT_EQ(findSelfIntersections(twoTriangles(v, f)).count, 0);
}

TEST(SelfIntersection, FoldAtACommonVertex) {
  // Two faces sharing vertex 0: the second folds back through the first.
  Eigen::Matrix<double, 6, 3> v;
  v << 0, 0, 0, 2, 0, 0, 0, 2, 0, 1, 0.2, -1, 0.2, 1, 1, 9, 9, 9;
  Faces f(2, 3);
  f << 0, 1, 2, 0, 3, 4;
  EXPECT_EQ(findSelfIntersections(twoTriangles(v, f)).count, 1);
  // Opened out (both in their own half-spaces): none.
  v.row(3) << -1, -1, 0;
  v.row(4) << -2, 0.5, 0.3;
  EXPECT_EQ(findSelfIntersections(twoTriangles(v, f)).count, 0);
}

TEST(SelfIntersection, FacesSharingAnEdgeAreNotTested) {
  // Folded flat onto each other across their common edge: a flip, not a crossing.
  Eigen::Matrix<double, 6, 3> v;
  v << 0, 0, 0, 2, 0, 0, 0, 2, 0, 0.5, 1, 0, 9, 9, 9, 9, 9, 8;
  Faces f(2, 3);
  f << 0, 1, 2, 1, 0, 3;
  EXPECT_EQ(findSelfIntersections(twoTriangles(v, f)).count, 0);
}

TEST(SelfIntersection, VertexPushedThroughTheSurface) {
  TriMesh m = subdivide(shapes::icosahedron(), 3, Scheme::Loop);
  // A vertex dragged through the centre to beyond the far side: its faces now cross
  // the faces there.
  m.V.row(0) = -1.5 * m.V.row(0);
  const SelfIntersections s = findSelfIntersections(m, 4);
  EXPECT_GT(s.count, 0);
  EXPECT_EQ(s.pairs.size(), std::min<std::size_t>(4, static_cast<std::size_t>(s.count)));
  for (const auto& p : s.pairs) EXPECT_LT(p[0], p[1]);
  EXPECT_THROW(findSelfIntersections(TriMesh{}), Error);
}

// The pairs with a face of a subset are exactly the whole count's pairs that have one:
// the incremental recount of the remesher's clean-up relies on it.
TEST(SelfIntersection, PairsWithASubsetAreThoseOfTheWholeCount) {
  TriMesh m = subdivide(shapes::torus(), 3, Scheme::Loop);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> jitter(-0.3, 0.3);
  for (Eigen::Index v = 0; v < m.V.rows(); v += 5)
    m.V.row(v) += Eigen::RowVector3d(jitter(rng), jitter(rng), jitter(rng));
  const SelfIntersections all = findSelfIntersections(m, std::numeric_limits<int>::max());
  ASSERT_GT(all.count, 20);
  std::vector<int> subset;
  std::vector<char> in(m.F.rows(), 0);
  for (int f = 0; f < m.F.rows(); f += 7) subset.push_back(f), in[f] = 1;
  std::vector<std::array<int, 2>> expected;
  for (const auto& p : all.pairs)
    if (in[p[0]] || in[p[1]]) expected.push_back(p);
  ASSERT_FALSE(expected.empty());
  EXPECT_EQ(selfIntersectionsWith(m, subset), expected);
  EXPECT_TRUE(selfIntersectionsWith(m, {}).empty());
  // The whole mesh as the subset: every pair.
  std::vector<int> every(m.F.rows());
  for (int f = 0; f < m.F.rows(); ++f) every[f] = f;
  EXPECT_EQ(selfIntersectionsWith(m, every), all.pairs);
}

TEST(DistanceBvh, FacesInBoxMatchesBruteForce) {
  const TriMesh m = subdivide(shapes::torus(), 2, Scheme::Loop, 0.05, 3);
  const TriangleBvh bvh(m);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1.5, 1.5), size(0.0, 0.4);
  for (int q = 0; q < 200; ++q) {
    const Eigen::Vector3d lo(u(rng), u(rng), u(rng) / 3);
    const Eigen::Vector3d hi = lo + Eigen::Vector3d(size(rng), size(rng), size(rng));
    std::vector<int> got;
    bvh.facesInBox(lo, hi, got);
    std::sort(got.begin(), got.end());
    std::vector<int> want;
    for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
      Eigen::Vector3d a = m.V.row(m.F(f, 0)), b = a;
      for (int k = 1; k < 3; ++k) {
        a = a.cwiseMin(m.V.row(m.F(f, k)).transpose());
        b = b.cwiseMax(m.V.row(m.F(f, k)).transpose());
      }
      if ((a.array() <= hi.array()).all() && (b.array() >= lo.array()).all())
        want.push_back(static_cast<int>(f));
    }
    EXPECT_EQ(got, want) << "box " << q;
  }
}

// The traversal of the hierarchy against itself finds every pair of triangles whose
// boxes meet exactly once, however its tasks are cut, a single leaf included.
TEST(DistanceBvh, PairsOfMeetingBoxesMatchBruteForce) {
  for (const TriMesh& m :
       {subdivide(shapes::torus(), 2, Scheme::Loop, 0.05, 3),
        subdivide(shapes::icosahedron(), 1, Scheme::Loop), shapes::tetrahedron()}) {
    std::vector<Eigen::Vector3d> lo(m.F.rows()), hi(m.F.rows());
    for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
      lo[f] = hi[f] = m.V.row(m.F(f, 0));
      for (int k = 1; k < 3; ++k) {
        lo[f] = lo[f].cwiseMin(m.V.row(m.F(f, k)).transpose());
        hi[f] = hi[f].cwiseMax(m.V.row(m.F(f, k)).transpose());
      }
    }
    std::vector<std::array<int, 2>> want;
    for (int f = 0; f < m.F.rows(); ++f)
      for (int g = f + 1; g < m.F.rows(); ++g)
        if ((lo[f].array() <= hi[g].array()).all() && (hi[f].array() >= lo[g].array()).all())
          want.push_back({f, g});
    const TriangleBvh bvh(m);
    for (int count : {1, 2, 7, 64, 100000}) {
      std::vector<std::array<int, 2>> got;
      for (const auto& task : bvh.selfPairTasks(count))
        bvh.forBoxesMeeting(task, [&](int f, int g) { got.push_back({f, g}); });
      std::sort(got.begin(), got.end());
      EXPECT_EQ(got, want) << m.F.rows() << " faces, " << count << " tasks";
    }
  }
}
