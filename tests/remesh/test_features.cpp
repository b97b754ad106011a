// What the simplification must keep (features.h): the corners of a boundary are found
// at the scale asked for, one per bend, so that the ragged edge of a scan's hole does not
// pin base vertices while the corners of a plate stay.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "osdmra/geometry/normals.h"
#include "osdmra/remesh/features.h"
#include "osdmra/subdivision/shapes.h"
#include "support.h"

using namespace osdmra;
using namespace osdmra::remeshing;
using namespace osdmra::test;

namespace {

// A flat n x n plate of unit cells, two triangles each, whose side y = 0 carries a
// spike of height 1 (in the plate's plane, outwards) at every x = 3 mod 6: a bend of
// two edges, as a scan's hole is ragged.
TriMesh raggedPlate(int n) {
  TriMesh m;
  m.V.resize((n + 1) * (n + 1), 3);
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const double y = (j == 0 && i % 6 == 3) ? -1.0 : j;
      m.V.row(j * (n + 1) + i) << i, y, 0;
    }
  m.F.resize(2 * n * n, 3);
  int f = 0;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
      m.F.row(f++) << a, b, d;
      m.F.row(f++) << a, d, c;
    }
  return m;
}

std::vector<int> cornersOf(const Features& features) {
  std::vector<int> out;
  for (int v = 0; v < static_cast<int>(features.corner.size()); ++v)
    if (features.corner[v]) out.push_back(v);
  return out;
}

}  // namespace

TEST(Features, BoundaryCornersAreFoundAtTheSpanAskedFor) {
  const int n = 24;
  const TriMesh plate = raggedPlate(n);
  const std::vector<int> plateCorners = {0, n, n * (n + 1), n * (n + 1) + n};
  // Two edges each way (span 0): each spike's tip turns by 2 atan(1/2) = 53 degrees,
  // more than kMaxTurn, and is a corner beside the plate's four.
  const std::vector<int> fine = cornersOf(detectFeatures(plate, 70.0, 0.0));
  EXPECT_EQ(fine.size(), plateCorners.size() + 4);
  for (int v : plateCorners) EXPECT_EQ(std::count(fine.begin(), fine.end(), v), 1) << v;
  // Four units each way: a spike turns by 2 atan(1/4) = 28 degrees and is no corner;
  // a plate corner turns by 90 degrees, and its neighbours, which see it within their
  // reach and turn less, are not corners as well.
  EXPECT_EQ(cornersOf(detectFeatures(plate, 70.0, 4.0)), plateCorners);
}

// An edge is a feature where the surface on either side meets at the angle, not where a
// sliver alone turns: a sphere of 1,280 faces displaced by noise at every level has
// edges whose two faces' normals differ by more than 70 degrees, in chains, but no
// feature; a cube refined linearly keeps all of its 12 x 16 edges.
TEST(Features, NoiseIsNotAFeatureButACubesEdgesAre) {
  const TriMesh noisy = subdivide(shapes::icosahedron(), 3, Scheme::Loop, 0.05, 3);
  int sharpPairs = 0;
  for (Eigen::Index f = 0; f < noisy.F.rows(); ++f)
    for (Eigen::Index g = f + 1; g < noisy.F.rows(); ++g) {
      int shared = 0;
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) shared += noisy.F(f, i) == noisy.F(g, j);
      if (shared == 2 && faceNormal(noisy, f).normalized().dot(faceNormal(noisy, g).normalized()) <
                             std::cos(70.0 * 3.14159265358979 / 180))
        ++sharpPairs;
    }
  ASSERT_GE(sharpPairs, 4);  // the precondition: face pairs as sharp as a feature
  EXPECT_TRUE(detectFeatures(noisy, 70.0).edges.empty());

  const TriMesh cube = subdivide(unitCube(), 4, Scheme::Linear);
  EXPECT_EQ(detectFeatures(cube, 70.0).edges.size(), 12u * 16u);
}

