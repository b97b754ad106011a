#include "osdmra/mra/selection.h"

#include <algorithm>
#include <limits>
#include <queue>
#include <string>

#include "osdmra/base/error.h"
#include "osdmra/mra/detail/lod_closure.h"

namespace osdmra {

const char* selectionName(Selection s) {
  return s == Selection::RateDistortion ? "rd" : "importance";
}

Selection parseSelection(const std::string& name) {
  if (name == "rd" || name == "rate-distortion") return Selection::RateDistortion;
  if (name == "importance") return Selection::Importance;
  throw Error("selection must be rd or importance, got '" + name + "'");
}

CoefficientOrder importanceOrder(const std::vector<Eigen::VectorXd>& importance) {
  CoefficientOrder order;
  for (std::size_t j = 0; j < importance.size(); ++j)
    for (Eigen::Index i = 0; i < importance[j].size(); ++i)
      order.emplace_back(static_cast<int>(j), static_cast<int>(i));
  // Stable: ties stay in (level, index) order.
  std::stable_sort(order.begin(), order.end(), [&](const auto& a, const auto& b) {
    return importance[a.first](a.second) > importance[b.first](b.second);
  });
  return order;
}

namespace {

using detail::LodClosure;
using Face = std::pair<int, int>;  // (level, face)

// What seeding one coefficient into the current closure would bring.
struct Trial {
  double gain = 0;     // importance^2 of the coefficients it makes available
  long long cost = 0;  // triangles it adds
  double ratio() const {
    return cost > 0 ? gain / static_cast<double>(cost) : std::numeric_limits<double>::infinity();
  }
};

struct Candidate {
  double ratio;
  int level, index;
  unsigned version;
};

// Priority: larger ratio; ties to the coarser level, then the lower index.
struct Lower {
  bool operator()(const Candidate& a, const Candidate& b) const {
    if (a.ratio != b.ratio) return a.ratio < b.ratio;
    if (a.level != b.level) return a.level > b.level;
    return a.index > b.index;
  }
};

class Greedy {
 public:
  Greedy(const Hierarchy& h, const std::vector<Eigen::VectorXd>& importance)
      : h_(h), imp_(importance), closure_(h), J_(h.levels()) {
    for (int j = 0; j < J_; ++j) {
      const std::size_t n = static_cast<std::size_t>(imp_[j].size());
      taken_.emplace_back(n, 0);
      version_.emplace_back(n, 0u);
      stamp_.emplace_back(n, 0u);
    }
    for (int j = 0; j <= J_; ++j)
      faceStamp_.emplace_back(static_cast<std::size_t>(h.numFaces(j)), 0u);
    closure_.setTime(1);
    closure_.setLog(&log_);
  }

  CoefficientOrder run() {
    if (J_ == 0) return {};
    // The base level's coefficients start; a finer one enters when a face on its edge
    // first exists (requeueAround), so every coefficient is queued in the end (each
    // base coefficient is taken, which splits every base face, and so on down).
    // Measuring deep coefficients against the empty mesh first (a chain of forced
    // splits each) cost 5x the time on the meshes measured and changed no choice.
    for (int e = 0; e < static_cast<int>(imp_[0].size()); ++e) push(0, e);
    while (!queue_.empty()) {
      const Candidate c = queue_.top();
      queue_.pop();
      if (stale(c)) continue;
      const double ratio = evaluate(c.level, c.index).ratio();
      dropStale();
      // Still the best against the current mesh (the others' ratios may be stale but
      // were true once): take it; otherwise queue it at its present value.
      if (queue_.empty() || ratio >= queue_.top().ratio)
        accept(c.level, c.index);
      else
        queue_.push({ratio, c.level, c.index, ++version_[c.level][c.index]});
    }
    return std::move(order_);
  }

 private:
  bool stale(const Candidate& c) const {
    return taken_[c.level][c.index] || c.version != version_[c.level][c.index];
  }
  void dropStale() {
    while (!queue_.empty() && stale(queue_.top())) queue_.pop();
  }
  void push(int j, int e) { queue_.push({evaluate(j, e).ratio(), j, e, ++version_[j][e]}); }

  // Index of the coefficient at the midpoint of halfedge h of M^j, read off the child
  // layout of hierarchy.h (as extractLod does).
  int coefficientOf(int j, int he) const {
    const Faces& fine = h_.faces(j + 1);
    const int f = he / 3, i = he % 3;
    const int m = i == 0 ? fine(4 * f, 1) : i == 1 ? fine(4 * f + 1, 2) : fine(4 * f, 2);
    return m - h_.numVertices(j);
  }

  // Triangles face f of M^j puts in the mesh: none unless it exists and is not split,
  // two when it is halved by a green split (a neighbour is red), else one.
  int triangles(int j, int f) {
    if (!closure_.exists(j, f) || closure_.isRed(j, f)) return 0;
    if (j == J_) return 1;
    const Connectivity& c = closure_.conn(j);
    for (int i = 0; i < 3; ++i) {
      const int t = c.twin(3 * f + i);
      if (t >= 0 && closure_.isRed(j, t / 3)) return 2;
    }
    return 1;
  }

