#include "osdmra/mesh/zero_area.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cstdint>
#include <unordered_set>
#include <vector>

#include "osdmra/base/error.h"
#include "osdmra/mesh/connectivity.h"

namespace osdmra {

namespace {

using Vec3 = Eigen::Vector3d;

// A zero-area face whose shortest edge is under this fraction of its longest is a
// needle (two corners at one place), else a cap (one corner on the opposite edge).
constexpr double kNeedle = 1e-6;

Vec3 point(const TriMesh& m, int v) {
  return m.V.row(v).transpose();
}

Vec3 normalOf(const TriMesh& m, int a, int b, int c) {
  return (point(m, b) - point(m, a)).cross(point(m, c) - point(m, a));
}

bool zeroArea(const TriMesh& m, int a, int b, int c) {
  double longest = 0;
  for (const auto& [x, y] : {std::pair{a, b}, std::pair{b, c}, std::pair{c, a}})
    longest = std::max(longest, (point(m, x) - point(m, y)).squaredNorm());
  // Twice the area over the longest edge is the height: at most kZeroAreaHeight times
  // that edge.
  return normalOf(m, a, b, c).norm() <= kZeroAreaHeight * longest;
}

// One round of mending, every check reading the mesh the round started from: a flip
// waits for the next round where an earlier change of the round changed one of its two
// faces or added the edge it would add, or a collapse or drop touched one of its
// corners; a collapse or a drop waits where any change touched a vertex it reads. (A
// flip changes two faces and one edge, so the flips of several caps around one vertex,
// a polygon fanned from a corner with points along both sides next to it, go in one
// round.)
class Round {
 public:
  Round(TriMesh& m, ZeroAreaRepair& out)
      : m_(m),
        out_(out),
        conn_(m.F, static_cast<int>(m.V.rows())),
        dirty_(m.V.rows(), 0),
        hard_(m.V.rows(), 0),
        dropped_(m.F.rows(), 0),
        changed_(m.F.rows(), 0),
        mergedInto_(m.V.rows(), -1) {}

  // Mends what it can; returns how many faces it mended.
  int run() {
    int changed = 0;
    for (int f = 0; f < m_.F.rows(); ++f) {
      const int a = m_.F(f, 0), b = m_.F(f, 1), c = m_.F(f, 2);
      if (changed_[f] || !zeroArea(m_, a, b, c)) continue;
      changed += mend(f);
    }
    apply();
    return changed;
  }

 private:
  bool mend(int f) {
    int shortest = 0, longest = 0;
    double lengths[3];
    for (int i = 0; i < 3; ++i) {
      lengths[i] = (point(m_, m_.F(f, (i + 1) % 3)) - point(m_, m_.F(f, i))).norm();
      if (lengths[i] < lengths[shortest]) shortest = i;
      if (lengths[i] > lengths[longest]) longest = i;
    }
    // A face alone (a fin cut off a non-manifold edge, say) is dropped: it is no
    // surface.
    if (conn_.twin(3 * f) < 0 && conn_.twin(3 * f + 1) < 0 && conn_.twin(3 * f + 2) < 0) {
      if (dirty_[m_.F(f, 0)] || dirty_[m_.F(f, 1)] || dirty_[m_.F(f, 2)]) return false;
      dropped_[f] = 1;
      touchHard({m_.F(f, 0), m_.F(f, 1), m_.F(f, 2)});
      ++out_.dropped;
      return true;
    }
    // Halfedge 3 f + i runs from corner i to corner i + 1.
    if (lengths[shortest] <= kNeedle * lengths[longest]) return collapse(3 * f + shortest);
    return mendCap(3 * f + longest);
  }

  // The cap whose long edge is halfedge h (a -> b, m the third corner).
  bool mendCap(int h) {
    const int f = h / 3, a = conn_.from(h), b = conn_.to(h), m = conn_.to(Connectivity::next(h));
    const int t = conn_.twin(h);
    if (t < 0) {
      // On the boundary: dropped, when m is interior (else m would pinch).
      if (conn_.isBoundaryVertex(m) || dirty_[a] || dirty_[b] || dirty_[m]) return false;
      dropped_[f] = 1;
      touchHard({a, b, m});
      ++out_.dropped;
      return true;
    }
    const int g = t / 3, d = conn_.to(Connectivity::next(t));
    if (changed_[g] || hard_[a] || hard_[b] || hard_[m] || hard_[d] || d == m ||
        conn_.findEdge(m, d) >= 0 || added_.count(edgeKey(m, d)) != 0)
      return false;
    // g = (b, a, d) split at m into (a, d, m) and (d, b, m): the same surface.
    if (zeroArea(m_, a, d, m) + zeroArea(m_, d, b, m) >= 1 + zeroArea(m_, b, a, d)) return false;
    m_.F.row(f) << a, d, m;
    m_.F.row(g) << d, b, m;
    changed_[f] = changed_[g] = 1;
    added_.insert(edgeKey(m, d));
    touch({a, b, m, d});
    ++out_.flipped;
    return true;
  }

