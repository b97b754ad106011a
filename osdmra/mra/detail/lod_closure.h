// The red/green closure of level-of-detail meshes over the hierarchy (lod.h explains
// the rules). Internal: extractLod, saturate, lodTriangleCounts and the
// rate-distortion order (selection.h) share it.
#pragma once

#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "osdmra/base/error.h"
#include "osdmra/subdivision/hierarchy.h"

namespace osdmra::detail {

// red_[j][f] is when face f of M^j turned red (split 1-to-4; j < J only: level-J faces
// are never split), in the clock of the caller (setTime), or kNever. One extraction
// uses one time; lodTriangleCounts grows the mask one coefficient per tick. With a
// log, every face that turns red is also recorded there, so that a caller can try a
// seed and take it back (unmark) or see exactly what it changed.
class LodClosure {
 public:
  static constexpr int kNever = std::numeric_limits<int>::max();

  explicit LodClosure(const Hierarchy& h) : h_(h), J_(h.levels()), red_(J_), conn_(J_, nullptr) {
    for (int j = 0; j < J_; ++j) red_[j].assign(static_cast<std::size_t>(h.numFaces(j)), kNever);
  }

  const Hierarchy& hierarchy() const { return h_; }
  int levels() const { return J_; }
  void setTime(int t) { now_ = t; }
  /// Faces that turn red from now on are appended to `log` (null: no log).
  void setLog(std::vector<std::pair<int, int>>* log) { log_ = log; }
  /// When face f of M^j turned red, or kNever (always kNever at level J).
  int redTime(int j, int f) const { return j < J_ ? red_[j][f] : kNever; }
  bool isRed(int j, int f) const { return j < J_ && red_[j][f] != kNever; }
  /// A face is in the mesh's tree when its parent is split (base faces always are).
  bool exists(int j, int f) const { return j == 0 || red_[j - 1][f >> 2] != kNever; }
  /// Takes back a face that turned red (only valid in the reverse order of the log,
  /// or for a whole log at once, after close()).
  void unmark(int j, int f) { red_[j][f] = kNever; }

  // Both level-j faces on edge {a, b} of M^j: the kept coefficient's vertex is that
  // edge's midpoint, which exists in the mesh only once they are split.
  void seed(int j, int a, int b) {
    const Connectivity& c = conn(j);
    int he = -1;
    for (int x : c.fan(a))
      if (c.to(x) == b) he = x;
    if (he < 0)
      for (int x : c.fan(b))
        if (c.to(x) == a) he = x;
    if (he < 0) throw Error("extractLod: hierarchy edge missing at level " + std::to_string(j));
    markRed(j, he / 3);
    if (c.twin(he) >= 0) markRed(j, c.twin(he) / 3);
  }

  // Applies the closure rules until nothing changes. Each face is processed once,
  // when it turns red, and every rule is re-checked exactly where its premises can
  // have changed, so the work is linear in the faces touched.
  void close() {
    while (!work_.empty()) {
      const auto [j, f] = work_.back();
      work_.pop_back();
      // (i) the face must exist: its parent is split. (Rule ii below implies it,
      // since every face has a sibling across one of its edges; kept for clarity.)
      if (j > 0) markRed(j - 1, f >> 2);
      const Connectivity& c = conn(j);
      for (int i = 0; i < 3; ++i) {
        const int t = c.twin(3 * f + i);
        if (t < 0) continue;
        const int g = t / 3;
        // (ii) the neighbour across must exist, so the split edge is matched by a
        // green split at the same level rather than by a coarser, unsplit edge.
        if (j > 0) markRed(j - 1, g >> 2);
        // (iii) the neighbour may now have two split edges.
        check(j, g);
      }
      // The children now exist; any of them may already see two red neighbours.
      if (j + 1 < J_)
        for (int k = 0; k < 4; ++k) check(j + 1, 4 * f + k);
    }
  }

  // Edge index (0..2) of face f of M^j across which the neighbour is red; -1 for
  // none. After close() there is at most one (rule iii).
  int redEdge(int j, int f) {
    if (j >= J_ || !conn_[j]) return -1;  // no red face at level j (see conn())
    const Connectivity& c = conn(j);
    for (int i = 0; i < 3; ++i) {
      const int t = c.twin(3 * f + i);
      if (t >= 0 && red_[j][t / 3] != kNever) return i;
    }
    return -1;
  }

  // Connectivity is fetched only when a face of the level is processed or checked,
  // so a level whose pointer is still null has no red face, and an empty mask
  // builds none.
  const Connectivity& conn(int j) {
    if (!conn_[j]) conn_[j] = &h_.connectivity(j);
    return *conn_[j];
  }

 private:
  void markRed(int j, int f) {
    if (red_[j][f] != kNever) return;
    red_[j][f] = now_;
    work_.emplace_back(j, f);
    if (log_) log_->emplace_back(j, f);
  }

  // Rule (iii) for face g of M^j.
  void check(int j, int g) {
    if (j >= J_ || red_[j][g] != kNever || !exists(j, g)) return;
    const Connectivity& c = conn(j);
    int n = 0;
    for (int i = 0; i < 3; ++i) {
      const int t = c.twin(3 * g + i);
      if (t >= 0 && red_[j][t / 3] != kNever) ++n;
    }
    if (n >= 2) markRed(j, g);
  }

  const Hierarchy& h_;
  int J_;
  std::vector<std::vector<int>> red_;
  std::vector<const Connectivity*> conn_;
  std::vector<std::pair<int, int>> work_;
  std::vector<std::pair<int, int>>* log_ = nullptr;
  int now_ = 0;
};

}  // namespace osdmra::detail