  // The faces whose triangle count the logged faces can change: themselves, their
  // children (which now exist) and their neighbours (which may turn green).
  void collectAffected() {
    affected_.clear();
    ++faceClock_;
    auto add = [&](int j, int f) {
      if (faceStamp_[j][f] == faceClock_) return;
      faceStamp_[j][f] = faceClock_;
      affected_.emplace_back(j, f);
    };
    for (const auto& [j, f] : log_) {
      add(j, f);
      for (int k = 0; k < 4; ++k) add(j + 1, 4 * f + k);
      const Connectivity& c = closure_.conn(j);
      for (int i = 0; i < 3; ++i) {
        const int t = c.twin(3 * f + i);
        if (t >= 0) add(j, t / 3);
      }
    }
  }

  long long affectedTriangles() {
    long long n = 0;
    for (const auto& [j, f] : affected_) n += triangles(j, f);
    return n;
  }

  // Calls visit(j, e) once for every coefficient not yet taken whose edge has both
  // faces split now and had not before the logged faces turned red.
  template <class Visit>
  void forEachFreed(Visit visit) {
    ++clock_;
    for (const auto& [j, f] : log_) {
      const Connectivity& c = closure_.conn(j);
      for (int i = 0; i < 3; ++i) {
        const int he = 3 * f + i, t = c.twin(he);
        if (t >= 0 && !closure_.isRed(j, t / 3)) continue;
        const int e = coefficientOf(j, he);
        if (taken_[j][e] || stamp_[j][e] == clock_) continue;
        stamp_[j][e] = clock_;
        visit(j, e);
      }
    }
  }

  void seed(int j, int e) {
    log_.clear();
    const auto ab = h_.parentEdge(j, e);
    closure_.seed(j, ab[0], ab[1]);
    closure_.close();
  }

  // Gain and cost of seeding (j, e), leaving the closure as it was.
  Trial evaluate(int j, int e) {
    Trial t;
    seed(j, e);
    collectAffected();
    t.cost = affectedTriangles();
    forEachFreed([&](int l, int k) { t.gain += imp_[l](k) * imp_[l](k); });
    for (const auto& [l, f] : log_) closure_.unmark(l, f);
    t.cost -= affectedTriangles();
    return t;
  }

  // Seeds (j, e) for good: lists it and everything it frees, most important first,
  // and re-measures the candidates whose cost it changed.
  void accept(int j, int e) {
    seed(j, e);
    freed_.clear();
    forEachFreed([&](int l, int k) { freed_.emplace_back(l, k); });
    std::stable_sort(freed_.begin(), freed_.end(), [&](const auto& a, const auto& b) {
      return imp_[a.first](a.second) > imp_[b.first](b.second);
    });
    // The seed first, so a prefix that ends inside the group is still a closed mask.
    order_.emplace_back(j, e);
    taken_[j][e] = 1;
    for (const auto& c : freed_)
      if (!taken_[c.first][c.second]) {
        taken_[c.first][c.second] = 1;
        order_.push_back(c);
      }
    requeueAround();
  }

  // The coefficients on the edges of the new faces (the children of newly split
  // faces) and of the split faces' neighbours now cost fewer triangles.
  void requeueAround() {
    const std::vector<Face> changed = log_;
    ++clock_;
    auto requeueEdgesOf = [&](int j, int f) {
      if (j >= J_) return;
      for (int i = 0; i < 3; ++i) {
        const int e = coefficientOf(j, 3 * f + i);
        if (taken_[j][e] || stamp_[j][e] == clock_) continue;
        stamp_[j][e] = clock_;
        requeue_.emplace_back(j, e);
      }
    };
    requeue_.clear();
    for (const auto& [j, f] : changed) {
      for (int k = 0; k < 4; ++k) requeueEdgesOf(j + 1, 4 * f + k);
      const Connectivity& c = closure_.conn(j);
      for (int i = 0; i < 3; ++i) {
        const int t = c.twin(3 * f + i);
        if (t >= 0 && !closure_.isRed(j, t / 3)) requeueEdgesOf(j, t / 3);
      }
    }
    for (const auto& [j, e] : requeue_) push(j, e);
  }

  const Hierarchy& h_;
  const std::vector<Eigen::VectorXd>& imp_;
  LodClosure closure_;
  int J_;
  std::vector<std::vector<char>> taken_;
  std::vector<std::vector<unsigned>> version_, stamp_, faceStamp_;
  unsigned clock_ = 0, faceClock_ = 0;
  std::priority_queue<Candidate, std::vector<Candidate>, Lower> queue_;
  std::vector<Face> log_, affected_, freed_, requeue_;
  CoefficientOrder order_;
};

}  // namespace

CoefficientOrder rateDistortionOrder(const Hierarchy& h,
                                     const std::vector<Eigen::VectorXd>& importance) {
  const int J = h.levels();
  if (static_cast<int>(importance.size()) != J)
    throw Error("rateDistortionOrder: importance has " + std::to_string(importance.size()) +
                " levels, the hierarchy " + std::to_string(J));
  for (int j = 0; j < J; ++j)
    if (importance[j].size() != h.numVertices(j + 1) - h.numVertices(j))
      throw Error("rateDistortionOrder: importance of level " + std::to_string(j) + " has " +
                  std::to_string(importance[j].size()) + " entries, expected " +
                  std::to_string(h.numVertices(j + 1) - h.numVertices(j)));
  return Greedy(h, importance).run();
}

}  // namespace osdmra
