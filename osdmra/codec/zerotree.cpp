#include "osdmra/codec/zerotree.h"

#include <algorithm>
#include <cstdlib>
#include <optional>

#include "osdmra/base/error.h"

namespace osdmra {

// ---- The tree ------------------------------------------------------------------------

namespace {

// Index in M^{j+1} of edge i of face g of M^{j+1}, read off the children of g in
// M^{j+2} (hierarchy.h: child 4g is (w0, m0, m2), child 4g+1 is (m0, w1, m1)).
int childLevelEdge(const Hierarchy& h, int j, int g, int i) {
  const Faces& F = h.faces(j + 2);
  const int m = i == 0 ? F(4 * g, 1) : i == 1 ? F(4 * g + 1, 2) : F(4 * g, 2);
  return m - h.numVertices(j + 1);
}

void addChild(std::array<int, 4>& slots, int child) {
  for (int& s : slots)
    if (s == child) return;
  for (int& s : slots)
    if (s < 0) {
      s = child;
      return;
    }
  throw Error("edge tree: an edge with more than four children or neighbours");
}

// The children of level j's edges. Face f = (v0, v1, v2) of M^j has children 4f..4f+3
// in M^{j+1}: (v0, m0, m2), (m0, v1, m1), (m2, m1, v2), (m1, m2, m0). Its edge i (from
// v_i to v_{i+1}) is halved into edge i of child i and edge i of child i+1 (mod 3),
// and the centre child's edge i is parallel to it.
std::vector<std::array<int, 4>> levelChildren(const Hierarchy& h, int j) {
  const Faces& F = h.faces(j);
  const Faces& fine = h.faces(j + 1);
  const int n = h.numVertices(j);
  std::vector<std::array<int, 4>> out(h.numVertices(j + 1) - n, {-1, -1, -1, -1});
  for (int f = 0; f < F.rows(); ++f)
    for (int i = 0; i < 3; ++i) {
      const int mid = i == 0 ? fine(4 * f, 1) : i == 1 ? fine(4 * f + 1, 2) : fine(4 * f, 2);
      std::array<int, 4>& slots = out[mid - n];
      addChild(slots, childLevelEdge(h, j, 4 * f + i, i));
      addChild(slots, childLevelEdge(h, j, 4 * f + (i + 1) % 3, i));
      addChild(slots, childLevelEdge(h, j, 4 * f + 3, i));
    }
  return out;
}

// The edges beside each edge of M^j: the two others of each triangle it borders.
std::vector<std::array<int, 4>> levelNeighbours(const Hierarchy& h, int j) {
  const Faces& F = h.faces(j);
  const Faces& fine = h.faces(j + 1);
  const int n = h.numVertices(j);
  std::vector<std::array<int, 4>> out(h.numVertices(j + 1) - n, {-1, -1, -1, -1});
  for (int f = 0; f < F.rows(); ++f) {
    const int e[3] = {fine(4 * f, 1) - n, fine(4 * f + 1, 2) - n, fine(4 * f, 2) - n};
    for (int i = 0; i < 3; ++i) {
      addChild(out[e[i]], e[(i + 1) % 3]);
      addChild(out[e[i]], e[(i + 2) % 3]);
    }
  }
  return out;
}

// The same two relations read off the face edges of a split hierarchy
// (Hierarchy::faceEdges), without looking up the finer faces: edge i of face f is
// halved into edges 3F + 2e and 3F + 2e + 1 of M^{j+1} (OpenSubdiv's numbering,
// hierarchy.cpp), and the centre child's edge i is M^{j+1}'s edge 3f + 2, 3f or 3f + 1
// for i = 0, 1, 2. The same sets as levelChildren's and levelNeighbours' (two halves
// may be listed the other way round; the coder reads them as sets).
void levelRelations(const Connectivity::FaceEdgeList& FE, int numEdges,
                    std::vector<std::array<int, 4>>* children,
                    std::vector<std::array<int, 4>>& neighbours) {
  const int numFaces = static_cast<int>(FE.size());
  neighbours.assign(numEdges, {-1, -1, -1, -1});
  if (children) children->assign(numEdges, {-1, -1, -1, -1});
  for (int f = 0; f < numFaces; ++f)
    for (int i = 0; i < 3; ++i) {
      const int e = FE[f][i];
      if (children) {
        addChild((*children)[e], 3 * numFaces + 2 * e);
        addChild((*children)[e], 3 * numFaces + 2 * e + 1);
        addChild((*children)[e], 3 * f + (i + 2) % 3);
      }
      addChild(neighbours[e], FE[f][(i + 1) % 3]);
      addChild(neighbours[e], FE[f][(i + 2) % 3]);
    }
}

}  // namespace

EdgeTree edgeTree(const Hierarchy& h) {
  EdgeTree t;
  const int J = h.levels();
  for (int j = 0; j < J; ++j) t.edges.push_back(h.numVertices(j + 1) - h.numVertices(j));
  t.children.resize(std::max(J - 1, 0));
  t.neighbours.resize(J);
  for (int j = 0; j < J; ++j) {
    if (const Connectivity::FaceEdgeList* FE = h.faceEdges(j)) {
      levelRelations(*FE, t.edges[j], j + 1 < J ? &t.children[j] : nullptr, t.neighbours[j]);
      continue;
    }
    if (j + 1 < J) t.children[j] = levelChildren(h, j);
    t.neighbours[j] = levelNeighbours(h, j);
  }
  return t;
}

int topPlane(const QuantisedLevels& q) {
  std::int64_t largest = 0;
  for (const auto& level : q)
    for (std::int32_t v : level) largest = std::max<std::int64_t>(largest, std::llabs(v));
  if (largest >= (std::int64_t{1} << kMaxPlanes))
    throw Error("zerotree: a coefficient needs more than " + std::to_string(kMaxPlanes) +
                " bit planes");
  int top = -1;
  while (largest >> (top + 1)) ++top;
  return top;
}

// ---- The traversal, shared by encoder and decoder --------------------------------

namespace {

constexpr int kLevelContexts = 8;

// The adaptive contexts of every kind of decision.
struct Contexts {
  // [level][component class][parent significant]; the class is 0 for the normal
  // component, 1 for a tangential one whose normal is insignificant, 2 otherwise.
  // [significant neighbours: 0, 1, 2 or more]
  BitModel significance[kLevelContexts][3][2][3];
  // [level][component class][the node itself significant][neighbours with a
  // significant subtree: 0, 1, 2 or more]
  BitModel subtree[kLevelContexts][3][2][3];
  // [level][normal or tangential][first refinement of this node]
  BitModel refinement[kLevelContexts][2][2];
  // [level][component: normal, along the edge, across it][signs of the significant
  // neighbours: none, more negative, as many of each, more positive]. Neighbours along
  // one crease or one curved region share the sign of their normal components.
  // [parent: insignificant, negative, positive]
  BitModel sign[kLevelContexts][3][4][3];
};

// Adds node i to a bit set (one bit per node, 64 per word).
void mark(std::uint64_t* set, std::size_t i) {
  set[i / 64] |= std::uint64_t{1} << (i % 64);
}

// Everything both sides know, updated identically.
struct State {
  std::vector<std::vector<std::int32_t>> high;
  std::vector<std::vector<std::int8_t>> plane, sign, born;
  std::vector<std::vector<std::uint8_t>> subtree, parentSig;
  // Per node: how many of its neighbours are significant, and have significant subtrees.
  std::vector<std::vector<std::uint8_t>> significantNear, subtreeNear;
  // Per node: the sum of the signs (+1 or -1) of its significant neighbours, and its
  // parent's sign (0 while the parent is insignificant).
  std::vector<std::vector<std::int8_t>> signNear, parentSign;
  // The passes visit only the nodes they have a decision for, as bit sets per level
  // (ascending order, as a scan of every node would visit them: the same stream at a
  // fraction of the cost): `active`, reached nodes with a sorting decision left;
  // `significant`, nodes significant before this plane; `bornNow`, from this plane.
  std::vector<std::vector<std::uint64_t>> active, significant, bornNow;
  int planesDone = 0;
  bool complete = false;

