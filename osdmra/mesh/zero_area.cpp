#include "osdmra/mesh/zero_area.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "osdmra/base/error.h"
#include "osdmra/mesh/connectivity.h"

namespace osdmra {

namespace {

using Vec3 = Eigen::Vector3d;

// A zero-area face whose shortest edge is under this fraction of its longest is a
// needle (two corners at one place), else a cap (one corner on the opposite edge).
constexpr double kNeedle = 1e-6;

// Rounds are few once flipCaps() has run (its flips are what a fan's chain of caps
// needs); the bound only guards against changes undoing each other.
constexpr int kMaxRounds = 64;

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

// A face's shortest and longest edges (edge i runs from corner i to corner i + 1), and
// whether it is a needle (kNeedle) rather than a cap.
struct Sides {
  int shortest = 0, longest = 0;
  bool needle = false;
};

Sides sidesOf(const TriMesh& m, int f) {
  Sides s;
  double lengths[3];
  for (int i = 0; i < 3; ++i) {
    lengths[i] = (point(m, m.F(f, (i + 1) % 3)) - point(m, m.F(f, i))).norm();
    if (lengths[i] < lengths[s.shortest]) s.shortest = i;
    if (lengths[i] > lengths[s.longest]) s.longest = i;
  }
  s.needle = lengths[s.shortest] <= kNeedle * lengths[s.longest];
  return s;
}

// One round of mending: faces whose vertices an earlier change of the round touched
// wait for the next round, so that every check reads the mesh the round started from.
class Round {
 public:
  Round(TriMesh& m, ZeroAreaRepair& out)
      : m_(m),
        out_(out),
        conn_(m.F, static_cast<int>(m.V.rows())),
        dirty_(m.V.rows(), 0),
        dropped_(m.F.rows(), 0),
        mergedInto_(m.V.rows(), -1) {}

  // Mends what it can; returns how many faces it mended.
  int run() {
    int changed = 0;
    for (int f = 0; f < m_.F.rows(); ++f) {
      const int a = m_.F(f, 0), b = m_.F(f, 1), c = m_.F(f, 2);
      if (dirty_[a] || dirty_[b] || dirty_[c] || !zeroArea(m_, a, b, c)) continue;
      changed += mend(f);
    }
    apply();
    return changed;
  }

 private:
  bool mend(int f) {
    const Sides sides = sidesOf(m_, f);
    // A face alone (a fin cut off a non-manifold edge, say) is dropped: it is no
    // surface.
    if (conn_.twin(3 * f) < 0 && conn_.twin(3 * f + 1) < 0 && conn_.twin(3 * f + 2) < 0) {
      dropped_[f] = 1;
      touch({m_.F(f, 0), m_.F(f, 1), m_.F(f, 2)});
      ++out_.dropped;
      return true;
    }
    // Halfedge 3 f + i runs from corner i to corner i + 1.
    if (sides.needle) return collapse(3 * f + sides.shortest);
    return mendCap(3 * f + sides.longest);
  }

