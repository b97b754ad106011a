#include "osdmra/mra/wavelets.h"

#include <Eigen/Cholesky>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <unordered_map>

#include "osdmra/base/detail/key_hash.h"
#include "osdmra/base/error.h"
#include "osdmra/mra/gram.h"

namespace osdmra {

const char* waveletKindName(WaveletKind k) {
  switch (k) {
    case WaveletKind::Lazy:
      return "lazy";
    case WaveletKind::Quasi:
      return "quasi";
    case WaveletKind::Pre:
      return "pre";
    case WaveletKind::Fixed:
      return "fixed";
  }
  return "?";
}

WaveletKind parseWaveletKind(const std::string& name) {
  for (WaveletKind k :
       {WaveletKind::Lazy, WaveletKind::Quasi, WaveletKind::Pre, WaveletKind::Fixed})
    if (name == waveletKindName(k)) return k;
  throw Error("unknown wavelets '" + name + "' (expected lazy, quasi, pre or fixed)");
}

namespace {

// Breadth-first ball of radius K around the oriented edge (a, b), with a canonical
// encoding: every ring is read counter-clockwise from the neighbour the search came
// from, so two balls with equal keys are isomorphic with vertices in the same order.
class EdgeBall {
 public:
  explicit EdgeBall(const Connectivity& conn)
      : conn_(conn), pos_(conn.numVertices(), -1), from_(conn.numVertices(), -1) {}

  void build(int a, int b, int K, bool encode = true) {
    verts.assign({a, b});
    depth_.assign({0, 0});
    pos_[a] = 0;
    pos_[b] = 1;
    from_[a] = b;
    from_[b] = a;
    key.clear();
    key.push_back(K);
    for (std::size_t i = 0; i < verts.size(); ++i) {
      const int u = verts[i], d = depth_[i];
      const IndexSpan ring = conn_.ring(u);
      const int k = ring.size();
      int start = 0;
      for (int s = 0; s < k; ++s)
        if (ring[s] == from_[u]) start = s;
      const bool boundary = conn_.isBoundaryVertex(u);
      if (encode) {
        key.push_back(boundary ? 1 : 0);
        key.push_back(k);
        key.push_back(boundary ? start : 0);
      } else if (d >= K) {
        continue;
      }
      for (int s = 0; s < k; ++s) {
        const int w = ring[(start + s) % k];
        if (pos_[w] < 0 && d < K) {
          pos_[w] = static_cast<int>(verts.size());
          from_[w] = u;
          verts.push_back(w);
          depth_.push_back(d + 1);
        }
        if (encode) key.push_back(pos_[w]);
      }
    }
  }
  /// Number of ball vertices within `r` edges of {a, b} (a prefix of verts).
  int within(int r) const {
    int n = 0;
    while (n < static_cast<int>(verts.size()) && depth_[n] <= r) ++n;
    return n;
  }
  void clear() {
    for (int v : verts) pos_[v] = -1;
  }

  std::vector<int> verts, key;

 private:
  const Connectivity& conn_;
  std::vector<int> pos_, from_, depth_;
};

// b = P^T (I^{j+1} e_m) restricted to S, with `mark` giving positions in S.
Eigen::VectorXd projectColumn(const std::vector<std::pair<int, double>>& column,
                              const SparseMatrix& P, const std::vector<int>& mark, int size) {
  Eigen::VectorXd b = Eigen::VectorXd::Zero(size);
  for (auto [k, value] : column)
    for (SparseMatrix::InnerIterator it(P, k); it; ++it)
      if (mark[it.col()] >= 0) b(mark[it.col()]) += it.value() * value;
  return b;
}

// The vertices within r <= 1 edges of {a, b} (none for r < 0) in EdgeBall's order,
// read off the two rings without a ball: a, b, a's ring on from b, then b's ring on
// from a but for a's ring. False where a ring lacks the edge's other end (a
// non-manifold vertex's partial ring): the ball is built then.
bool oneRingOrder(const Connectivity& conn, int a, int b, int r, std::vector<int>& order) {
  order.clear();
  if (r < 0) return true;
  order.assign({a, b});
  if (r == 0) return true;
  const IndexSpan ringA = conn.ring(a), ringB = conn.ring(b);
  const int ka = ringA.size(), kb = ringB.size();
  const int fromA = static_cast<int>(std::find(ringA.begin(), ringA.end(), b) - ringA.begin());
  const int fromB = static_cast<int>(std::find(ringB.begin(), ringB.end(), a) - ringB.begin());
  if (fromA == ka || fromB == kb) return false;
  for (int k = 1; k < ka; ++k) order.push_back(ringA[(fromA + k) % ka]);
  for (int k = 1; k < kb; ++k) {
    const int w = ringB[(fromB + k) % kb];
    if (std::find(ringA.begin(), ringA.end(), w) == ringA.end()) order.push_back(w);
  }
  return true;
}

// Which vertices of a level have a "lattice" neighbourhood: every vertex within R
// edges is interior with valence 6 and the R-ball does not wrap around (a torus of
// a small base does), i.e. it holds exactly the 1 + 3R(R+1) vertices of the
// triangular lattice's. Refinement keeps such balls lattice-like (the R-ball of a
// level-(j+1) vertex lies in the refinement of its parent's R-ball, R >= 2), so only
// vertices whose parents lack the property are searched.
class LatticeBalls {
 public:
  explicit LatticeBalls(int R) : R_(R) {}

