#include "osdmra/recovery.h"

#include <algorithm>
#include <sstream>

#include "osdmra/connectivity.h"
#include "osdmra/error.h"

namespace osdmra {

namespace {

enum Label : signed char { Unknown = 0, Old = 1, New = 2 };

std::uint64_t pairKey(int a, int b) {
  if (a > b) std::swap(a, b);
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) |
         static_cast<std::uint32_t>(b);
}

bool regular(const Connectivity& c, int v) {
  return c.isBoundaryVertex(v) ? c.valence(v) == 4 : c.valence(v) == 6;
}

// Labels one component from `seed` assumed old. Fills label and parent pairs;
// returns false (with `why`) on the first contradiction.
bool labelComponent(const Connectivity& c, int seed, const std::vector<int>& component,
                    std::vector<signed char>& label, std::vector<std::array<int, 2>>& parents,
                    std::string& why) {
  for (int v : component) {
    label[v] = Unknown;
    parents[v] = {-1, -1};
  }
  std::vector<int> queue{seed};
  label[seed] = Old;
  for (std::size_t qi = 0; qi < queue.size(); ++qi) {
    const int v = queue[qi];
    for (int m : c.ring(v)) {
      if (label[m] == Old) {
        why = "vertices " + std::to_string(v) + " and " + std::to_string(m) +
              " would both be old but are adjacent";
        return false;
      }
      label[m] = New;
      if (!regular(c, m)) {
        why = "vertex " + std::to_string(m) + " (valence " + std::to_string(c.valence(m)) +
              ") would be an edge midpoint but is not regular";
        return false;
      }
      const IndexSpan ring = c.ring(m);
      int pos = -1;
      for (int i = 0; i < ring.size(); ++i)
        if (ring[i] == v) pos = i;
      int w;
      if (c.isBoundaryVertex(m)) {
        // Boundary midpoint: its parents are the two ends of its ring path.
        if (pos != 0 && pos != 3) {
          why =
              "boundary vertex " + std::to_string(m) + " would be the midpoint of an interior edge";
          return false;
        }
        w = ring[3 - pos];
      } else {
        w = ring[(pos + 3) % 6];
      }
      if (label[w] == New) {
        why = "vertex " + std::to_string(w) + " would be both old and new";
        return false;
      }
      if (parents[m][0] >= 0 && pairKey(parents[m][0], parents[m][1]) != pairKey(v, w)) {
        why = "vertex " + std::to_string(m) + " would have two different parent edges";
        return false;
      }
      parents[m] = {v, w};
      if (label[w] == Unknown) {
        label[w] = Old;
        queue.push_back(w);
      }
    }
  }
  for (int v : component)
    if (label[v] == Unknown) {
      why = "vertex " + std::to_string(v) + " is neither old nor a midpoint";
      return false;
    }
  return true;
}

// Peels one round off (F, n). On success fills the coarse mesh and the round.
bool peel(const Connectivity& c, Connectivity& coarseConn, Recovery::Round& round, bool& arbitrary,
          std::string& why) {
  const Faces& F = c.faces();
  const int n = c.numVertices();
  if (F.rows() % 4 != 0) {
    why = "the face count " + std::to_string(F.rows()) + " is not a multiple of 4";
    return false;
  }
  if (c.firstNonManifoldEdgeFace >= 0 || c.firstFlippedFace >= 0 || c.firstNonManifoldVertex >= 0 ||
      c.firstIsolatedVertex >= 0) {
    why = "the mesh is not a manifold";
    return false;
  }
  std::vector<signed char> label(n, Unknown);
  std::vector<std::array<int, 2>> parents(n, {-1, -1});
  std::vector<char> seen(n, 0);
  for (int start = 0; start < n; ++start) {
    if (seen[start]) continue;
    // The component of `start`, by breadth-first search over rings.
    std::vector<int> component{start};
    seen[start] = 1;
    for (std::size_t i = 0; i < component.size(); ++i)
      for (int w : c.ring(component[i]))
        if (!seen[w]) {
          seen[w] = 1;
          component.push_back(w);
        }
    int seed = -1;
    for (int v : component)
      if (!regular(c, v) && (seed < 0 || v < seed)) seed = v;
    if (seed >= 0) {
      if (!labelComponent(c, seed, component, label, parents, why)) return false;
      continue;
    }
    // No extraordinary vertex: the smallest vertex or one of its neighbours is old.
    const int v0 = *std::min_element(component.begin(), component.end());
    std::vector<int> candidates{v0};
    for (int w : c.ring(v0)) candidates.push_back(w);
    bool ok = false;
    std::string first;
    for (int cand : candidates) {
      std::string w;
      if (labelComponent(c, cand, component, label, parents, w)) {
        ok = true;
        arbitrary = true;
        break;
      }
      if (first.empty()) first = w;
    }
    if (!ok) {
      why = first;
      return false;
    }
  }

  // Coarse numbering: old vertices in input order.
  round.coarseOf.assign(n, -1);
  int coarseCount = 0;
  for (int v = 0; v < n; ++v)
    if (label[v] == Old) round.coarseOf[v] = coarseCount++;
  round.parents.assign(n, {-1, -1});
  int numNew = 0;
  for (int v = 0; v < n; ++v)
    if (label[v] == New) {
      round.parents[v] = {round.coarseOf[parents[v][0]], round.coarseOf[parents[v][1]]};
      ++numNew;
    }

  // Coarse faces from the centre faces (m1, m2, m0) of split triangles (v0, v1, v2):
  // v0 is the parent m2 and m0 share, and so on.
  auto common = [&](int x, int y) {
    for (int a : parents[x])
      for (int b : parents[y])
        if (a == b) return a;
    return -1;
  };
  // The corner child (a, ab, ca) must be an input face: the face on halfedge a->ab.
  auto hasCorner = [&](int a, int ab, int ca) {
    for (int h : c.fan(a))
      if (c.to(h) == ab) return c.from(Connectivity::prev(h)) == ca;
    return false;
  };
  Faces coarse(F.rows() / 4, 3);
  Eigen::Index k = 0;
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const int x = F(f, 0), y = F(f, 1), z = F(f, 2);
    if (label[x] != New || label[y] != New || label[z] != New) continue;
    const int a = common(y, z), b = common(z, x), cc = common(x, y);
    if (a < 0 || b < 0 || cc < 0 || a == b || b == cc || a == cc || k == coarse.rows()) {
      why = "face " + std::to_string(f) + " does not sit in the middle of a split triangle";
      return false;
    }
    // Splitting (a, b, cc) gives back this centre face and three corner faces; with
    // one centre per quarter of the faces, that accounts for every input face.
    if (!hasCorner(a, z, y) || !hasCorner(b, x, z) || !hasCorner(cc, y, x)) {
      why = "the triangles around face " + std::to_string(f) + " are not a 1-to-4 split";
      return false;
    }
    coarse.row(k++) << round.coarseOf[a], round.coarseOf[b], round.coarseOf[cc];
  }
  if (k != coarse.rows()) {
    why = "found " + std::to_string(k) + " centre triangles for " + std::to_string(F.rows()) +
          " faces (expected a quarter)";
    return false;
  }
  coarseConn = Connectivity(coarse, coarseCount);
  if (coarseConn.firstNonManifoldEdgeFace >= 0 || coarseConn.firstFlippedFace >= 0 ||
      coarseConn.firstNonManifoldVertex >= 0 || coarseConn.firstIsolatedVertex >= 0) {
    why = "the coarser mesh would not be a manifold";
    return false;
  }
  // One midpoint per coarse edge (so no two vertices split the same edge).
  if (coarseConn.numEdges() != numNew) {
    why = std::to_string(numNew) + " midpoints for " + std::to_string(coarseConn.numEdges()) +
          " edges of the coarser mesh";
    return false;
  }
  return true;
}

}  // namespace

Recovery recoverSubdivision(const Faces& F, int numVertices, int maxLevels) {
  return recoverSubdivision(Connectivity(F, numVertices), maxLevels);
}

Recovery recoverSubdivision(const Connectivity& mesh, int maxLevels) {
  Recovery r;
  // The finest round reads the caller's connectivity; coarser ones own theirs.
  Connectivity current;
  const Connectivity* fine = &mesh;
  while (r.levels < maxLevels) {
    Connectivity coarse;
    Recovery::Round round;
    bool arbitrary = false;
    std::string why;
    if (!peel(*fine, coarse, round, arbitrary, why)) {
      r.stopReason = why;
      break;
    }
    r.arbitraryChoice = r.arbitraryChoice || arbitrary;
    r.rounds.push_back(std::move(round));
    current = std::move(coarse);
    fine = &current;
    ++r.levels;
  }
  r.baseFaces = fine->faces();
  r.numBaseVertices = fine->numVertices();
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
