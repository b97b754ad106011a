// The face grid (face_grid.h): a query returns every face whose bounding box meets
// the triangle's (or the box's), as brute force finds them, each once, a face much
// larger than the cells included, before and after freeze(); a bad cell size is refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <random>
#include <vector>

#include "osdmra/base/error.h"
#include "osdmra/geometry/face_grid.h"

using namespace osdmra;

TEST(FaceGrid, FindsEveryFaceWhoseBoxMeetsTheQuerysAsBruteForceDoes) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> at(-1.0, 1.0), size(0.0, 0.3);
  const int n = 300;
  Points V(3 * n, 3);
  std::vector<std::array<int, 3>> faces(n);
  for (int f = 0; f < n; ++f) {
    const Eigen::RowVector3d c(at(rng), at(rng), at(rng));
    // Face 0 spans the whole cloud: over kMaxSpan cells a side at the small cells.
    const double scale = f == 0 ? 30.0 : 1.0;
    for (int k = 0; k < 3; ++k) {
      V.row(3 * f + k) = c + scale * Eigen::RowVector3d(size(rng), size(rng), size(rng)) -
                         (f == 0 ? Eigen::RowVector3d(4.5, 4.5, 4.5) : Eigen::RowVector3d::Zero());
      faces[f][k] = 3 * f + k;
    }
  }
  auto box = [&](const std::array<int, 3>& t, int c, bool hi) {
    const double a = V(t[0], c), b = V(t[1], c), d = V(t[2], c);
    return hi ? std::max({a, b, d}) : std::min({a, b, d});
  };
  for (double cell : {0.05, 0.2, 3.0}) {
    SCOPED_TRACE(cell);
    // Half the faces laid out by freeze(), half inserted after: a query sees both.
    FaceGrid grid(V, cell);
    for (int f = 0; f < n; f += 2) grid.insert(f, faces[f]);
    grid.freeze();
    for (int f = 1; f < n; f += 2) grid.insert(f, faces[f]);
    std::vector<int> near;
    for (int q = 0; q < n; q += 7) {
      grid.near(faces[q], near);
      // The query by box, as the box of a triangle, gives the same faces.
      std::vector<int> byBox;
      Eigen::Vector3d lo, hi;
      for (int c = 0; c < 3; ++c) {
        lo[c] = box(faces[q], c, false);
        hi[c] = box(faces[q], c, true);
      }
      grid.near(lo, hi, byBox);
      std::sort(byBox.begin(), byBox.end());
      std::vector<int> sorted = near;
      std::sort(sorted.begin(), sorted.end());
      EXPECT_EQ(std::adjacent_find(sorted.begin(), sorted.end()), sorted.end());  // once each
      EXPECT_EQ(byBox, sorted);
      for (int g = 0; g < n; ++g) {
        bool meet = true;
        for (int c = 0; c < 3; ++c)
          meet = meet && box(faces[g], c, false) <= box(faces[q], c, true) &&
                 box(faces[q], c, false) <= box(faces[g], c, true);
        if (meet) {
          EXPECT_TRUE(std::binary_search(sorted.begin(), sorted.end(), g)) << q << " " << g;
        }
      }
    }
  }
  EXPECT_THROW(FaceGrid(V, 0.0), Error);
  EXPECT_THROW(FaceGrid(V, std::numeric_limits<double>::infinity()), Error);
}