  /// Advances to level j of h (call for j = 0, 1, ... in order).
  void advance(const Hierarchy& h, int j) {
    const Connectivity& conn = h.connectivity(j);
    const int n = conn.numVertices();
    std::vector<char> next(n, 0);
    if (j > 0) {
      const int nc = h.numVertices(j - 1);
      for (int v = 0; v < nc; ++v) next[v] = ok_[v];
      for (int e = 0; e < n - nc; ++e) {
        const auto [a, b] = h.parentEdge(j - 1, e);
        next[nc + e] = ok_[a] || ok_[b];
      }
    }
    mark_.assign(n, 0);
    for (int v = 0; v < n; ++v)
      if (!next[v]) next[v] = search(conn, v);
    ok_ = std::move(next);
  }
  bool operator()(int v) const { return ok_[v] != 0; }

 private:
  bool search(const Connectivity& conn, int v) {
    queue_.assign({v});
    depth_.assign({0});
    mark_[v] = 1;
    bool ok = true;
    for (std::size_t i = 0; i < queue_.size() && ok; ++i) {
      const int u = queue_[i];
      if (conn.isBoundaryVertex(u) || conn.valence(u) != 6) ok = false;
      if (depth_[i] == R_) continue;
      for (int w : conn.ring(u))
        if (!mark_[w]) {
          mark_[w] = 1;
          queue_.push_back(w);
          depth_.push_back(depth_[i] + 1);
        }
    }
    for (int u : queue_) mark_[u] = 0;
    return ok && static_cast<int>(queue_.size()) == 1 + 3 * R_ * (R_ + 1);
  }
  int R_;
  std::vector<char> ok_, mark_;
  std::vector<int> queue_, depth_;
};

// The local Galerkin solution alpha over S for new vertex n_j + e.
Eigen::VectorXd galerkinAlpha(const Hierarchy& h, int j, int e, const std::vector<int>& S,
                              const SparseMatrix& P, LocalGram& coarse, LocalGram& fine,
                              std::vector<int>& mark) {
  const int size = static_cast<int>(S.size());
  if (size == 0) return Eigen::VectorXd();
  const int m = h.numVertices(j) + e;
  const auto [a, b] = h.parentEdge(j, e);
  const Eigen::MatrixXd G = coarse.block(S);
  for (int i = 0; i < size; ++i) mark[S[i]] = i;
  const Eigen::VectorXd rhs = projectColumn(fine.column(m), P, mark, size);
  for (int v : S) mark[v] = -1;
  Eigen::LLT<Eigen::MatrixXd> llt(G);
  if (llt.info() != Eigen::Success)
    throw Error("local Gram matrix not positive definite at level " + std::to_string(j) +
                ", edge " + std::to_string(a) + "-" + std::to_string(b));
  return llt.solve(rhs);
}

// 4^{j+1} ||psi||^2 for psi = phi^{j+1}_m - sum_{i in S} alpha_i phi^j_i, m = n_j + e.
double scaledNorm2(const Hierarchy& h, int j, int e, const std::vector<int>& S,
                   const Eigen::VectorXd& alpha, const SparseMatrix& P, LocalGram& fine,
                   std::vector<int>& mark, std::vector<int>& fineMark) {
  const int m = h.numVertices(j) + e;
  for (std::size_t i = 0; i < S.size(); ++i) mark[S[i]] = static_cast<int>(i);
  // q = e_m - P alpha on level j+1. P alpha reaches the children of S and of their
  // neighbours (Loop's vertex rule) and the midpoints of edges in the fans of S
  // (Loop's edge rule uses the opposite vertices).
  std::vector<int> support{m};
  fineMark[m] = 0;
  const Connectivity& conn = h.connectivity(j);
  auto add = [&](int k) {
    if (k >= 0 && fineMark[k] < 0) {
      fineMark[k] = static_cast<int>(support.size());
      support.push_back(k);
    }
  };
  for (int v : S) {
    add(v);
    for (int x : conn.ring(v)) add(x);
    for (int hh : conn.fan(v)) {
      add(h.midpoint(j, conn.from(hh), conn.to(hh)));
      add(h.midpoint(j, conn.to(hh), conn.from(Connectivity::prev(hh))));
      add(h.midpoint(j, conn.from(Connectivity::prev(hh)), conn.from(hh)));
    }
  }
  Eigen::VectorXd q = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(support.size()));
  q(0) = 1.0;
  for (std::size_t i = 0; i < support.size(); ++i)
    for (SparseMatrix::InnerIterator it(P, support[i]); it; ++it)
      if (mark[it.col()] >= 0)
        q(static_cast<Eigen::Index>(i)) -= it.value() * alpha(mark[it.col()]);
  for (int v : S) mark[v] = -1;
  for (int k : support) fineMark[k] = -1;
  return fine.quadraticForm(support, q) * std::ldexp(1.0, 2 * (j + 1));
}

// Fixed wavelets' corrections (WaveletKind::Fixed): the quasi-wavelets' of the
// regular lattice, solved once and written out here, so that decoding a stream never
// depends on a solver's rounding (Wavelets.FixedWeightsAreTheLatticeQuasiWavelets
// checks them against the Galerkin solutions). r = 1 reads an end's ring from the
// other end: positions 1 and 5 are the wings (shared by both ends), 2 and 4 the
// sides, 3 the vertex across.
struct LatticeWeights {
  double pair;                     ///< r = 0: both ends
  double end, wing, side, across;  ///< r = 1
};
constexpr LatticeWeights kLoopLattice{13109.0 / 66367, 0.26026168103351543, -0.017365693237373615,
                                      -0.060214499406156483, -0.047047034167273409};
constexpr LatticeWeights kLinearLattice{5.0 / 28, 41.0 / 212, -3.0 / 212, -11.0 / 424, -5.0 / 212};

// Column of alpha^j for edge {a, b} of fixed wavelets: emit(row, value) for each entry,
// rows ascending. The lattice's r = 1 weights where both ends are interior of valence
// 6 (which the lattice's 1-ring needs), its r = 0 weights elsewhere. Any weights give
// an invertible lifting; these are the quasi-wavelets' wherever the neighbourhood
// is the lattice's, and within 0.1 dB of them in the codec (docs/COMPRESSION.md).
template <class Emit>
void fixedEntries(const Connectivity& conn, int a, int b, const LatticeWeights& w, Emit&& emit) {
  const auto regular = [&](int v) { return !conn.isBoundaryVertex(v) && conn.valence(v) == 6; };
  if (!regular(a) || !regular(b)) {
    emit(std::min(a, b), w.pair);
    emit(std::max(a, b), w.pair);
    return;
  }
  // Ten entries, each as (row << 4 | slot) so that sorting plain integers orders the
  // rows (this runs once per new vertex of every level in a decoder).
  const double byPosition[6] = {w.end, w.wing, w.side, w.across, w.side, w.wing};
  std::uint64_t key[10];
  double value[10];
  int count = 0;
  const auto add = [&](int row, double weight) {
    key[count] = static_cast<std::uint64_t>(row) << 4 | static_cast<std::uint64_t>(count);
    value[count++] = weight;
  };
  for (const auto& [u, other] : {std::pair{a, b}, std::pair{b, a}}) {
    const IndexSpan ring = conn.ring(u);
    int from = 0;
    while (ring[from] != other) ++from;
    add(u, byPosition[0]);
    for (int i = 1; i < 6; ++i)
      if (u == a || (i != 1 && i != 5)) add(ring[(from + i) % 6], byPosition[i]);
  }
  for (int i = 1; i < count; ++i) {  // insertion sort of ten keys
    const std::uint64_t x = key[i];
    int k = i;
    for (; k > 0 && key[k - 1] > x; --k) key[k] = key[k - 1];
    key[k] = x;
  }
  // A small closed mesh can wrap an end's ring onto the other's: weights add up.
  for (int i = 0; i < count;) {
    const std::uint64_t row = key[i] >> 4;
    double sum = value[key[i] & 15];
    for (++i; i < count && key[i] >> 4 == row; ++i) sum += value[key[i] & 15];
    emit(static_cast<int>(row), sum);
  }
}

void fixedColumn(const Connectivity& conn, int a, int b, const LatticeWeights& w,
                 std::vector<std::pair<int, double>>& column) {
  column.clear();
  fixedEntries(conn, a, b, w, [&](int row, double value) { column.emplace_back(row, value); });
}

// alpha^j of fixed wavelets, for a decoder (no neighbourhood is looked at beyond the
// edge's ends), written in place as compressed columns of at most ten entries.
void fixedCorrections(const Hierarchy& h, Scheme scheme, int j, AlphaMatrix& alpha) {
  const int n = h.numVertices(j), numNew = h.numVertices(j + 1) - n;
  const Connectivity& conn = h.connectivity(j);
  const LatticeWeights& w = scheme == Scheme::Loop ? kLoopLattice : kLinearLattice;
  alpha.resize(n, numNew);
  alpha.resizeNonZeros(static_cast<Eigen::Index>(numNew) * 10);
  int* outer = alpha.outerIndexPtr();
  int* rows = alpha.innerIndexPtr();
  double* values = alpha.valuePtr();
  int nnz = 0;
  for (int e = 0; e < numNew; ++e) {
    const auto [a, b] = h.parentEdge(j, e);
    outer[e] = nnz;
    fixedEntries(conn, a, b, w, [&](int row, double value) {
      rows[nnz] = row;
      values[nnz++] = value;
    });
  }
  outer[numNew] = nnz;
  alpha.data().resize(nnz);
}

// alpha^j of the pre-wavelets and, when `norms` is given, ||psi^j_m|| for every new
// vertex m.
AlphaMatrix preWavelets(const Hierarchy& h, Scheme scheme, int j, ElementGram& elements,
                        Eigen::VectorXd* norms) {
  const int n = h.numVertices(j), nn = h.numVertices(j + 1);
  const SparseMatrix Ij = gram(h.connectivity(j), j, elements);
  const SparseMatrix Ij1 = gram(h.connectivity(j + 1), j + 1, elements);
  const SparseMatrix& P = h.refinement(scheme, j);
  const SparseMatrix PtI = SparseMatrix(P.transpose()) * Ij1;  // n_j x n_{j+1}
  const Eigen::MatrixXd B = Eigen::MatrixXd(PtI).rightCols(nn - n);
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt{Eigen::SparseMatrix<double>(Ij)};
  if (ldlt.info() != Eigen::Success)
    throw Error("Gram matrix I^" + std::to_string(j) + " is not positive definite");
  const Eigen::MatrixXd alpha = ldlt.solve(B);
  if (norms) {
    // ||psi_m||^2 = q^T I^{j+1} q with q = e_m - P alpha_m, expanded as
    //   I^{j+1}_mm - 2 alpha_m . (P^T I^{j+1} e_m) + alpha_m^T (P^T I^{j+1} P) alpha_m
    // so that only n_j-row products are formed. Q = E - P alpha is dense: forming it
    // and I^{j+1} Q as sparse matrices took seconds for a few thousand vertices.
    const SparseMatrix C = PtI * P;  // n_j x n_j
    const Eigen::MatrixXd Calpha = C * alpha;
    const Eigen::VectorXd cross = alpha.cwiseProduct(B).colwise().sum().transpose();
    const Eigen::VectorXd quad = alpha.cwiseProduct(Calpha).colwise().sum().transpose();
    *norms = (Eigen::VectorXd(Ij1.diagonal()).tail(nn - n) - 2.0 * cross + quad).cwiseSqrt();
  }
  return alpha.sparseView(0.0, 0.0);
}

}  // namespace