  explicit State(const EdgeTree& t) {
    for (int E : t.edges) {
      const std::size_t n = 3 * static_cast<std::size_t>(E), words = (n + 63) / 64;
      high.emplace_back(n, 0);
      plane.emplace_back(n, -1);
      sign.emplace_back(n, 1);
      born.emplace_back(n, -1);
      subtree.emplace_back(n, 0);
      parentSig.emplace_back(n, 0);
      significantNear.emplace_back(n, 0);
      subtreeNear.emplace_back(n, 0);
      signNear.emplace_back(n, 0);
      parentSign.emplace_back(n, 0);
      active.emplace_back(words, 0);
      significant.emplace_back(words, 0);
      bornNow.emplace_back(words, 0);
    }
    if (!t.edges.empty())
      for (std::size_t i = 0; i < 3 * static_cast<std::size_t>(t.edges[0]); ++i)
        mark(active[0].data(), i);
  }
};

// One level's arrays as raw pointers, taken once per level and pass: indexed through
// the vectors of vectors, every access reloaded their data pointers, since a store to
// any of the byte arrays may alias them as far as the compiler knows.
struct LevelView {
  std::int32_t* high;
  std::int8_t *plane, *sign, *born;
  std::uint8_t *subtree, *parentSig, *significantNear, *subtreeNear;
  std::int8_t *signNear, *parentSign;
  std::uint64_t *active, *bornNow;
  const std::array<int, 4>* children;  // none at the last level
  const std::array<int, 4>* neighbours;

