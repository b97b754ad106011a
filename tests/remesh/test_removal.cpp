// One removal of the simplification (removal.h): the z^a flattening's closed forms,
// the certificate that the old faces map onto the new ones bijectively, and the refusal
// of a removal that would fold.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "osdmra/remesh/removal.h"

using namespace osdmra::remeshing;

namespace {

// A closed ring of unit-length spokes at the given angles (degrees) around the
// origin, lifted to height z (a cone when z != 0).
std::vector<Vec3> ringAt(const std::vector<double>& degrees, double z = 0.0) {
  std::vector<Vec3> ring;
  double at = 0;
  for (double d : degrees) {
    ring.emplace_back(std::cos(at * kPi / 180), std::sin(at * kPi / 180), z);
    at += d;
  }
  ring.push_back(ring.front());
  return ring;
}

double area(const Vec2& a, const Vec2& b, const Vec2& c) {
  return 0.5 * cross2(b - a, c - a);
}

}  // namespace

TEST(Removal, AFlatRingFlattensIsometrically) {
  const std::vector<Vec3> ring = ringAt({60, 60, 60, 60, 60, 60});
  const Flattening f = flattenRing(Vec3::Zero(), ring, false, -1);
  EXPECT_NEAR(f.exponent, 1.0, 1e-14);
  for (std::size_t k = 0; k < ring.size(); ++k) {
    EXPECT_NEAR(f.points[k].x(), ring[k].x(), 1e-14);
    EXPECT_NEAR(f.points[k].y(), ring[k].y(), 1e-14);
  }
  const auto tris = triangulateRing(f.points, false, -1);
  EXPECT_EQ(tris.size(), 4u);
  EXPECT_TRUE(isBijective(f, tris, false));
}

TEST(Removal, AConeOpensByTheZToTheAMap) {
  // A regular cone: 6 spokes of slant length L; the angles at the apex sum to S < 2 pi,
  // so a = 2 pi / S and the flat radii are L^a (MAPS eq. 1).
  const double z = 0.5;
  const std::vector<Vec3> ring = ringAt({60, 60, 60, 60, 60, 60}, z);
  const Flattening f = flattenRing(Vec3::Zero(), ring, false, -1);
  const Vec3 a = ring[0], b = ring[1];
  const double S = 6 * std::atan2(a.cross(b).norm(), a.dot(b));
  EXPECT_NEAR(f.exponent, 2 * kPi / S, 1e-12);
  double sum = 0;
  for (double x : f.angles) sum += x;
  EXPECT_NEAR(sum, 2 * kPi, 1e-12);
  EXPECT_NEAR(f.points[0].norm(), std::pow(a.norm(), f.exponent), 1e-12);
}

TEST(Removal, TheNewFacesTileTheFanExactly) {
  // An irregular ring: the new faces cover the same area as the fan, every point of the
  // fan lands in exactly one of them, and no point outside does.
  const std::vector<Vec3> ring = ringAt({40, 95, 30, 70, 50, 75}, 0.2);
  const Flattening f = flattenRing(Vec3(0, 0, 0), ring, false, -1);
  const auto tris = triangulateRing(f.points, false, -1);
  ASSERT_TRUE(isBijective(f, tris, false));
  double fan = 0, tiled = 0;
  for (int k = 0; k < 6; ++k) fan += area(Vec2::Zero(), f.points[k], f.points[k + 1]);
  for (const auto& t : tris) tiled += area(f.points[t[0]], f.points[t[1]], f.points[t[2]]);
  EXPECT_NEAR(tiled, fan, 1e-12 * fan);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0, 1);
  for (int i = 0; i < 2000; ++i) {
    const int k = i % 6;
    double s = u(rng), t = u(rng);
    if (s + t > 1) s = 1 - s, t = 1 - t;
    const Vec2 p = s * f.points[k] + t * f.points[k + 1];  // in fan triangle k
    std::array<double, 3> b;
    const int q = locateInTriangles(p, f.points, tris, b);
    ASSERT_GE(q, 0);
    const Vec2 back =
        b[0] * f.points[tris[q][0]] + b[1] * f.points[tris[q][1]] + b[2] * f.points[tris[q][2]];
    EXPECT_LT((back - p).norm(), 1e-12);
    int inside = 0;  // exactly one triangle holds an interior point
    for (const auto& tri : tris)
      inside += minOf(barycentric(p, f.points[tri[0]], f.points[tri[1]], f.points[tri[2]])) > 1e-9;
    EXPECT_LE(inside, 1);
  }
  std::array<double, 3> b;
  EXPECT_EQ(locateInTriangles(Vec2(5, 5), f.points, tris, b), -1);
}