  // The needle whose short edge is halfedge h: its ends merged, where that keeps a
  // manifold and turns no face over.
  bool collapse(int h) {
    int u = conn_.from(h), w = conn_.to(h);
    const int t = conn_.twin(h);
    if (conn_.isBoundaryVertex(u) && conn_.isBoundaryVertex(w) && t >= 0)
      return false;  // an interior edge between two boundary points: a pinch
    if (conn_.isBoundaryVertex(u)) std::swap(u, w);  // the boundary end stays
    std::vector<int> opposite = {conn_.to(Connectivity::next(h))};
    if (t >= 0) opposite.push_back(conn_.to(Connectivity::next(t)));
    // Link condition: u and w share no neighbour but the far corners of their faces,
    // each of which keeps at least three neighbours.
    const IndexSpan ru = conn_.ring(u), rw = conn_.ring(w);
    for (int x : ru)
      if (x != w && std::find(rw.begin(), rw.end(), x) != rw.end() &&
          std::find(opposite.begin(), opposite.end(), x) == opposite.end())
        return false;
    for (int x : opposite)
      if (conn_.valence(x) <= 3) return false;
    if (dirty_[u] || dirty_[w]) return false;
    for (int x : ru)
      if (dirty_[x]) return false;
    for (int x : rw)
      if (dirty_[x]) return false;
    if (turnsOver(u, w)) return false;
    for (int g : facesAround(u))
      if (std::count(m_.F.row(g).data(), m_.F.row(g).data() + 3, w) > 0) dropped_[g] = 1;
    mergedInto_[u] = w;
    touchHard({u, w});
    for (int x : ru) dirty_[x] = hard_[x] = 1;
    for (int x : rw) dirty_[x] = hard_[x] = 1;
    ++out_.collapsed;
    return true;
  }

  std::vector<int> facesAround(int v) const {
    std::vector<int> out;
    for (int g : conn_.fan(v)) out.push_back(g / 3);
    return out;
  }

  // Whether moving u onto w turns a face of u's (other than those it shares with w)
  // against itself.
  bool turnsOver(int u, int w) const {
    for (int g : facesAround(u)) {
      std::array<int, 3> c = {m_.F(g, 0), m_.F(g, 1), m_.F(g, 2)};
      if (std::find(c.begin(), c.end(), w) != c.end()) continue;
      const Vec3 before = normalOf(m_, c[0], c[1], c[2]);
      for (int& x : c)
        if (x == u) x = w;
      if (normalOf(m_, c[0], c[1], c[2]).dot(before) <= 0 && before.squaredNorm() > 0) return true;
    }
    return false;
  }

  // A flip's corners: collapses and drops around them wait.
  void touch(std::initializer_list<int> vertices) {
    for (int v : vertices) dirty_[v] = 1;
  }
  // A collapse's or a drop's: every change around them waits.
  void touchHard(std::initializer_list<int> vertices) {
    for (int v : vertices) dirty_[v] = hard_[v] = 1;
  }
  static std::uint64_t edgeKey(int x, int y) {
    return static_cast<std::uint64_t>(std::min(x, y)) << 32 |
           static_cast<std::uint32_t>(std::max(x, y));
  }

  // The round's collapses and drops written into the mesh.
  void apply() {
    Faces kept(m_.F.rows(), 3);
    int n = 0;
    for (int f = 0; f < m_.F.rows(); ++f) {
      if (dropped_[f]) continue;
      for (int i = 0; i < 3; ++i) {
        const int v = m_.F(f, i);
        kept(n, i) = mergedInto_[v] >= 0 ? mergedInto_[v] : v;
      }
      ++n;
    }
    m_.F = kept.topRows(n);
  }

  TriMesh& m_;
  ZeroAreaRepair& out_;
  const Connectivity conn_;
  std::vector<char> dirty_, hard_, dropped_, changed_;
  std::unordered_set<std::uint64_t> added_;  // edges the round's flips made
  std::vector<int> mergedInto_;
};

}  // namespace

bool isZeroAreaFace(const TriMesh& mesh, int f) {
  return zeroArea(mesh, mesh.F(f, 0), mesh.F(f, 1), mesh.F(f, 2));
}

ZeroAreaRepair removeZeroAreaFaces(TriMesh& mesh) {
  ZeroAreaRepair out;
  auto count = [&] {
    int n = 0;
    for (int f = 0; f < mesh.F.rows(); ++f) n += isZeroAreaFace(mesh, f);
    return n;
  };
  const int zeroAreaFaces = count();
  if (zeroAreaFaces == 0) return out;
  try {
    validate(mesh, "");
  } catch (const Error&) {
    return out;  // validate() will say what is wrong
  }
  // Every change leaves fewer zero-area faces (a flip is made only so; a drop or a
  // collapse removes one), so there are at most as many rounds as there are such faces:
  // a fan's caps along a line go one per round.
  for (int round = 0; round <= zeroAreaFaces; ++round)
    if (Round(mesh, out).run() == 0) break;
  removeUnreferencedVertices(mesh);
  out.left = count();
  return out;
}

}  // namespace osdmra
