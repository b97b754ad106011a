#include "osdmra/wavelets.h"

#include <Eigen/Cholesky>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <optional>
#include <string>
#include <unordered_map>

#include "osdmra/error.h"
#include "osdmra/gram.h"

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

struct KeyHash {
  std::size_t operator()(const std::vector<int>& k) const {
    std::uint64_t h = 1469598103934665603ull;
    for (int x : k) {
      h ^= static_cast<std::uint32_t>(x);
      h *= 1099511628211ull;
    }
    return static_cast<std::size_t>(h);
  }
};

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

AlphaMatrix preWavelets(const Hierarchy& h, Scheme scheme, int j, ElementGram& elements) {
  const int n = h.numVertices(j), nn = h.numVertices(j + 1);
  const SparseMatrix Ij = gram(h.connectivity(j), j, elements);
  const SparseMatrix Ij1 = gram(h.connectivity(j + 1), j + 1, elements);
  const SparseMatrix& P = h.refinement(scheme, j);
  const Eigen::MatrixXd B = Eigen::MatrixXd(SparseMatrix(P.transpose()) * Ij1).rightCols(nn - n);
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt{Eigen::SparseMatrix<double>(Ij)};
  if (ldlt.info() != Eigen::Success)
    throw Error("Gram matrix I^" + std::to_string(j) + " is not positive definite");
  const Eigen::MatrixXd alpha = ldlt.solve(B);
  return alpha.sparseView(0.0, 0.0);
}

}  // namespace

std::vector<AlphaMatrix> waveletCorrections(const Hierarchy& h, Scheme scheme,
                                             const WaveletOptions& options,
                                             const Progress& progress, WaveletStats* stats) {
  const int J = h.levels();
  std::vector<AlphaMatrix> alphas(J);
  if (options.kind == WaveletKind::Quasi && (options.rings < 0 || options.rings > 8))
    throw Error("rings must be in 0..8, got " + std::to_string(options.rings));
  if (options.kind == WaveletKind::Pre && h.numVertices(J) > kMaxPreWaveletVertices)
    throw Error("pre-wavelets are dense and limited to " + std::to_string(kMaxPreWaveletVertices) +
                " finest-level vertices; this surface has " + std::to_string(h.numVertices(J)) +
                " (use quasi-wavelets)");
  ElementGram elements(scheme);
  // Alpha of a neighbourhood, in ball order. Inner products depend on topology only
  // and scale by 4^-j on both sides of the system, so one cache serves every level.
  std::unordered_map<std::vector<int>, Eigen::VectorXd, KeyHash> cache;
  const int r = options.rings;
  // Radius that determines alpha: r rings of S, plus the reach of the Gram entries
  // (supports and element types: 3 rings for Loop, 1 for polyhedral) and of b.
  const int K = r + (scheme == Scheme::Loop ? 4 : 2);
  Eigen::VectorXd regularAlpha;
  // The K-ball of edge {a, b} lies in the (K+1)-balls of a and of b.
  LatticeBalls lattice(K + 1);

  for (int j = 0; j < J; ++j) {
    const int n = h.numVertices(j), numNew = h.numVertices(j + 1) - n;
    if (progress) progress("wavelets", double(j) / J);
    if (options.kind == WaveletKind::Lazy) {
      alphas[j].resize(n, numNew);
      continue;
    }
    if (options.kind == WaveletKind::Pre) {
      alphas[j] = preWavelets(h, scheme, j, elements);
      continue;
    }
    const Connectivity& conn = h.connectivity(j);
    const SparseMatrix& P = h.refinement(scheme, j);
    // Built on the first cache miss only: at fine levels nearly every edge hits.
    std::optional<LocalGram> coarse, fine;
    EdgeBall ball(conn);
    std::vector<int> mark(n, -1);
    // Edges whose K-ball is the lattice's all have the same neighbourhood: skip
    // encoding it and reuse the regular solution.
    lattice.advance(h, j);
    // alpha^j in compressed column form, one column per new vertex in order, rows
    // sorted within each column.
    std::vector<int> outer{0}, inner;
    std::vector<double> values;
    outer.reserve(numNew + 1);
    std::vector<std::pair<int, double>> column;
    auto appendColumn = [&](const int* rows, const Eigen::VectorXd& a) {
      column.clear();
      for (Eigen::Index i = 0; i < a.size(); ++i) column.emplace_back(rows[i], a(i));
      std::sort(column.begin(), column.end());
      for (auto [row, value] : column) {
        inner.push_back(row);
        values.push_back(value);
      }
      outer.push_back(static_cast<int>(inner.size()));
    };
    for (int e = 0; e < numNew; ++e) {
      const auto [a, b] = h.parentEdge(j, e);
      const bool regular = lattice(a) && lattice(b);
      if (regular && regularAlpha.size() > 0) {
        ball.build(a, b, r, false);
        if (stats) ++stats->reused;
        appendColumn(ball.verts.data(), regularAlpha);
        ball.clear();
        continue;
      }
      ball.build(a, b, K);
      const int size = ball.within(r);
      auto it = cache.find(ball.key);
      if (it == cache.end()) {
        std::vector<int> S(ball.verts.begin(), ball.verts.begin() + size);
        if (!coarse) {
          coarse.emplace(conn, j, elements);
          fine.emplace(h.connectivity(j + 1), j + 1, elements);
        }
        const Eigen::MatrixXd G = coarse->block(S);
        for (int i = 0; i < size; ++i) mark[S[i]] = i;
        const Eigen::VectorXd rhs = projectColumn(fine->column(n + e), P, mark, size);
        for (int v : S) mark[v] = -1;
        Eigen::LLT<Eigen::MatrixXd> llt(G);
        if (llt.info() != Eigen::Success)
          throw Error("local Gram matrix not positive definite at level " + std::to_string(j) +
                      ", edge " + std::to_string(a) + "-" + std::to_string(b));
        it = cache.emplace(ball.key, llt.solve(rhs)).first;
        if (stats) ++stats->localSolves;
      } else if (stats) {
        ++stats->reused;
      }
      if (regular) regularAlpha = it->second;
      appendColumn(ball.verts.data(), it->second);
      ball.clear();
    }
    alphas[j] = Eigen::Map<const AlphaMatrix>(n, numNew, static_cast<Eigen::Index>(inner.size()),
                                              outer.data(), inner.data(), values.data());
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

}  // namespace osdmra
