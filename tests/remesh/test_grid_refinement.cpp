// The grid's refinement (grid_refinement.h): an undistorted map gives the uniform grid
// untouched, and a distorted but bijective map whose uniform grid folds comes out
// without a fold, its domain grid still an embedding.
#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "osdmra/remesh/grid_refinement.h"
#include "osdmra/remesh/planar.h"

using namespace osdmra::remeshing;

namespace {

// A twist of the plane about `centre`: each circle turned by an angle that falls from
// `turn` at the centre to 0 at `radius`. A bijection that keeps orientation (each circle
// maps onto itself), but points a grid step apart at different radii turn apart, so a
// grid triangle across the twist can come out clockwise.
struct Twist {
  Vec2 centre{1.0 / 3, 1.0 / 3};
  double radius = 0.3, turn = 4;
  Vec2 operator()(const Vec2& p) const {
    const Vec2 d = p - centre;
    const double r = d.norm(), s = std::max(0.0, 1 - r / radius);
    const double a = turn * s * s, c = std::cos(a), sn = std::sin(a);
    return centre + Vec2(c * d.x() - sn * d.y(), sn * d.x() + c * d.y());
  }
};

// A grid over the unit triangle sampled through `map`: points on the sides at their
// uniform places, interior ones where refineGrid() puts them.
template <class Map>
struct PlanarGrid {
  int levels, N;
  Map map;
  std::map<std::pair<int, int>, Vec2> image, domain;
  int placements = 0;

  PlanarGrid(int l, Map m) : levels(l), N(1 << l), map(m) {
    for (int i = 0; i <= N; ++i)
      for (int j = 0; i + j <= N; ++j)
        if (i == 0 || j == 0 || i + j == N) set(i, j, Vec2(double(i) / N, double(j) / N));
  }
  void set(int i, int j, const Vec2& uv) {
    domain[{i, j}] = uv;
    image[{i, j}] = map(uv);
  }
  GridCallbacks callbacks() {
    GridCallbacks g;
    g.place = [this](int i, int j, const Vec2& uv) {
      ++placements;
      set(i, j, uv);
    };
    g.folded = [this](const std::array<int, 2>& a, const std::array<int, 2>& b,
                      const std::array<int, 2>& c) {
      const Vec2 x = image.at({a[0], a[1]}), y = image.at({b[0], b[1]}), z = image.at({c[0], c[1]});
      return !(cross2(y - x, z - x) > 0);
    };
    return g;
  }
  // Counts the finest grid's triangles folded in the image, and in the domain.
  template <class Of>
  int folded(Of of) const {
    int count = 0;
    for (int i = 0; i < N; ++i)
      for (int j = 0; i + j < N; ++j)
        for (int up = 0; up < 2 && i + j + up < N; ++up) {
          const Vec2 a = up ? of.at({i + 1, j}) : of.at({i, j});
          const Vec2 b = up ? of.at({i + 1, j + 1}) : of.at({i + 1, j});
          const Vec2 c = of.at({i, j + 1});
          count += !(cross2(b - a, c - a) > 0);
        }
    return count;
  }
};

struct Affine {
  Vec2 operator()(const Vec2& p) const {
    return Vec2(2 * p.x() + 0.5 * p.y(), 0.3 * p.x() + p.y());
  }
};

TEST(GridRefinement, AnUndistortedMapGivesTheUniformGrid) {
  PlanarGrid<Affine> grid(4, Affine{});
  std::vector<Eigen::Vector2d> domain;
  EXPECT_EQ(refineGrid(4, grid.callbacks(), {}, &domain), 0);
  const int N = grid.N;
  for (int i = 1; i < N; ++i)
    for (int j = 1; i + j < N; ++j) {
      // Exactly the uniform grid's places (dyadic fractions), each placed once.
      EXPECT_EQ(grid.domain.at({i, j}), Vec2(double(i) / N, double(j) / N));
      EXPECT_EQ(domain[static_cast<std::size_t>(i) * (N + 1) + j], grid.domain.at({i, j}));
    }
  EXPECT_EQ(grid.placements, (N - 1) * (N - 2) / 2);
}

// The twist's uniform grid folds; refined, it folds fewer triangles (none over 5 radians:
// 11 at 4 levels, 23 at 5; sharper twists can leave one, which the clean-up is for), and
// its domain grid stays an embedding, the map a bijection.
TEST(GridRefinement, MendsTheFoldsOfADistortedButBijectiveMap) {
  for (double turn : {3.0, 4.0, 5.0, 6.0})
    for (int levels : {3, 4, 5}) {
      SCOPED_TRACE("turn " + std::to_string(turn) + ", levels " + std::to_string(levels));
      Twist twist;
      twist.turn = turn;
      PlanarGrid<Twist> uniform(levels, twist);
      GridRefinementOptions none;
      none.fromLevel = levels + 1;  // no level mended
      EXPECT_EQ(refineGrid(levels, uniform.callbacks(), none), 0);
      const int before = uniform.folded(uniform.image);
      EXPECT_EQ(uniform.folded(uniform.domain), 0);

      PlanarGrid<Twist> mended(levels, twist);
      const int moves = refineGrid(levels, mended.callbacks());
      const int after = mended.folded(mended.image);
      EXPECT_LE(after, before);
      if (before > 0) {
        EXPECT_GT(moves, 0);
      }
      if (turn == 5.0) {
        EXPECT_GT(before, 0);
        EXPECT_EQ(after, 0);
      }
      EXPECT_EQ(mended.folded(mended.domain), 0);
    }
}

}  // namespace