TEST(Removal, ARemovalThatWouldFoldIsRefused) {
  // The z^a map cannot turn a fan triangle over (on a closed ring no angle exceeds half
  // the sum), but an old face of no angle at v (two spokes in one direction: a slit of
  // a scan) would collapse all its points onto one line: refused.
  const std::vector<Vec3> slit = ringAt({0, 90, 90, 90, 90});
  const Flattening f = flattenRing(Vec3::Zero(), slit, false, -1);
  EXPECT_FALSE(isBijective(f, triangulateRing(f.points, false, -1), false));
  // A retriangulation that does not tile the polygon once is refused too: a clockwise
  // face, or faces that overlap.
  const std::vector<Vec3> ring = ringAt({60, 60, 60, 60, 60, 60});
  const Flattening g = flattenRing(Vec3::Zero(), ring, false, -1);
  auto tris = triangulateRing(g.points, false, -1);
  ASSERT_TRUE(isBijective(g, tris, false));
  std::swap(tris[0][1], tris[0][2]);
  EXPECT_FALSE(isBijective(g, tris, false));
  const std::vector<std::array<int, 3>> overlapping = {{0, 1, 3}, {0, 2, 4}, {0, 3, 4}, {0, 4, 5}};
  EXPECT_FALSE(isBijective(g, overlapping, false));  // all positive, the right count
}

TEST(Removal, AFeatureLineSplitsTheRingIntoTwoHalves) {
  // Spokes 0 and 3 are the feature neighbours: each side spans pi, the feature's ends lie
  // on the x axis and the new faces share the edge between them.
  const std::vector<Vec3> ring = ringAt({50, 60, 70, 50, 60, 70}, 0.0);
  const Flattening f = flattenRing(Vec3::Zero(), ring, false, 3);
  EXPECT_NEAR(f.points[0].y(), 0.0, 1e-14);
  EXPECT_NEAR(f.points[3].y(), 0.0, 1e-14);
  EXPECT_LT(f.points[3].x(), 0.0);
  const auto tris = triangulateRing(f.points, false, 3);
  ASSERT_TRUE(isBijective(f, tris, false));
  int sharing = 0;
  for (const auto& t : tris)
    for (int i = 0; i < 3; ++i) {
      const int a = t[i] % 6, b = t[(i + 1) % 3] % 6;
      sharing += (a == 0 && b == 3) || (a == 3 && b == 0);
    }
  EXPECT_EQ(sharing, 2);  // once from each side
}

TEST(Removal, ABoundaryRingFlattensToAHalfDisk) {
  std::vector<Vec3> ring;
  for (double d : {0.0, 50.0, 100.0, 150.0})
    ring.emplace_back(std::cos(d * kPi / 180), std::sin(d * kPi / 180), 0);
  const Flattening f = flattenRing(Vec3::Zero(), ring, true, -1);
  EXPECT_NEAR(f.exponent, 180.0 / 150.0, 1e-12);
  EXPECT_NEAR(f.points[3].y(), 0.0, 1e-12);
  EXPECT_LT(f.points[3].x(), 0.0);
  const auto tris = triangulateRing(f.points, true, -1);
  EXPECT_EQ(tris.size(), 2u);
  EXPECT_TRUE(isBijective(f, tris, true));
}

TEST(Removal, AFanIsCertifiedExactlyWhereThePolygonIsStarShapedFromItsCorner) {
  // A flat ring of five spokes whose flattened polygon has one reflex corner (spoke 2
  // is short): a fan from a corner that sees the whole polygon tiles it once; a fan
  // from a corner that does not see it has a triangle turned over and is refused.
  std::vector<Vec3> ring = ringAt({72, 72, 72, 72, 72});
  ring[2] *= 0.2;
  const Flattening f = flattenRing(Vec3(0, 0, 0), ring, false, -1);
  int certified = 0;
  for (int from = 0; from < 5; ++from) {
    SCOPED_TRACE(from);
    const auto fan = fanOfRing(from, static_cast<int>(f.points.size()), false);
    ASSERT_EQ(fan.size(), 3u);
    // Star-shaped from `from`: every fan triangle positive.
    bool sees = true;
    for (const auto& t : fan)
      sees = sees && area(f.points[t[0]], f.points[t[1]], f.points[t[2]]) > 0;
    EXPECT_EQ(isBijective(f, fan, false), sees);
    certified += sees;
  }
  // The reflex corner sees everything; its two neighbours' fans cut across it.
  EXPECT_GT(certified, 0);
  EXPECT_LT(certified, 5);
  EXPECT_TRUE(isBijective(f, fanOfRing(2, static_cast<int>(f.points.size()), false), false));
  // On a boundary, the half disk's corners 0..m: fans from either end, and from the
  // middle, tile it.
  const std::vector<Vec3> half{{1, 0, 0}, {0.5, 0.8, 0}, {-0.5, 0.8, 0}, {-1, 0, 0}};
  const Flattening h = flattenRing(Vec3(0, 0, 0), half, true, -1);
  for (int from : {0, 1, 3}) EXPECT_TRUE(isBijective(h, fanOfRing(from, 4, true), true)) << from;
}