namespace {

// Quasi-wavelets (and lazy ones with norms, and fixed ones with norms), level by
// level: one local solution per distinct neighbourhood, in ball order, shared by
// every level, since inner products depend on topology only and scale by 4^-j on
// both sides of the Galerkin system. The norm is stored as 4^{j+1} ||psi||^2, also
// invariant. Fixed wavelets' alpha is read off the edge's ends; only its norm is
// shared.
//
// Each distinct neighbourhood (the canonical key of an edge's K-ball) is a class.
// An edge of level j+1 lies in the refinement of its parent edge's ball at level j,
// which that ball's key determines (for K >= 3: kMinInheritedRadius), so edges with
// parents of one class, at the same place about them, are of one class too: after
// level 0 a key is built only for a new (class, place), not for every edge near an
// extraordinary vertex at every level.
class LocalCorrections {
 public:
  LocalCorrections(const Hierarchy& h, Scheme scheme, const WaveletOptions& options,
                   WaveletStats* stats)
      : h_(h),
        scheme_(scheme),
        fixed_(options.kind == WaveletKind::Fixed),
        // Lazy wavelets are quasi-wavelets with an empty S (r = -1); fixed ones reach
        // one ring.
        r_(options.kind == WaveletKind::Lazy ? -1
           : fixed_                          ? 1
                                             : options.rings),
        // Radius that determines alpha and the norm: r rings of S, plus the reach of
        // the Gram entries (supports and element types: 3 rings for Loop, 1 for
        // polyhedral) and of b = P^T I^{j+1} e_m.
        K_(r_ + (scheme == Scheme::Loop ? 4 : 2)),
        lattice_(scheme == Scheme::Loop ? kLoopLattice : kLinearLattice),
        elements_(scheme),
        // The K-ball of edge {a, b} lies in the (K+1)-balls of a and of b.
        latticeBalls_(K_ + 1),
        stats_(stats) {}