  LevelView(const EdgeTree& t, State& s, std::size_t j)
      : high(s.high[j].data()),
        plane(s.plane[j].data()),
        sign(s.sign[j].data()),
        born(s.born[j].data()),
        subtree(s.subtree[j].data()),
        parentSig(s.parentSig[j].data()),
        significantNear(s.significantNear[j].data()),
        subtreeNear(s.subtreeNear[j].data()),
        signNear(s.signNear[j].data()),
        parentSign(s.parentSign[j].data()),
        active(s.active[j].data()),
        bornNow(s.bornNow[j].data()),
        children(j < t.children.size() ? t.children[j].data() : nullptr),
        neighbours(t.neighbours[j].data()) {}
};

// Calls visit(i) for every member of `set` in ascending order, each word read before
// its members are visited (visit may change the set). Stops when visit returns false.
template <class Visit>
bool forEachMember(const std::vector<std::uint64_t>& set, Visit&& visit) {
  for (std::size_t w = 0; w < set.size(); ++w)
    for (std::uint64_t bits = set[w]; bits != 0; bits &= bits - 1)
      if (!visit(64 * w + static_cast<std::size_t>(__builtin_ctzll(bits)))) return false;
  return true;
}

// Node i has become significant (or its subtree has): each of its neighbours (same
// component, the edges beside it in its triangles; the relation is symmetric) counts
// one more such neighbour, or adds its sign (`delta`) to their sums. The counts and sums
// are kept as nodes change rather than gathered at every decision; the contexts cap
// the counts at 2.
template <class T>
void addForNeighbours(const LevelView& L, T* values, std::size_t i, int delta = 1) {
  for (int e : L.neighbours[i / 3])
    if (e >= 0) values[3 * static_cast<std::size_t>(e) + i % 3] += static_cast<T>(delta);
}

// The sign context of node i: none of its neighbours significant, their signs summing
// below, at or above zero.
int signContext(const LevelView& L, std::size_t i) {
  if (L.significantNear[i] == 0) return 0;
  return L.signNear[i] < 0 ? 1 : L.signNear[i] == 0 ? 2 : 3;
}

int capped(std::uint8_t count) {
  return count < 2 ? count : 2;
}

int componentClass(const LevelView& L, std::size_t i) {
  const std::size_t c = i % 3;
  if (c == 0) return 0;
  return L.born[i - c] >= 0 ? 2 : 1;
}

// One node's sorting-pass events: its significance, then its subtree's (`child` is the
// next level's view, none at the last level). Returns false when the coder stopped (a
// cut stream), with nothing half-applied.
template <class Io>
bool sortNode(const LevelView& L, const LevelView* child, int j, std::size_t i, int p,
              Contexts& ctx, Io& io) {
  const int lc = std::min(j, kLevelContexts - 1), cls = componentClass(L, i);
  if (L.born[i] < 0) {
    BitModel& m = ctx.significance[lc][cls][L.parentSig[i]][capped(L.significantNear[i])];
    const int bit = io.significant(m, j, i, p);
    if (io.stopped()) return false;
    if (bit) {
      const int ps = L.parentSign[i] == 0 ? 0 : L.parentSign[i] < 0 ? 1 : 2;
      const int negative = io.sign(ctx.sign[lc][i % 3][signContext(L, i)][ps], j, i);
      if (io.stopped()) return false;
      L.born[i] = L.plane[i] = static_cast<std::int8_t>(p);
      const std::int8_t sign = negative ? -1 : 1;
      addForNeighbours(L, L.significantNear, i);
      addForNeighbours(L, L.signNear, i, sign);
      if (child)
        for (int c : L.children[i / 3])
          if (c >= 0) child->parentSign[3 * static_cast<std::size_t>(c) + i % 3] = sign;
      L.high[i] = 1;
      L.sign[i] = sign;
      mark(L.bornNow, i);
    }
  }
  if (child && !L.subtree[i]) {
    const int self = L.born[i] >= 0;
    const int bit = io.subtree(ctx.subtree[lc][cls][self][capped(L.subtreeNear[i])], j, i, p);
    if (io.stopped()) return false;
    if (bit) {
      L.subtree[i] = 1;
      addForNeighbours(L, L.subtreeNear, i);
      for (int c : L.children[i / 3])
        if (c >= 0) {
          const std::size_t k = 3 * static_cast<std::size_t>(c) + i % 3;
          mark(child->active, k);
          child->parentSig[k] = static_cast<std::uint8_t>(self);
        }
    }
  }
  return true;
}

template <class Io>
bool sortingPass(const EdgeTree& t, int p, State& s, Contexts& ctx, Io& io) {
  const int levels = static_cast<int>(t.edges.size());
  for (int j = 0; j < levels; ++j) {
    const LevelView L(t, s, j);
    const std::optional<LevelView> child =
        j + 1 < levels ? std::optional<LevelView>(LevelView(t, s, j + 1)) : std::nullopt;
    const LevelView* next = child ? &*child : nullptr;
    // A node leaves the sorting passes once significant with its subtree known to be
    // (or at the last level, where it has none).
    const bool ok = forEachMember(s.active[j], [&](std::size_t i) {
      if (!sortNode(L, next, j, i, p, ctx, io)) return false;
      if (L.born[i] >= 0 && (!next || L.subtree[i]))
        L.active[i / 64] &= ~(std::uint64_t{1} << (i % 64));
      return true;
    });
    if (!ok) return false;
  }
  return true;
}

template <class Io>
bool refinementPass(int p, State& s, Contexts& ctx, Io& io) {
  for (std::size_t j = 0; j < s.significant.size(); ++j) {
    const int lc = std::min(static_cast<int>(j), kLevelContexts - 1);
    const bool ok = forEachMember(s.significant[j], [&](std::size_t i) {
      const int first = s.born[j][i] == p + 1;
      BitModel& m = ctx.refinement[lc][i % 3 == 0 ? 0 : 1][first];
      const int bit = io.refinement(m, static_cast<int>(j), i, p);
      if (io.stopped()) return false;
      s.high[j][i] = 2 * s.high[j][i] + bit;
      s.plane[j][i] = static_cast<std::int8_t>(p);
      return true;
    });
    if (!ok) return false;
    // This plane's new nodes refine from the next plane on.
    for (std::size_t w = 0; w < s.significant[j].size(); ++w) {
      s.significant[j][w] |= s.bornNow[j][w];
      s.bornNow[j][w] = 0;
    }
  }
  return true;
}

template <class Io>
void runPlanes(const EdgeTree& t, int top, State& s, Io& io) {
  Contexts ctx;
  for (int p = top; p >= 0; --p) {
    if (!sortingPass(t, p, s, ctx, io) || !refinementPass(p, s, ctx, io)) return;
    ++s.planesDone;
  }
  s.complete = true;
}

// The encoder's side: answers from the coefficients, written to the range coder.
class EncoderIo {
 public:
  EncoderIo(const EdgeTree& t, const QuantisedLevels& q, RangeEncoder& enc)
      : q_(q), enc_(enc), below_(descendantMaxima(t, q)) {}
  bool stopped() const { return false; }
  int significant(BitModel& m, int j, std::size_t i, int p) {
    return put(m, (magnitude(j, i) >> p) != 0);
  }
  int subtree(BitModel& m, int j, std::size_t i, int p) { return put(m, (below_[j][i] >> p) != 0); }
  int sign(BitModel& m, int j, std::size_t i) { return put(m, q_[j][i] < 0); }
  int refinement(BitModel& m, int j, std::size_t i, int p) {
    return put(m, static_cast<int>((magnitude(j, i) >> p) & 1));
  }

