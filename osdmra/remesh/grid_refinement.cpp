#include "osdmra/remesh/grid_refinement.h"

#include "osdmra/base/error.h"
#include "osdmra/remesh/planar.h"

namespace osdmra::remeshing {

namespace {

// The six neighbours of a grid point, counter-clockwise, in steps of its level.
constexpr int kDi[6] = {1, 0, -1, -1, 0, 1};
constexpr int kDj[6] = {0, 1, 1, 0, -1, -1};

class Refinement {
 public:
  Refinement(int levels, const GridCallbacks& grid, const GridRefinementOptions& options)
      : levels_(levels), N_(1 << levels), grid_(grid), options_(options) {
    domain_.resize(static_cast<std::size_t>(N_ + 1) * (N_ + 1), Vec2::Zero());
    // Dyadic fractions: the uniform grid, and its midpoints, are exact.
    for (int i = 0; i <= N_; ++i)
      for (int j = 0; i + j <= N_; ++j) at(i, j) = Vec2(double(i) / N_, double(j) / N_);
  }

  int run() {
    for (int l = 1; l <= levels_; ++l) {
      placeNewPoints(l);
      if (l >= options_.fromLevel) mendFolds(l);
    }
    return moves_;
  }
  std::vector<Vec2>& domain() { return domain_; }

 private:
  Vec2& at(int i, int j) { return domain_[static_cast<std::size_t>(i) * (N_ + 1) + j]; }

  // Level l's new interior points at the domain midpoints of the level-(l-1) edges they
  // split: along i, along j, or across the diagonal (i + 1, j - 1).
  void placeNewPoints(int l) {
    const int st = N_ >> l;
    for (int i = st; i < N_; i += st)
      for (int j = st; i + j < N_; j += st) {
        const bool oddI = (i / st) % 2 != 0, oddJ = (j / st) % 2 != 0;
        if (!oddI && !oddJ) continue;  // a point of level l-1
        const Vec2 mid = !oddJ   ? 0.5 * (at(i - st, j) + at(i + st, j))
                         : !oddI ? 0.5 * (at(i, j - st) + at(i, j + st))
                                 : 0.5 * (at(i - st, j + st) + at(i + st, j - st));
        at(i, j) = mid;
        grid_.place(i, j, mid);
      }
  }

  // How many of the six level-l triangles around (i, j) are folded.
  int foldsAround(int i, int j, int st) const {
    int folds = 0;
    for (int k = 0; k < 6; ++k) {
      const int m = (k + 1) % 6;
      folds += grid_.folded({i, j}, {i + st * kDi[k], j + st * kDj[k]},
                            {i + st * kDi[m], j + st * kDj[m]});
    }
    return folds;
  }

  // Whether (i, j) at `p` keeps every domain triangle around it counter-clockwise.
  bool keepsOrientation(int i, int j, int st, const Vec2& p) {
    for (int k = 0; k < 6; ++k) {
      const int m = (k + 1) % 6;
      if (!(cross2(at(i + st * kDi[k], j + st * kDj[k]) - p,
                   at(i + st * kDi[m], j + st * kDj[m]) - p) > 0))
        return false;
    }
    return true;
  }

  // Point (i, j) moved to the step that folds the fewest of its triangles, if fewer than
  // now; placed back where it was otherwise. True if it moved.
  bool mendPoint(int i, int j, int st) {
    const int now = foldsAround(i, j, st);
    if (now == 0) return false;
    const Vec2 from = at(i, j);
    int fewest = now;
    Vec2 best = from;
    for (double step : options_.steps)
      for (int k = 0; k < 6; ++k) {
        const Vec2 p = from + step * (at(i + st * kDi[k], j + st * kDj[k]) - from);
        if (!keepsOrientation(i, j, st, p)) continue;
        grid_.place(i, j, p);
        const int folds = foldsAround(i, j, st);
        if (folds < fewest) {
          fewest = folds;
          best = p;
        }
      }
    at(i, j) = best;
    grid_.place(i, j, best);
    return fewest < now;
  }

  // Every interior point of level l may move, new or not: only the finest grid is kept,
  // and a coarse point is often the one a fold needs moved.
  void mendFolds(int l) {
    const int st = N_ >> l;
    for (int pass = 0; pass < options_.passes; ++pass) {
      int moved = 0;
      for (int i = st; i < N_; i += st)
        for (int j = st; i + j < N_; j += st) moved += mendPoint(i, j, st);
      moves_ += moved;
      if (moved == 0) break;
    }
  }

  const int levels_, N_;
  const GridCallbacks& grid_;
  const GridRefinementOptions& options_;
  std::vector<Vec2> domain_;
  int moves_ = 0;
};

}  // namespace

int refineGrid(int levels, const GridCallbacks& grid, const GridRefinementOptions& options,
               std::vector<Eigen::Vector2d>* domain) {
  if (levels < 0 || levels > 15) throw Error("refineGrid: levels out of range");
  Refinement r(levels, grid, options);
  const int moves = r.run();
  if (domain) *domain = std::move(r.domain());
  return moves;
}

}  // namespace osdmra::remeshing