  ElementGram& elements() { return elements_; }

  /// alpha^j, and the norms of level j's wavelets when `norms` is given; only the
  /// columns `needed` marks when it is given (the others empty).
  AlphaMatrix level(int j, Eigen::VectorXd* norms, const std::vector<char>* needed = nullptr);

 private:
  // Distances double under the split. A child edge's ends lie one edge of level j+1
  // from an end p of its parent; a vertex of the child's K-ball is within K + 1 of p,
  // so it is p's neighbour u, or the midpoint of an edge (u, w), with u within
  // floor((K + 2) / 2) of p on level j, and its ring is read off u's ring. The parent's
  // key names every vertex within K of the parent edge and gives the ring of each within
  // K - 1: enough from K = 3 on.
  static constexpr int kMinInheritedRadius = 3;

  struct Entry {
    Eigen::VectorXd alpha;
    double scaledNorm2 = 0;
  };
  // Per level: what the solves of level j share.
  struct Level {
    int j;
    const Connectivity& conn;
    const SparseMatrix& P;
    EdgeBall ball;
    int ballRadius = -1;            // radius `ball` holds for the current edge (-1: none)
    bool latticeBallsHere = false;  // whether latticeBalls_ is at this level
    // Built on the first cache miss only: at fine levels nearly every edge hits.
    std::optional<LocalGram> coarse, fine;
    std::vector<int> mark, fineMark;
    std::vector<std::pair<int, double>> column;
    std::vector<int> order;  // S for r <= 1 (oneRingOrder)
  };
  // The level-(j-1) edge whose midpoint is an end of level j's edge {a, b} (a's, if both
  // are: a level-j edge has at least one).
  int parentOf(int j, int a, int b) const {
    const int n = h_.numVertices(j - 1);
    return (a >= n ? a : b) - n;
  }
  int classOf(Level& L, int e, bool inherit, bool needed);
  int classFromKey(Level& L, int e);
  bool placeAboutParent(int j, int a, int b, int parent, std::uint64_t& place) const;
  void buildBall(Level& L, int e, int radius);
  const Entry& entryOf(Level& L, int e, int c, bool withNorm);
  Entry solve(Level& L, int e, bool withNorm);
  void columnOf(Level& L, int e, const Entry& entry);

