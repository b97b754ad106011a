#include "osdmra/subdivision/recovery.h"

#include <algorithm>
#include <atomic>
#include <numeric>
#include <sstream>

#include "osdmra/mesh/connectivity.h"
#include "osdmra/base/error.h"
#include "osdmra/base/detail/parallel.h"

namespace osdmra {

namespace {

enum Label : signed char { Unknown = 0, Old = 1, New = 2 };

std::uint64_t pairKey(int a, int b) {
  if (a > b) std::swap(a, b);
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) |
         static_cast<std::uint32_t>(b);
}

bool regular(const VertexRings& c, int v) {
  return c.isBoundaryVertex(v) ? c.valence(v) == 4 : c.valence(v) == 6;
}

// Union-find over vertices that several threads may update at once: every link
// goes from a root to a smaller root by compare-and-swap, so parent[x] <= x always,
// and each class ends up rooted at its smallest vertex whatever the interleaving.
// Path halving only ever moves a pointer further up the same tree.
struct Classes {
  std::vector<std::atomic<int>> parent;
  explicit Classes(int n) : parent(n) {
    forChunks(n, numChunks(n), [&](int, int begin, int end) {
      for (int v = begin; v < end; ++v) parent[v].store(v, std::memory_order_relaxed);
    });
  }
  int find(int x) {
    int p = parent[x].load(std::memory_order_relaxed);
    while (p != x) {
      const int grand = parent[p].load(std::memory_order_relaxed);
      if (grand != p) parent[x].compare_exchange_weak(p, grand, std::memory_order_relaxed);
      x = grand;
      p = parent[x].load(std::memory_order_relaxed);
    }
    return x;
  }
  void unite(int a, int b) {
    while (true) {
      a = find(a);
      b = find(b);
      if (a == b) return;
      if (a < b) std::swap(a, b);
      int expected = a;
      if (parent[a].compare_exchange_strong(expected, b, std::memory_order_relaxed)) return;
    }
  }
};

// Checks vertex v against a labelling: an old vertex has only new neighbours; a new
// one is regular, with exactly two old neighbours, opposite each other in its ring
// (the two ends of its ring path on a boundary), which are its parents. `lonely` is
// set when v is new without any old neighbour, as in a component no old vertex of the
// labelling reaches.
bool checkVertex(const VertexRings& c, int v, const std::vector<signed char>& label,
                 std::array<int, 2>& parents, bool& lonely, std::string& why) {
  const IndexSpan ring = c.ring(v);
  if (label[v] == Old) {
    for (int m : ring)
      if (label[m] == Old) {
        why = "vertices " + std::to_string(v) + " and " + std::to_string(m) +
              " would both be old but are adjacent";
        return false;
      }
    return true;
  }
  if (!regular(c, v)) {
    why = "vertex " + std::to_string(v) + " (valence " + std::to_string(ring.size()) +
          ") would be an edge midpoint but is not regular";
    return false;
  }
  int numOld = 0, first = -1;
  for (int i = 0; i < ring.size(); ++i)
    if (label[ring[i]] == Old && numOld++ == 0) first = i;
  lonely = numOld == 0;
  const bool boundary = c.isBoundaryVertex(v);
  if (numOld != 2 || first > 2 || label[ring[first + 3]] != Old || (boundary && first != 0)) {
    why = "vertex " + std::to_string(v) + " would be an edge midpoint but has " +
          std::to_string(numOld) + " old neighbours" +
          (numOld == 2 ? std::string(boundary ? " not at the ends of its boundary edge"
                                              : " not opposite each other")
                       : std::string());
    return false;
  }
  parents = {ring[first], ring[first + 3]};
  return true;
}

// Labels every vertex old or new. Two neighbours opposite each other across a
// regular vertex are both old or both new (in a regular patch they lie on one line
// of the lattice, two edges apart; across a midpoint they are its parents or two
// midpoints), so one union-find pass over the rings groups the vertices into classes
// that never mix old and new, and the old vertices of a component are one class:
// neighbouring ones are opposite across their midpoint. Extraordinary vertices are
// old, which names the old class; a component without any tries the class of its
// smallest vertex, then those of that vertex's neighbours in ring order, and keeps
// the first that checks out (so the base is chosen consistently). Every vertex is
// then checked, which is what makes the labelling trustworthy, whatever produced it.
bool label(const VertexRings& c, std::vector<signed char>& label,
           std::vector<std::array<int, 2>>& parents, bool& arbitrary, std::string& why) {
  const int n = c.numVertices();
  const int chunks = numChunks(n);
  Classes classes(n);
  forChunks(n, chunks, [&](int, int begin, int end) {
    for (int v = begin; v < end; ++v) {
      constexpr int kAhead = 8;  // the finds below read random places: ask early
      if (v + kAhead < end)
        for (int w : c.ring(v + kAhead)) __builtin_prefetch(&classes.parent[w]);
      if (!regular(c, v)) continue;
      const IndexSpan ring = c.ring(v);
      if (c.isBoundaryVertex(v)) {
        classes.unite(ring[0], ring[3]);
      } else {
        for (int i = 0; i < 3; ++i) classes.unite(ring[i], ring[i + 3]);
      }
    }
  });
  std::vector<std::uint8_t> oldClass(n, 0);
  for (int v = 0; v < n; ++v)
    if (!regular(c, v)) oldClass[classes.find(v)] = 1;
  forChunks(n, chunks, [&](int, int begin, int end) {
    for (int v = begin; v < end; ++v) label[v] = oldClass[classes.find(v)] ? Old : New;
  });

  // Check every vertex; report the first failure in vertex order, as a serial pass
  // would, unless it is only a lonely new vertex (handled below).
  struct Failure {
    int vertex = -1;
    std::string why;
    bool anyLonely = false;
  };
  std::vector<Failure> failures(chunks);
  forChunks(n, chunks, [&](int chunk, int begin, int end) {
    Failure& f = failures[chunk];
    for (int v = begin; v < end; ++v) {
      bool lonely = false;
      if (!checkVertex(c, v, label, parents[v], lonely, f.why)) {
        if (!lonely) {
          f.vertex = v;
          return;
        }
        f.anyLonely = true;
      }
    }
  });
  bool anyLonely = false;
  for (const Failure& f : failures) {
    if (f.vertex >= 0) {
      why = f.why;
      return false;
    }
    anyLonely = anyLonely || f.anyLonely;
  }
  if (!anyLonely) return true;

  // Vertices without an old neighbour: each must lie in a component that has no
  // extraordinary vertex (no old vertex at all so far).
  std::vector<char> inComponent(n, 0);
  for (int v0 = 0; v0 < n; ++v0) {
    if (label[v0] != New || parents[v0][0] >= 0) continue;
    std::vector<int> component{v0};
    inComponent[v0] = 1;
    for (std::size_t i = 0; i < component.size(); ++i)
      for (int w : c.ring(component[i])) {
        if (label[w] == Old) {
          why = "vertex " + std::to_string(v0) + " is neither old nor a midpoint";
          return false;
        }
        if (!inComponent[w]) {
          inComponent[w] = 1;
          component.push_back(w);
        }
      }
    std::vector<int> candidates{classes.find(v0)};
    for (int w : c.ring(v0))
      if (std::find(candidates.begin(), candidates.end(), classes.find(w)) == candidates.end())
        candidates.push_back(classes.find(w));
    std::string first;
    bool ok = false;
    for (int root : candidates) {
      for (int w : component) label[w] = classes.find(w) == root ? Old : New;
      ok = true;
      std::string w;
      for (int u : component) {
        bool lonely = false;
        if (!checkVertex(c, u, label, parents[u], lonely, w)) {
          ok = false;
          break;
        }
      }
      if (ok) break;
      if (first.empty()) first = w;
    }
    if (!ok) {
      why = first;
      return false;
    }
    arbitrary = true;
  }
  return true;
}

// Peels one round off the mesh (F, c). On success fills the round and the coarse
// faces; the caller checks that the coarse mesh is a manifold with one edge per
// midpoint, which completes the proof that splitting it gives back F exactly.
bool peel(const Faces& F, const VertexRings& c, Faces& coarse, int& coarseCount,
          Recovery::Round& round, std::string& why, bool& arbitrary) {
  const int n = c.numVertices();
  if (F.rows() % 4 != 0) {
    why = "the face count " + std::to_string(F.rows()) + " is not a multiple of 4";
    return false;
  }
  if (c.firstNonManifoldVertex >= 0 || c.firstIsolatedVertex >= 0) {
    why = "the mesh is not a manifold (at vertex " +
          std::to_string(std::max(c.firstNonManifoldVertex, c.firstIsolatedVertex)) + ")";
    return false;
  }
  std::vector<signed char> labels(n, Unknown);
  round.parents.assign(n, {-1, -1});  // input indices until the coarse numbering
  if (!label(c, labels, round.parents, arbitrary, why)) return false;

  // Coarse numbering: old vertices in input order.
  round.coarseOf.assign(n, -1);
  coarseCount = 0;
  for (int v = 0; v < n; ++v)
    if (labels[v] == Old) round.coarseOf[v] = coarseCount++;

  // The coarse faces, from the centre faces seen around each midpoint m. With its
  // parents p0 = ring[i] and p1 = ring[i+3], the face (m, ring[i+1], ring[i+2]) is the
  // centre of the coarse triangle (p0, q, p1) when ring[i+1] is the midpoint of p0
  // and some q and ring[i+2] that of q and p1; the same with p0 and p1 exchanged for
  // the face on the other side (a boundary midpoint has one). That is all there is to
  // check: in a labelling that passed checkVertex the three corner faces of such a
  // centre are in the input too (m's ring gives (m, p0, ring[i+1]) and
  // (m, ring[i+2], p1); ring[i+1]'s ring, ordered the same way, holds the one at q),
  // and they lie across the centre's edges, so they are distinct. Each centre is
  // taken from its smallest midpoint; with one centre per four faces the input is
  // exactly the split of the coarse faces. The caller checks that those make a
  // manifold with one edge per midpoint.
  // Parents as coarse indices from here on (the reads below then stay in one array).
  std::vector<std::array<int, 2>>& parents = round.parents;
  const int chunks = numChunks(n);
  forChunks(n, chunks, [&](int, int begin, int end) {
    for (int v = begin; v < end; ++v)
      if (labels[v] == New)
        parents[v] = {round.coarseOf[parents[v][0]], round.coarseOf[parents[v][1]]};
  });
  struct Centres {
    std::vector<int> corners;  // three coarse indices per centre
    std::string why;
  };
  std::vector<Centres> found(chunks);
  forChunks(n, chunks, [&](int chunk, int begin, int end) {
    Centres& out = found[chunk];
    out.corners.reserve(static_cast<std::size_t>(end - begin) * 3 / 2);
    for (int m = begin; m < end; ++m) {
      // The parents of the next midpoints' neighbours are random reads: ask early.
      constexpr int kAhead = 8;
      if (m + kAhead < end && labels[m + kAhead] == New)
        for (int w : c.ring(m + kAhead)) __builtin_prefetch(&parents[w]);
      if (labels[m] != New) continue;
      const IndexSpan ring = c.ring(m);
      // checkVertex took the old neighbour that comes first in ring order as the
      // first parent.
      const int i0 = labels[ring[0]] == Old ? 0 : labels[ring[1]] == Old ? 1 : 2;
      for (int side = 0; side < (c.isBoundaryVertex(m) ? 1 : 2); ++side) {
        const int i = i0 + 3 * side;
        const int x = ring[(i + 1) % 6], y = ring[(i + 2) % 6];
        if (x < m || y < m) continue;  // taken from its smallest midpoint
        const int p0 = parents[m][side], p1 = parents[m][1 - side];
        const std::array<int, 2>& px = parents[x];
        const int q = px[0] == p0 ? px[1] : px[1] == p0 ? px[0] : -1;
        if (q < 0 || pairKey(parents[y][0], parents[y][1]) != pairKey(q, p1)) {
          out.why = "the face (" + std::to_string(m) + ", " + std::to_string(x) + ", " +
                    std::to_string(y) + ") does not sit in the middle of a split triangle";
          return;
        }
        out.corners.insert(out.corners.end(), {p0, q, p1});
      }
    }
  });
  std::size_t total = 0;
  for (const Centres& f : found) {
    if (!f.why.empty()) {
      why = f.why;
      return false;
    }
    total += f.corners.size() / 3;
  }
  if (4 * total != static_cast<std::size_t>(F.rows())) {
    why = "found " + std::to_string(total) + " centre triangles for " + std::to_string(F.rows()) +
          " faces (expected a quarter)";
    return false;
  }
  coarse.resize(static_cast<Eigen::Index>(total), 3);
  int* to = coarse.data();
  for (Centres& f : found) {
    to = std::copy(f.corners.begin(), f.corners.end(), to);
    std::vector<int>().swap(f.corners);
  }
  return true;
}

}  // namespace

