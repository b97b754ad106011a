#include "osdmra/mra/wavelets.h"

#include <Eigen/Cholesky>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
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
  }
  return "?";
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

// The local Galerkin solution for new vertex n_j + e with S = the first `size`
// ball vertices, and 4^{j+1} ||psi||^2 with psi = phi^{j+1}_m - sum alpha_i phi^j_i.
template <class Entry>
Entry solveLocalImpl(const Hierarchy& h, int j, int e, const std::vector<int>& ball, int size,
                     const SparseMatrix& P, LocalGram& coarse, LocalGram& fine,
                     std::vector<int>& mark, std::vector<int>& fineMark) {
  const int n = h.numVertices(j), m = n + e;
  const auto [a, b] = h.parentEdge(j, e);
  Entry entry;
  const std::vector<int> S(ball.begin(), ball.begin() + size);
  if (size > 0) {
    const Eigen::MatrixXd G = coarse.block(S);
    for (int i = 0; i < size; ++i) mark[S[i]] = i;
    const Eigen::VectorXd rhs = projectColumn(fine.column(m), P, mark, size);
    Eigen::LLT<Eigen::MatrixXd> llt(G);
    if (llt.info() != Eigen::Success) {
      for (int v : S) mark[v] = -1;
      throw Error("local Gram matrix not positive definite at level " + std::to_string(j) +
                  ", edge " + std::to_string(a) + "-" + std::to_string(b));
    }
    entry.alpha = llt.solve(rhs);
  }
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
        q(static_cast<Eigen::Index>(i)) -= it.value() * entry.alpha(mark[it.col()]);
  for (int v : S) mark[v] = -1;
  for (int k : support) fineMark[k] = -1;
  entry.scaledNorm2 = fine.quadraticForm(support, q) * std::ldexp(1.0, 2 * (j + 1));
  return entry;
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

std::vector<AlphaMatrix> waveletCorrections(const Hierarchy& h, Scheme scheme,
                                            const WaveletOptions& options, const Progress& progress,
                                            WaveletStats* stats,
                                            std::vector<Eigen::VectorXd>* norms) {
  const int J = h.levels();
  std::vector<AlphaMatrix> alphas(J);
  if (norms) norms->assign(J, Eigen::VectorXd());
  if (options.kind == WaveletKind::Quasi && (options.rings < 0 || options.rings > 8))
    throw Error("rings must be in 0..8, got " + std::to_string(options.rings));
  if (options.kind == WaveletKind::Pre && h.numVertices(J) > kMaxPreWaveletVertices)
    throw Error("pre-wavelets are dense and limited to " + std::to_string(kMaxPreWaveletVertices) +
                " finest-level vertices; this surface has " + std::to_string(h.numVertices(J)) +
                " (use quasi-wavelets)");
  ElementGram elements(scheme);
  // One local solution per distinct neighbourhood, in ball order, shared by every
  // level: inner products depend on topology only and scale by 4^-j on both sides
  // of the Galerkin system. The norm is stored as 4^{j+1} ||psi||^2, also invariant.
  struct Entry {
    Eigen::VectorXd alpha;
    double scaledNorm2 = 0;
  };
  std::unordered_map<std::vector<int>, Entry, KeyHash> cache;
  // Lazy wavelets are quasi-wavelets with an empty S (r = -1).
  const int r = options.kind == WaveletKind::Lazy ? -1 : options.rings;
  // Radius that determines alpha and the norm: r rings of S, plus the reach of the
  // Gram entries (supports and element types: 3 rings for Loop, 1 for polyhedral)
  // and of b = P^T I^{j+1} e_m.
  const int K = r + (scheme == Scheme::Loop ? 4 : 2);
  std::optional<Entry> regularEntry;
  // The K-ball of edge {a, b} lies in the (K+1)-balls of a and of b.
  LatticeBalls lattice(K + 1);

  for (int j = 0; j < J; ++j) {
    const int n = h.numVertices(j), numNew = h.numVertices(j + 1) - n;
    if (progress) progress("wavelets", double(j) / J);
    const SparseMatrix& P = h.refinement(scheme, j);
    if (options.kind == WaveletKind::Pre) {
      alphas[j] = preWavelets(h, scheme, j, elements, norms ? &(*norms)[j] : nullptr);
      continue;
    }
    const Connectivity& conn = h.connectivity(j);
    // Built on the first cache miss only: at fine levels nearly every edge hits.
    std::optional<LocalGram> coarse, fine;
    EdgeBall ball(conn);
    std::vector<int> mark(n, -1), fineMark;
    // Edges whose K-ball is the lattice's all have the same neighbourhood: skip
    // encoding it and reuse the regular solution.
    lattice.advance(h, j);
    // alpha^j filled column by column in compressed form (rows sorted within each
    // column), straight into its final storage.
    AlphaMatrix& alpha = alphas[j];
    alpha.resize(n, numNew);
    alpha.reserve(static_cast<Eigen::Index>(numNew) *
                  (regularEntry ? regularEntry->alpha.size() : 2 * (r + 1) * (r + 2) + 2));
    std::vector<std::pair<int, double>> column;
    auto appendColumn = [&](int e, const int* rows, const Eigen::VectorXd& a) {
      column.clear();
      for (Eigen::Index i = 0; i < a.size(); ++i) column.emplace_back(rows[i], a(i));
      std::sort(column.begin(), column.end());
      alpha.startVec(e);
      for (auto [row, value] : column) alpha.insertBack(row, e) = value;
    };
    Eigen::VectorXd levelNorms(norms ? numNew : 0);
    const double normScale = std::ldexp(1.0, -2 * (j + 1));
    for (int e = 0; e < numNew; ++e) {
      const auto [a, b] = h.parentEdge(j, e);
      const bool regular = lattice(a) && lattice(b);
      const Entry* entry = nullptr;
      if (regular && regularEntry) {
        ball.build(a, b, std::max(r, 0), false);
        if (stats) ++stats->reused;
        entry = &*regularEntry;
      } else {
        ball.build(a, b, K);
        auto it = cache.find(ball.key);
        if (it == cache.end()) {
          if (!coarse) {
            coarse.emplace(conn, j, elements);
            fine.emplace(h.connectivity(j + 1), j + 1, elements);
            fineMark.assign(h.numVertices(j + 1), -1);
          }
          it = cache
                   .emplace(ball.key, solveLocalImpl<Entry>(h, j, e, ball.verts, ball.within(r), P,
                                                            *coarse, *fine, mark, fineMark))
                   .first;
          if (stats) ++stats->localSolves;
        } else if (stats) {
          ++stats->reused;
        }
        entry = &it->second;
        if (regular) regularEntry = *entry;
      }
      appendColumn(e, ball.verts.data(), entry->alpha);
      if (norms) levelNorms(e) = std::sqrt(entry->scaledNorm2 * normScale);
      ball.clear();
    }
    alpha.finalize();
    alpha.makeCompressed();
    if (norms) (*norms)[j] = std::move(levelNorms);
  }
  if (progress) progress("wavelets", 1.0);
  return alphas;
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