 private:
  std::int64_t magnitude(int j, std::size_t i) const { return std::llabs(q_[j][i]); }
  int put(BitModel& m, int bit) {
    enc_.encode(m, bit);
    return bit;
  }
  // The largest |q| strictly below each node, bottom-up.
  static std::vector<std::vector<std::int64_t>> descendantMaxima(const EdgeTree& t,
                                                                 const QuantisedLevels& q) {
    std::vector<std::vector<std::int64_t>> below(q.size());
    for (std::size_t j = 0; j < q.size(); ++j) below[j].assign(q[j].size(), 0);
    for (int j = static_cast<int>(t.children.size()) - 1; j >= 0; --j)
      for (std::size_t i = 0; i < below[j].size(); ++i)
        for (int child : t.children[j][i / 3])
          if (child >= 0) {
            const std::size_t k = 3 * static_cast<std::size_t>(child) + i % 3;
            below[j][i] = std::max(
                {below[j][i], below[j + 1][k], static_cast<std::int64_t>(std::llabs(q[j + 1][k]))});
          }
    return below;
  }

  const QuantisedLevels& q_;
  RangeEncoder& enc_;
  std::vector<std::vector<std::int64_t>> below_;
};

// The decoder's side: answers from the range decoder.
class DecoderIo {
 public:
  explicit DecoderIo(RangeDecoder& dec) : dec_(dec) {}
  bool stopped() const { return dec_.exhausted(); }
  int significant(BitModel& m, int, std::size_t, int) { return dec_.decode(m); }
  int subtree(BitModel& m, int, std::size_t, int) { return dec_.decode(m); }
  int sign(BitModel& m, int, std::size_t) { return dec_.decode(m); }
  int refinement(BitModel& m, int, std::size_t, int) { return dec_.decode(m); }