Recovery recoverSubdivision(const Faces& F, int numVertices, int maxLevels) {
  Recovery r;
  Faces owned;  // the coarser faces, once a round is peeled
  const Faces* faces = &F;
  int n = numVertices;
  VertexRings rings(F, n);
  while (r.levels < maxLevels) {
    Faces coarse;
    int coarseCount = 0;
    Recovery::Round round;
    bool arbitrary = false;
    std::string why;
    if (!peel(*faces, rings, coarse, coarseCount, round, why, arbitrary)) {
      r.stopReason = why;
      break;
    }
    VertexRings coarseRings(coarse, coarseCount);
    if (coarseRings.firstNonManifoldVertex >= 0) {
      r.stopReason = "the coarser mesh would not be a manifold (at its vertex " +
                     std::to_string(coarseRings.firstNonManifoldVertex) + ")";
      break;
    }
    // One midpoint per coarse edge (no edge split twice, once from each side).
    const int numNew = n - coarseCount;
    if (coarseRings.numEdgesIfManifold() != numNew) {
      r.stopReason = std::to_string(numNew) + " midpoints for " +
                     std::to_string(coarseRings.numEdgesIfManifold()) +
                     " edges of the coarser mesh";
      break;
    }
    r.arbitraryChoice = r.arbitraryChoice || arbitrary;
    r.rounds.push_back(std::move(round));
    owned = std::move(coarse);
    faces = &owned;
    rings = std::move(coarseRings);
    n = coarseCount;
    ++r.levels;
  }
  r.baseFaces = faces == &owned ? std::move(owned) : F;
  r.numBaseVertices = n;
  return r;
}