  // The cap whose long edge is halfedge h (a -> b, m the third corner).
  bool mendCap(int h) {
    const int f = h / 3, a = conn_.from(h), b = conn_.to(h), m = conn_.to(Connectivity::next(h));
    const int t = conn_.twin(h);
    if (t < 0) {
      // On the boundary: dropped, when m is interior (else m would pinch).
      if (conn_.isBoundaryVertex(m) || dirty_[m]) return false;
      dropped_[f] = 1;
      touch({a, b, m});
      ++out_.dropped;
      return true;
    }
    const int g = t / 3, d = conn_.to(Connectivity::next(t));
    if (dirty_[d] || d == m || conn_.findEdge(m, d) >= 0) return false;
    // g = (b, a, d) split at m into (a, d, m) and (d, b, m): the same surface.
    if (zeroArea(m_, a, d, m) + zeroArea(m_, d, b, m) >= 1 + zeroArea(m_, b, a, d)) return false;
    m_.F.row(f) << a, d, m;
    m_.F.row(g) << d, b, m;
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
    dirty_[u] = dirty_[w] = 1;
    for (int x : ru) dirty_[x] = 1;
    for (int x : rw) dirty_[x] = 1;
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

  void touch(std::initializer_list<int> vertices) {
    for (int v : vertices) dirty_[v] = 1;
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
  std::vector<char> dirty_, dropped_;
  std::vector<int> mergedInto_;
};

std::uint64_t halfedgeKey(int from, int to) {
  return static_cast<std::uint64_t>(static_cast<std::uint32_t>(from)) << 32 |
         static_cast<std::uint32_t>(to);
}

// Flips every cap whose flip leaves fewer zero-area faces, one after another through
// a worklist, the face of each halfedge kept in a map updated at every flip: a fan's
// chain of caps along a line (each flip makes the next cap's neighbour a triangle) goes
// in one pass, where rounds that read the mesh they started from take one cap a round.
// Each flip leaves fewer zero-area faces, so there are at most as many flips as such
// faces. Needles and caps on the boundary are left to the rounds. Returns the flips.
int flipCaps(TriMesh& m) {
  std::unordered_map<std::uint64_t, int> faceOf;
  auto link = [&](int f, bool add) {
    for (int i = 0; i < 3; ++i) {
      const std::uint64_t k = halfedgeKey(m.F(f, i), m.F(f, (i + 1) % 3));
      if (add)
        faceOf[k] = f;
      else
        faceOf.erase(k);
    }
  };
  std::vector<int> work;
  std::vector<char> queued(static_cast<std::size_t>(m.F.rows()), 0);
  auto push = [&](int f) {
    if (queued[f] || !zeroArea(m, m.F(f, 0), m.F(f, 1), m.F(f, 2))) return;
    queued[f] = 1;
    work.push_back(f);
  };
  for (int f = 0; f < m.F.rows(); ++f) link(f, true);
  for (int f = static_cast<int>(m.F.rows()) - 1; f >= 0; --f) push(f);
  int flips = 0;
  while (!work.empty()) {
    const int f = work.back();
    work.pop_back();
    queued[f] = 0;
    const std::array<int, 3> c = {m.F(f, 0), m.F(f, 1), m.F(f, 2)};
    if (!zeroArea(m, c[0], c[1], c[2])) continue;
    const Sides sides = sidesOf(m, f);
    if (sides.needle) continue;
    const int l = sides.longest;
    const int a = c[l], b = c[(l + 1) % 3], mid = c[(l + 2) % 3];
    const auto across = faceOf.find(halfedgeKey(b, a));
    if (across == faceOf.end()) continue;  // on the boundary
    const int g = across->second;
    int d = -1;
    for (int i = 0; i < 3; ++i)
      if (m.F(g, i) != a && m.F(g, i) != b) d = m.F(g, i);
    if (d < 0 || d == mid || faceOf.count(halfedgeKey(mid, d)) != 0 ||
        faceOf.count(halfedgeKey(d, mid)) != 0)
      continue;
    // g = (b, a, d) split at mid into (a, d, mid) and (d, b, mid): the same surface.
    if (zeroArea(m, a, d, mid) + zeroArea(m, d, b, mid) >= 1 + zeroArea(m, b, a, d)) continue;
    link(f, false);
    link(g, false);
    m.F.row(f) << a, d, mid;
    m.F.row(g) << d, b, mid;
    link(f, true);
    link(g, true);
    ++flips;
    for (const int h : {f, g}) {
      push(h);
      for (int i = 0; i < 3; ++i) {
        const auto next = faceOf.find(halfedgeKey(m.F(h, (i + 1) % 3), m.F(h, i)));
        if (next != faceOf.end()) push(next->second);
      }
    }
  }
  return flips;
}

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
  if (count() == 0) return out;
  try {
    validate(mesh, "");
  } catch (const Error&) {
    return out;  // validate() will say what is wrong
  }
  out.flipped += flipCaps(mesh);
  for (int round = 0; round < kMaxRounds; ++round)
    if (Round(mesh, out).run() == 0) break;
  removeUnreferencedVertices(mesh);
  out.left = count();
  return out;
}

}  // namespace osdmra