 private:
  RangeDecoder& dec_;
};

}  // namespace

void encodeZerotree(const EdgeTree& tree, const QuantisedLevels& q, int top, RangeEncoder& enc) {
  if (q.size() != tree.edges.size())
    throw Error("zerotree: " + std::to_string(q.size()) + " levels of coefficients for a tree of " +
                std::to_string(tree.edges.size()));
  for (std::size_t j = 0; j < q.size(); ++j)
    if (q[j].size() != 3 * static_cast<std::size_t>(tree.edges[j]))
      throw Error("zerotree: level " + std::to_string(j) + " has the wrong coefficient count");
  if (top < topPlane(q)) throw Error("zerotree: the top plane is below the largest coefficient");
  State s(tree);
  EncoderIo io(tree, q, enc);
  runPlanes(tree, top, s, io);
}

ZerotreeState decodeZerotree(const EdgeTree& tree, int top, RangeDecoder& dec) {
  if (top >= kMaxPlanes) throw Error("zerotree: top plane " + std::to_string(top) + " too large");
  State s(tree);
  DecoderIo io(dec);
  runPlanes(tree, top, s, io);
  ZerotreeState out;
  out.high = std::move(s.high);
  out.plane = std::move(s.plane);
  out.sign = std::move(s.sign);
  out.planesDone = s.planesDone;
  out.complete = s.complete;
  return out;
}

std::vector<std::vector<double>> reconstruct(const ZerotreeState& s) {
  std::vector<std::vector<double>> out(s.high.size());
  for (std::size_t j = 0; j < s.high.size(); ++j) {
    out[j].assign(s.high[j].size(), 0.0);
    for (std::size_t i = 0; i < s.high[j].size(); ++i)
      if (s.plane[j][i] >= 0)
        out[j][i] = s.sign[j][i] * (s.high[j][i] + 0.5) * static_cast<double>(1 << s.plane[j][i]);
  }
  return out;
}

}  // namespace osdmra