std::vector<int> canonicalIndices(const Recovery& r, const Hierarchy& h) {
  if (h.levels() != r.levels || h.numVertices(0) != r.numBaseVertices)
    throw Error("canonicalIndices: the hierarchy does not match the recovered base");
  // Coarse to fine: old vertices keep their index, new ones are their parents' midpoint.
  std::vector<int> canon(r.numBaseVertices);
  for (int v = 0; v < r.numBaseVertices; ++v) canon[v] = v;
  for (int L = 1; L <= r.levels; ++L) {
    const Recovery::Round& round = r.rounds[r.levels - L];
    std::vector<int> next(round.coarseOf.size());
    for (std::size_t v = 0; v < next.size(); ++v) {
      if (round.coarseOf[v] >= 0) {
        next[v] = canon[round.coarseOf[v]];
      } else {
        next[v] = h.midpoint(L - 1, canon[round.parents[v][0]], canon[round.parents[v][1]]);
        if (next[v] < 0) throw Error("internal: recovered parents are not an edge");
      }
    }
    canon = std::move(next);
  }
  return canon;
}

CanonicalSurface canonicalSurface(const TriMesh& mesh, int levels) {
  const int n = static_cast<int>(mesh.V.rows());
  Recovery r = recoverSubdivision(mesh.F, n, levels < 0 ? 15 : levels);
  if (r.levels == 0) throw Error(describe(r));
  if (levels >= 0 && r.levels < levels)
    throw Error(describe(r) + "; " + std::to_string(levels) + " levels were asked for (level " +
                std::to_string(r.levels + 1) + " down fails: " + r.stopReason + ")");
  Hierarchy h(r.baseFaces, r.numBaseVertices, r.levels);
  const std::vector<int> canon = canonicalIndices(r, h);
  Points V(n, 3);
  bool identity = h.faces(r.levels) == mesh.F;
  for (int v = 0; v < n; ++v) {
    V.row(canon[v]) = mesh.V.row(v);
    identity = identity && canon[v] == v;
  }
  std::vector<int> inputOrder;
  Faces inputFaces;
  if (!identity) {
    inputOrder.resize(n);
    for (int v = 0; v < n; ++v) inputOrder[canon[v]] = v;
    inputFaces = mesh.F;
  }
  return CanonicalSurface{std::move(r), std::move(h), std::move(V), std::move(inputOrder),
                          std::move(inputFaces)};
}

std::string describe(const Recovery& r) {
  std::ostringstream os;
  if (r.levels == 0) {
    os << "no subdivision connectivity (" << r.stopReason << ")";
    return os.str();
  }
  os << "subdivision connectivity: " << r.levels << (r.levels == 1 ? " level" : " levels")
     << " over a base of " << r.numBaseVertices << " vertices and " << r.baseFaces.rows()
     << " faces";
  if (r.arbitraryChoice) os << " (a regular component: one of several valid bases was chosen)";
  return os.str();
}

}  // namespace osdmra