  const Hierarchy& h_;
  Scheme scheme_;
  bool fixed_;
  int r_, K_;
  const LatticeWeights& lattice_;
  ElementGram elements_;
  LatticeBalls latticeBalls_;
  WaveletStats* stats_;
  std::unordered_map<std::vector<int>, int, KeyHash> classOfKey_;
  std::vector<std::optional<Entry>> entries_;  // per class, solved on first need
  int latticeClass_ = -1;
  // (parent's class, the edge's ends about the parent) -> class; the classes of the
  // previous level's edges.
  std::unordered_map<std::uint64_t, int> inherited_;
  std::vector<int> parentClasses_;
};

AlphaMatrix LocalCorrections::level(int j, Eigen::VectorXd* norms,
                                    const std::vector<char>* needed) {
  const int n = h_.numVertices(j), numNew = h_.numVertices(j + 1) - n;
  Level L{j,
          h_.connectivity(j),
          h_.refinement(scheme_, j),
          EdgeBall(h_.connectivity(j)),
          -1,
          false,
          {},
          {},
          std::vector<int>(n, -1),
          {},
          {},
          {}};
  const bool inherit = j > 0 && K_ >= kMinInheritedRadius;
  // Edges whose K-ball is the lattice's all have the same neighbourhood: skip
  // encoding it and reuse the regular solution. Once its class is known, edges
  // inherit it from their parents instead, unless a mask leaves parents without a class.
  L.latticeBallsHere = !(inherit && latticeClass_ >= 0 && !needed);
  if (L.latticeBallsHere) latticeBalls_.advance(h_, j);
  // alpha^j filled column by column in compressed form (rows sorted within each
  // column), straight into its final storage.
  AlphaMatrix alpha(n, numNew);
  const bool latticeSolved = latticeClass_ >= 0 && entries_[latticeClass_];
  alpha.reserve(static_cast<Eigen::Index>(numNew) * (latticeSolved
                                                         ? entries_[latticeClass_]->alpha.size()
                                                         : 2 * (r_ + 1) * (r_ + 2) + 2));
  if (norms) norms->resize(numNew);
  const double normScale = std::ldexp(1.0, -2 * (j + 1));
  std::vector<int> classes(numNew, -1);
  for (int e = 0; e < numNew; ++e) {
    alpha.startVec(e);
    // Every edge's class that costs no key unless the edge is needed: the next level's
    // edges inherit it.
    const bool isNeeded = !needed || (*needed)[e];
    classes[e] = classOf(L, e, inherit, isNeeded);
    if (isNeeded) {
      const Entry& entry = entryOf(L, e, classes[e], norms != nullptr);
      columnOf(L, e, entry);
      for (auto [row, value] : L.column) alpha.insertBack(row, e) = value;
      if (norms) (*norms)(e) = std::sqrt(entry.scaledNorm2 * normScale);
    }
    if (L.ballRadius >= 0) L.ball.clear();
    L.ballRadius = -1;
  }
  parentClasses_ = std::move(classes);
  alpha.finalize();
  alpha.makeCompressed();
  return alpha;
}

// The class of edge e's neighbourhood: the lattice's, its parent's at the same place,
// or found from its key; -1 where that would take a key and e is not `needed` (its
// children then build theirs).
int LocalCorrections::classOf(Level& L, int e, bool inherit, bool needed) {
  const auto [a, b] = h_.parentEdge(L.j, e);
  const int parent = inherit ? parentOf(L.j, a, b) : -1;
  if (latticeClass_ >= 0) {
    // The refinement of a lattice ball is the lattice's (its edges' balls lie in it).
    if (inherit && parentClasses_[parent] == latticeClass_) return latticeClass_;
    if (L.latticeBallsHere && latticeBalls_(a) && latticeBalls_(b)) return latticeClass_;
  }
  std::uint64_t place = 0;
  if (!inherit || !placeAboutParent(L.j, a, b, parent, place))
    return needed ? classFromKey(L, e) : -1;
  const auto it = inherited_.find(place);
  if (it != inherited_.end()) return it->second;
  if (!needed) return -1;
  const int c = classFromKey(L, e);
  inherited_.emplace(place, c);
  return c;
}

int LocalCorrections::classFromKey(Level& L, int e) {
  buildBall(L, e, K_);
  if (stats_) ++stats_->keys;
  auto [it, added] = classOfKey_.emplace(L.ball.key, static_cast<int>(entries_.size()));
  if (added) entries_.emplace_back();
  const auto [a, b] = h_.parentEdge(L.j, e);
  if (latticeClass_ < 0 && L.latticeBallsHere && latticeBalls_(a) && latticeBalls_(b))
    latticeClass_ = it->second;
  return it->second;
}

// `place` = (the class of the level-(j-1) edge `parent` = {p, q} whose midpoint is an end
// of level j's edge {a, b}, how each end lies about that edge): p or q itself, its midpoint, or the
// midpoint of an edge from p or q to the third corner of the face after or before it in that end's
// ring (the rings' order is the orientation the parent's key is read in), three bits each below the
// class. False where the parent has no class.
bool LocalCorrections::placeAboutParent(int j, int a, int b, int parent,
                                        std::uint64_t& place) const {
  const int n = h_.numVertices(j - 1);
  const int parentClass = parentClasses_[parent];
  if (parentClass < 0) return false;
  const auto [p, q] = h_.parentEdge(j - 1, parent);
  const Connectivity& conn = h_.connectivity(j - 1);
  place = static_cast<std::uint64_t>(parentClass);
  for (const int v : {a, b}) {
    int code = -1;
    if (v < n) {
      code = v == p ? 0 : 1;
    } else if (v - n == parent) {
      code = 2;
    } else {
      const auto [s, t] = h_.parentEdge(j - 1, v - n);
      const int shared = s == p || s == q ? s : t, corner = shared == s ? t : s;
      const IndexSpan ring = conn.ring(shared);
      const int other = shared == p ? q : p, k = ring.size();
      int i = 0;
      while (i < k && ring[i] != other) ++i;
      if (i == k) return false;
      code = 3 + 2 * (shared == p ? 0 : 1) + (ring[(i + 1) % k] == corner ? 0 : 1);
    }
    place = place << 3 | static_cast<std::uint64_t>(code);
  }
  return true;
}

// L.ball holds edge e's ball of at least `radius` (encoded when radius is K).
void LocalCorrections::buildBall(Level& L, int e, int radius) {
  if (L.ballRadius >= radius) return;
  if (L.ballRadius >= 0) L.ball.clear();
  const auto [a, b] = h_.parentEdge(L.j, e);
  L.ball.build(a, b, radius, radius == K_);
  L.ballRadius = radius;
}

// The shared solution of class c, solved from edge e (its r-ball: S is its prefix) if it
// is not yet.
const LocalCorrections::Entry& LocalCorrections::entryOf(Level& L, int e, int c, bool withNorm) {
  std::optional<Entry>& entry = entries_[c];
  if (entry) {
    if (stats_) ++stats_->reused;
  } else {
    buildBall(L, e, std::max(r_, 0));
    entry = solve(L, e, withNorm);
  }
  return *entry;
}

LocalCorrections::Entry LocalCorrections::solve(Level& L, int e, bool withNorm) {
  if (!L.coarse) {
    L.coarse.emplace(L.conn, L.j, elements_);
    L.fine.emplace(h_.connectivity(L.j + 1), L.j + 1, elements_);
    L.fineMark.assign(h_.numVertices(L.j + 1), -1);
  }
  Entry entry;
  std::vector<int> S(L.ball.verts.begin(), L.ball.verts.begin() + L.ball.within(r_));
  if (fixed_) {
    columnOf(L, e, entry);
    S.clear();
    entry.alpha.resize(static_cast<Eigen::Index>(L.column.size()));
    for (std::size_t i = 0; i < L.column.size(); ++i) {
      S.push_back(L.column[i].first);
      entry.alpha(static_cast<Eigen::Index>(i)) = L.column[i].second;
    }
  } else {
    entry.alpha = galerkinAlpha(h_, L.j, e, S, L.P, *L.coarse, *L.fine, L.mark);
  }
  if (withNorm)
    entry.scaledNorm2 = scaledNorm2(h_, L.j, e, S, entry.alpha, L.P, *L.fine, L.mark, L.fineMark);
  if (stats_) ++stats_->localSolves;
  return entry;
}

// Edge e's column of alpha^j in L.column, (row, value) with rows ascending.
void LocalCorrections::columnOf(Level& L, int e, const Entry& entry) {
  const auto [a, b] = h_.parentEdge(L.j, e);
  if (fixed_) {
    fixedColumn(L.conn, a, b, lattice_, L.column);
    return;
  }
  L.column.clear();
  const std::vector<int>* S = &L.order;
  if (r_ > 1 || !oneRingOrder(L.conn, a, b, r_, L.order) ||
      static_cast<Eigen::Index>(L.order.size()) != entry.alpha.size()) {
    buildBall(L, e, std::max(r_, 0));
    S = &L.ball.verts;
  }
  for (Eigen::Index i = 0; i < entry.alpha.size(); ++i)
    L.column.emplace_back((*S)[static_cast<std::size_t>(i)], entry.alpha(i));
  std::sort(L.column.begin(), L.column.end());
}

void checkOptions(const Hierarchy& h, const WaveletOptions& options) {
  const int J = h.levels();
  if (options.kind == WaveletKind::Quasi && (options.rings < 0 || options.rings > 8))
    throw Error("rings must be in 0..8, got " + std::to_string(options.rings));
  if (options.kind == WaveletKind::Pre && h.numVertices(J) > kMaxPreWaveletVertices)
    throw Error("pre-wavelets are dense and limited to " + std::to_string(kMaxPreWaveletVertices) +
                " finest-level vertices; this surface has " + std::to_string(h.numVertices(J)) +
                " (use quasi-wavelets)");
}

// Every new vertex's column of alpha^j for j = 0..J-1, or only those `needed` marks (the
// others empty), with the norms when asked.
std::vector<AlphaMatrix> corrections(const Hierarchy& h, Scheme scheme,
                                     const WaveletOptions& options, const Progress& progress,
                                     WaveletStats* stats, std::vector<Eigen::VectorXd>* norms,
                                     const std::vector<std::vector<char>>* needed) {
  checkOptions(h, options);
  const int J = h.levels();
  std::vector<AlphaMatrix> alphas(J);
  if (norms) norms->assign(J, Eigen::VectorXd());
  if (!norms && correctionsAreLocal(options)) {
    // What a decoder asks for: corrections that need no neighbourhood (none for lazy
    // wavelets), and no norms, which would.
    for (int j = 0; j < J; ++j) localCorrections(h, scheme, options.kind, j, alphas[j]);
    if (progress) progress("wavelets", 1.0);
    return alphas;
  }
  LocalCorrections local(h, scheme, options, stats);
  for (int j = 0; j < J; ++j) {
    if (progress) progress("wavelets", double(j) / J);
    Eigen::VectorXd* levelNorms = norms ? &(*norms)[j] : nullptr;
    alphas[j] = options.kind == WaveletKind::Pre
                    ? preWavelets(h, scheme, j, local.elements(), levelNorms)
                    : local.level(j, levelNorms, needed ? &(*needed)[j] : nullptr);
  }
  if (progress) progress("wavelets", 1.0);
  return alphas;
}

}  // namespace