namespace {

// A plate with a horn: one triangle of a flat 8 x 8 plate of unit cells split from a
// point raised 0.5 above it and leaning 4 units over the plate, a thin three-sided
// cone (its face angles sum to about 30 degrees) like the ears of docs/REMESH.md's
// decimated knight.
struct Horn {
  TriMesh mesh;
  int tip = -1;
};

Horn leaningHorn() {
  const int n = 8;
  TriMesh plate = raggedPlate(n);
  // A straight edge: the ragged plate's spikes put back in line (y = the row).
  for (Eigen::Index v = 0; v < plate.V.rows(); ++v)
    plate.V(v, 1) = static_cast<double>(v / (n + 1));
  const int f = 2 * (3 * n + 3);  // a face in the middle of the plate
  const Eigen::RowVector3i abc = plate.F.row(f);
  Horn h;
  h.tip = static_cast<int>(plate.V.rows());
  h.mesh.V.resize(plate.V.rows() + 1, 3);
  h.mesh.V << plate.V, (plate.V.row(abc(0)) + plate.V.row(abc(1)) + plate.V.row(abc(2))) / 3 +
                           Eigen::RowVector3d(4.0, 0.0, 0.5);
  h.mesh.F.resize(plate.F.rows() + 2, 3);
  h.mesh.F << plate.F, Eigen::RowVector3i(abc(1), abc(2), h.tip),
      Eigen::RowVector3i(abc(2), abc(0), h.tip);
  h.mesh.F.row(f) << abc(0), abc(1), h.tip;
  return h;
}

}  // namespace

// A tip stays a base vertex (a corner) even where one of its faces looks like a scan's
// fold: a horn's faces face sideways of the surface around it, and the one facing the
// plate faces against the sum of its corners' normals. Taken for noise, the knight's ear
// tips went first and the grid cut them off (1.49% of the diagonal from the input).
TEST(Features, ATipIsACornerThoughOneOfItsFacesLooksFolded) {
  const Horn h = leaningHorn();
  const Points normals = vertexNormalSums(h.mesh);
  int looksFolded = 0;
  for (Eigen::Index f = h.mesh.F.rows() - 3; f < h.mesh.F.rows(); ++f) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (int k = 0; k < 3; ++k) sum += normals.row(h.mesh.F(f, k)).transpose();
    looksFolded += faceNormal(h.mesh, f).dot(sum) <= 0;
  }
  ASSERT_EQ(looksFolded, 1);  // the case this test is about
  const Features features = detectFeatures(h.mesh, 70.0, 0.0);
  EXPECT_TRUE(features.tip[h.tip]);
  EXPECT_FALSE(features.fold[h.tip]);
  EXPECT_TRUE(features.corner[h.tip]);
  EXPECT_EQ(std::count(features.tip.begin(), features.tip.end(), 1), 1);
}

// A feature line on its own is kept only as long as the length asked for: a plate of
// n x n unit cells bent by 90 degrees along x = n / 2 has one crease, n edges long, from
// rim to rim. remesh() asks for a base edge where the base would otherwise be over size:
// a base following a shorter line would need two vertices closer together than its own
// edges. A cube's edges, which meet at its corners, are no line on its own.
TEST(Features, ALineOnItsOwnShorterThanAskedIsNoFeature) {
  const int n = 12;
  TriMesh plate = raggedPlate(n);
  for (Eigen::Index v = 0; v < plate.V.rows(); ++v) {
    plate.V(v, 1) = static_cast<double>(v / (n + 1));  // a straight rim
    if (plate.V(v, 0) > n / 2) {
      plate.V(v, 2) = plate.V(v, 0) - n / 2;
      plate.V(v, 0) = n / 2;
    }
  }
  EXPECT_EQ(detectFeatures(plate, 70.0).edges.size(), static_cast<std::size_t>(n));
  EXPECT_EQ(detectFeatures(plate, 70.0, 0.0, n - 0.5).edges.size(), static_cast<std::size_t>(n));
  EXPECT_TRUE(detectFeatures(plate, 70.0, 0.0, n + 0.5).edges.empty());

  const TriMesh cube = subdivide(unitCube(), 4, Scheme::Linear);
  EXPECT_EQ(detectFeatures(cube, 70.0, 0.0, 10.0).edges.size(), 12u * 16u);
}