std::vector<AlphaMatrix> waveletCorrections(const Hierarchy& h, Scheme scheme,
                                            const WaveletOptions& options, const Progress& progress,
                                            WaveletStats* stats,
                                            std::vector<Eigen::VectorXd>* norms) {
  return corrections(h, scheme, options, progress, stats, norms, nullptr);
}

std::vector<AlphaMatrix> waveletCorrections(const Hierarchy& h, Scheme scheme,
                                            const WaveletOptions& options,
                                            const std::vector<std::vector<char>>& needed) {
  const int J = h.levels();
  if (static_cast<int>(needed.size()) != J)
    throw Error("waveletCorrections: one mask per level is needed, got " +
                std::to_string(needed.size()) + " for " + std::to_string(J));
  for (int j = 0; j < J; ++j)
    if (static_cast<int>(needed[j].size()) != h.numVertices(j + 1) - h.numVertices(j))
      throw Error("waveletCorrections: level " + std::to_string(j) + "'s mask has " +
                  std::to_string(needed[j].size()) + " entries for " +
                  std::to_string(h.numVertices(j + 1) - h.numVertices(j)) + " wavelets");
  return corrections(h, scheme, options, {}, nullptr, nullptr, &needed);
}

bool correctionsAreLocal(const WaveletOptions& options) {
  return options.kind == WaveletKind::Fixed || options.kind == WaveletKind::Lazy;
}

void localCorrections(const Hierarchy& h, Scheme scheme, WaveletKind kind, int j,
                      AlphaMatrix& alpha) {
  if (kind == WaveletKind::Fixed)
    fixedCorrections(h, scheme, j, alpha);
  else if (kind == WaveletKind::Lazy)
    alpha.resize(h.numVertices(j), h.numVertices(j + 1) - h.numVertices(j));
  else
    throw Error("localCorrections: these wavelets' corrections are solved, not local");
}

SparseMatrix synthesisMatrix(const Hierarchy& h, Scheme scheme, int j, const AlphaMatrix& alpha) {
  const int n = h.numVertices(j), nn = h.numVertices(j + 1);
  SparseMatrix E(nn, nn - n);
  std::vector<Eigen::Triplet<double>> t;
  for (int e = 0; e < nn - n; ++e) t.emplace_back(n + e, e, 1.0);
  E.setFromTriplets(t.begin(), t.end());
  const SparseMatrix Palpha = h.refinement(scheme, j) * alpha;
  return SparseMatrix(E - Palpha);
}

OrthogonalityStats orthogonality(const Hierarchy& h, Scheme scheme, int j,
                                 const AlphaMatrix& alpha) {
  ElementGram elements(scheme);
  const SparseMatrix Ifine = gram(h.connectivity(j + 1), j + 1, elements);
  const SparseMatrix Icoarse = gram(h.connectivity(j), j, elements);
  const SparseMatrix Q = synthesisMatrix(h, scheme, j, alpha);
  const SparseMatrix QT = Q.transpose();
  // Row m: <psi_m, phi_k> for every k; psi norms from Q^T I Q.
  const SparseMatrix inner = QT * Ifine * h.refinement(scheme, j);
  const SparseMatrix IQ = Ifine * Q;
  const Eigen::VectorXd phiNorm = Icoarse.diagonal().cwiseSqrt();
  const AlphaMatrix support = alpha;  // column m lists S(m)
  OrthogonalityStats stats;
  std::vector<char> inS(h.numVertices(j), 0);
  for (int m = 0; m < inner.outerSize(); ++m) {
    double psi2 = 0;
    for (SparseMatrix::InnerIterator it(QT, m); it; ++it)
      psi2 += it.value() * IQ.coeff(it.col(), m);
    const double psiNorm = std::sqrt(psi2);
    for (AlphaMatrix::InnerIterator it(support, m); it; ++it) inS[it.row()] = 1;
    double rowWorst = 0;
    for (SparseMatrix::InnerIterator it(inner, m); it; ++it) {
      const double c = std::abs(it.value()) / (psiNorm * phiNorm(it.col()));
      rowWorst = std::max(rowWorst, c);
      if (inS[it.col()]) stats.worstInside = std::max(stats.worstInside, c);
    }
    for (AlphaMatrix::InnerIterator it(support, m); it; ++it) inS[it.row()] = 0;
    stats.worst = std::max(stats.worst, rowWorst);
    stats.mean += rowWorst;
  }
  if (inner.outerSize() > 0) stats.mean /= static_cast<double>(inner.outerSize());
  return stats;
}

}  // namespace osdmra
