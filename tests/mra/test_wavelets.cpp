// Wavelets (wavelets.h, math.md section 3): alpha^j has the documented shape and
// pattern (lazy: none; quasi: the r-ring of the parent edge; pre: every coarse vertex);
// the Galerkin condition <psi^j_m, phi^j_k> = 0 for k in S(m), checked on the
// assembled Gram matrices, and for every k with pre-wavelets; orthogonality() reports
// what its definition says, improving with r; the reported norms are those of the
// assembled wavelets; and neighbourhoods are solved once and shared.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <string>
#include <vector>

#include "osdmra/base/error.h"
#include "osdmra/mra/gram.h"
#include "osdmra/mra/wavelets.h"
#include "osdmra/subdivision/shapes.h"
#include "support.h"

using namespace osdmra;
using namespace osdmra::test;

namespace {

const WaveletOptions kLazy{WaveletKind::Lazy, 0}, kPre{WaveletKind::Pre, 0};

WaveletOptions quasi(int rings) {
  return {WaveletKind::Quasi, rings};
}

// The vertices of `c` within r edges of a or b: the r-ring of the edge {a, b}.
std::set<int> ringsAround(const Connectivity& c, int a, int b, int r) {
  std::set<int> ball{a, b};
  std::vector<int> front{a, b};
  for (int d = 0; d < r; ++d) {
    std::vector<int> next;
    for (int v : front)
      for (int w : c.ring(v))
        if (ball.insert(w).second) next.push_back(w);
    front = std::move(next);
  }
  return ball;
}

// The rows column e of alpha stores: S(m) for the new vertex m = n_j + e.
std::set<int> pattern(const AlphaMatrix& alpha, int e) {
  std::set<int> rows;
  for (AlphaMatrix::InnerIterator it(alpha, e); it; ++it) rows.insert(static_cast<int>(it.row()));
  return rows;
}

// c(m, k) = |<psi^j_m, phi^j_k>| / (||psi^j_m|| ||phi^j_k||) for every new vertex m
// (rows) and coarse vertex k (columns), from the assembled I^j and I^{j+1}:
// <psi_m, phi_k> = (Q^T I^{j+1} P)_{mk}, ||psi_m||^2 = (Q^T I^{j+1} Q)_{mm}.
Eigen::MatrixXd normalisedInnerProducts(const Hierarchy& h, Scheme s, int j,
                                        const AlphaMatrix& alpha) {
  ElementGram elements(s);
  const SparseMatrix coarse = gram(h.connectivity(j), j, elements);
  const SparseMatrix fine = gram(h.connectivity(j + 1), j + 1, elements);
  const Eigen::MatrixXd Q = Eigen::MatrixXd(synthesisMatrix(h, s, j, alpha));
  const Eigen::MatrixXd P = Eigen::MatrixXd(h.refinement(s, j));
  const Eigen::MatrixXd IQ = fine * Q;
  Eigen::MatrixXd c = (IQ.transpose() * P).cwiseAbs();
  const Eigen::VectorXd psi = (Q.transpose() * IQ).diagonal().cwiseSqrt();
  const Eigen::VectorXd phi = Eigen::VectorXd(coarse.diagonal()).cwiseSqrt();
  for (Eigen::Index m = 0; m < c.rows(); ++m)
    for (Eigen::Index k = 0; k < c.cols(); ++k) c(m, k) /= psi(m) * phi(k);
  return c;
}

// OrthogonalityStats by their definition (wavelets.h), from normalisedInnerProducts.
OrthogonalityStats measured(const Eigen::MatrixXd& c, const AlphaMatrix& alpha) {
  OrthogonalityStats o;
  for (Eigen::Index m = 0; m < c.rows(); ++m) {
    for (int k : pattern(alpha, static_cast<int>(m)))
      o.worstInside = std::max(o.worstInside, c(m, k));
    o.worst = std::max(o.worst, c.row(m).maxCoeff());
    o.mean += c.row(m).maxCoeff();
  }
  o.mean /= static_cast<double>(c.rows());
  return o;
}

// Calls check(h, scheme, wavelets, j, alpha^j) for every level j of the octahedron,
// torus, disc and valences refined twice, both schemes, and lazy, quasi (r = 0, 1, 2)
// and pre-wavelets.
template <class Check>
void forEachLevel(Check check) {
  for (const char* name : {"octahedron", "torus", "disc", "valences"})
    for (Scheme s : {Scheme::Loop, Scheme::Linear})
      for (const WaveletOptions& k : {kLazy, quasi(0), quasi(1), quasi(2), kPre}) {
        SCOPED_TRACE(std::string(name) + " " + schemeName(s) + " " + waveletsName(k));
        const TriMesh base = shapes::byName(name);
        const Hierarchy h(base.F, static_cast<int>(base.V.rows()), 2);
        const std::vector<AlphaMatrix> alphas = waveletCorrections(h, s, k);
        ASSERT_EQ(alphas.size(), 2u);
        for (int j = 0; j < 2; ++j) {
          SCOPED_TRACE("level " + std::to_string(j));
          check(h, s, k, j, alphas[j]);
        }
      }
}

}  // namespace

// alpha^j is n_j x (n_{j+1} - n_j); its column for m = n_j + e stores S(m): nothing
// for lazy wavelets, the r-ring of the parent edge for quasi-wavelets. Q^{j+1} = E -
// P alpha is n_{j+1} x (n_{j+1} - n_j), E itself for lazy wavelets.
TEST(Wavelets, AlphaHasTheDocumentedShapeAndPattern) {
  forEachLevel(
      [](const Hierarchy& h, Scheme s, const WaveletOptions& k, int j, const AlphaMatrix& alpha) {
        const int n = h.numVertices(j), added = h.numVertices(j + 1) - n;
        ASSERT_EQ(alpha.rows(), n);
        ASSERT_EQ(alpha.cols(), added);
        const SparseMatrix Q = synthesisMatrix(h, s, j, alpha);
        EXPECT_EQ(Q.rows(), h.numVertices(j + 1));
        EXPECT_EQ(Q.cols(), added);
        if (k.kind == WaveletKind::Lazy) {
          EXPECT_EQ(alpha.nonZeros(), 0);
          EXPECT_EQ(Q.nonZeros(), added);
          for (int e = 0; e < added; ++e) EXPECT_EQ(Q.coeff(n + e, e), 1.0);
        }
        if (k.kind == WaveletKind::Quasi)
          for (int e = 0; e < added; ++e) {
            const auto [a, b] = h.parentEdge(j, e);
            EXPECT_EQ(pattern(alpha, e), ringsAround(h.connectivity(j), a, b, k.rings))
                << "new vertex " << n + e;
          }
      });
}

// The Galerkin condition on the assembled matrices, independently of orthogonality():
// psi^j_m is orthogonal to phi^j_k for every k in S(m), to rounding, and to every
// phi^j_k for pre-wavelets. Lazy wavelets are not (the check is not vacuous).
TEST(Wavelets, GalerkinConditionOnTheAssembledGram) {
  forEachLevel(
      [](const Hierarchy& h, Scheme s, const WaveletOptions& k, int j, const AlphaMatrix& alpha) {
        const OrthogonalityStats o = measured(normalisedInnerProducts(h, s, j, alpha), alpha);
        EXPECT_LT(o.worstInside, 1e-12);
        if (k.kind == WaveletKind::Pre) {
          EXPECT_LT(o.worst, 1e-12);
        }
        if (k.kind == WaveletKind::Lazy) {
          EXPECT_GT(o.worst, 0.1);
        }
      });
}

// orthogonality() reports what wavelets.h defines; on the octahedron's level 1 -> 2
// every ring brings the quasi-wavelets closer to orthogonal, from the lazy wavelets
// to the pre-wavelets.
TEST(Wavelets, OrthogonalityStatsMatchTheirDefinitionAndImproveWithRings) {
  const TriMesh base = shapes::octahedron();
  const Hierarchy h(base.F, 6, 2);
  for (Scheme s : {Scheme::Loop, Scheme::Linear}) {
    double previous = 2.0;  // c <= 1 (Cauchy-Schwarz)
    for (const WaveletOptions& k : {kLazy, quasi(0), quasi(1), quasi(2), kPre}) {
      SCOPED_TRACE(std::string(schemeName(s)) + " " + waveletsName(k));
      const AlphaMatrix alpha = waveletCorrections(h, s, k)[1];
      const OrthogonalityStats reported = orthogonality(h, s, 1, alpha);
      const OrthogonalityStats expected = measured(normalisedInnerProducts(h, s, 1, alpha), alpha);
      EXPECT_NEAR(reported.worstInside, expected.worstInside, 1e-12);
      EXPECT_NEAR(reported.worst, expected.worst, 1e-12);
      EXPECT_NEAR(reported.mean, expected.mean, 1e-12);
      EXPECT_LT(reported.worstInside, 1e-12);
      EXPECT_LE(reported.mean, reported.worst);
      EXPECT_LT(reported.worst, previous);
      previous = reported.worst;
    }
    EXPECT_LT(previous, 1e-12);  // pre-wavelets
  }
}

// When the r-ring of every edge is the whole of M^j (the octahedron's 1-rings at
// level 0), quasi-wavelets are pre-wavelets.
TEST(Wavelets, QuasiWaveletsOverTheWholeLevelArePreWavelets) {
  const TriMesh base = shapes::octahedron();
  const Hierarchy h(base.F, 6, 1);
  for (Scheme s : {Scheme::Loop, Scheme::Linear}) {
    SCOPED_TRACE(schemeName(s));
    const AlphaMatrix q = waveletCorrections(h, s, quasi(1))[0];
    const AlphaMatrix p = waveletCorrections(h, s, kPre)[0];
    for (int e = 0; e < q.cols(); ++e) EXPECT_EQ(pattern(q, e).size(), 6u);
    EXPECT_LT(Eigen::MatrixXd(Eigen::MatrixXd(q) - Eigen::MatrixXd(p)).cwiseAbs().maxCoeff(),
              1e-13);
  }
}

// On the torus every vertex is regular: a handful of distinct neighbourhoods (the
// first levels, before rings stop wrapping around) serve thousands of wavelets. Every
// new vertex is either solved or reused; lazy wavelets without norms solve nothing.
TEST(Wavelets, ReuseOnARegularSurface) {
  const TriMesh base = shapes::torus();
  const Hierarchy h(base.F, static_cast<int>(base.V.rows()), 4);
  const long long added = h.numVertices(4) - h.numVertices(0);
  for (Scheme s : {Scheme::Loop, Scheme::Linear})
    for (const WaveletOptions& k : {kLazy, quasi(0), quasi(1), quasi(2)}) {
      SCOPED_TRACE(std::string(schemeName(s)) + " " + waveletsName(k));
      WaveletStats stats;
      std::vector<Eigen::VectorXd> norms;
      const std::vector<AlphaMatrix> alpha = waveletCorrections(h, s, k, {}, &stats);
      if (k.kind == WaveletKind::Lazy) {
        EXPECT_EQ(stats.localSolves + stats.reused, 0);
        for (int j = 0; j < 4; ++j) {
          EXPECT_EQ(alpha[j].nonZeros(), 0);
          EXPECT_EQ(alpha[j].rows(), h.numVertices(j));
          EXPECT_EQ(alpha[j].cols(), h.numVertices(j + 1) - h.numVertices(j));
        }
        waveletCorrections(h, s, k, {}, &stats, &norms);  // the norms need the solves
      }
      EXPECT_EQ(stats.localSolves + stats.reused, added);
      EXPECT_GE(stats.localSolves, 1);
      EXPECT_LT(stats.localSolves * 500, added) << stats.localSolves << " solves";
    }
}

// A decoder's corrections (the masked overload): the marked columns are those of the
// whole alpha^j (to rounding: which wavelet first solves a neighbourhood shared by
// others may differ), the others empty; a mask of the wrong shape is refused.
TEST(Wavelets, OnlyTheMarkedColumnsWhenMasked) {
  const TriMesh base = shapes::byName("valences");
  const Hierarchy h(base.F, static_cast<int>(base.V.rows()), 3);
  for (Scheme s : {Scheme::Loop, Scheme::Linear})
    for (const WaveletOptions& k : {kLazy, quasi(0), quasi(1), kPre}) {
      SCOPED_TRACE(std::string(schemeName(s)) + " " + waveletsName(k));
      const std::vector<AlphaMatrix> whole = waveletCorrections(h, s, k);
      std::vector<std::vector<char>> needed(3);
      for (int j = 0; j < 3; ++j) {
        needed[j].resize(static_cast<std::size_t>(h.numVertices(j + 1) - h.numVertices(j)));
        for (std::size_t e = 0; e < needed[j].size(); ++e) needed[j][e] = (e * 7 + j) % 3 == 0;
      }
      const std::vector<AlphaMatrix> masked = waveletCorrections(h, s, k, needed);
      ASSERT_EQ(masked.size(), 3u);
      for (int j = 0; j < 3; ++j) {
        ASSERT_EQ(masked[j].rows(), whole[j].rows());
        ASSERT_EQ(masked[j].cols(), whole[j].cols());
        for (Eigen::Index e = 0; e < whole[j].cols(); ++e) {
          const Eigen::VectorXd a = Eigen::MatrixXd(masked[j].col(e)),
                                b = Eigen::MatrixXd(whole[j].col(e));
          if (needed[j][static_cast<std::size_t>(e)] || k.kind == WaveletKind::Lazy ||
              k.kind == WaveletKind::Pre) {
            EXPECT_LE((a - b).lpNorm<Eigen::Infinity>(), 1e-12) << "level " << j << " column " << e;
          } else {
            EXPECT_EQ(masked[j].col(e).nonZeros(), 0) << "level " << j << " column " << e;
          }
        }
      }
    }
  std::vector<std::vector<char>> wrong(2);
  expectContains(errorOf([&] { waveletCorrections(h, Scheme::Loop, quasi(1), wrong); }),
                 {"one mask per level"});
  wrong.resize(3);
  expectContains(errorOf([&] { waveletCorrections(h, Scheme::Loop, quasi(1), wrong); }),
                 {"level 0's mask has 0 entries"});
}

TEST(Wavelets, RejectsRingsOutOfRange) {
  const TriMesh base = shapes::octahedron();
  const Hierarchy h(base.F, 6, 1);
  for (int rings : {-1, 9})
    expectContains(errorOf([&] { waveletCorrections(h, Scheme::Loop, quasi(rings)); }),
                   {"rings must be in 0..8", std::to_string(rings)});
}

// <psi^j_m, phi^j_k> = 0 exactly for every k in S(m) (the Galerkin condition), and
// for every k with pre-wavelets; rows of P sum to one.
TEST(Wavelets, GalerkinOrthogonalityInsideTheSupport) {
  for (auto& [name, base] : shapes::all())
    for (Scheme s : {Scheme::Loop, Scheme::Linear})
      for (WaveletOptions k :
           {WaveletOptions{WaveletKind::Quasi, 0}, WaveletOptions{WaveletKind::Quasi, 2},
            WaveletOptions{WaveletKind::Pre, 0}}) {
        SCOPED_TRACE(name + " " + schemeName(s) + " " + waveletsName(k));
        const int J = 2;
        Hierarchy h(base.F, static_cast<int>(base.V.rows()), J);
        const auto alphas = waveletCorrections(h, s, k);
        for (int j = 0; j < J; ++j) {
          const SparseMatrix& P = h.refinement(s, j);
          for (int r = 0; r < P.rows(); ++r) EXPECT_NEAR(P.row(r).sum(), 1.0, 1e-15);
          const OrthogonalityStats o = orthogonality(h, s, j, alphas[j]);
          EXPECT_LT(o.worstInside, 1e-11) << "level " << j;
          if (k.kind == WaveletKind::Pre) {
            EXPECT_LT(o.worst, 1e-11) << "pre-wavelets, level " << j;
          }
        }
      }
}

// As r grows the quasi-wavelets approach the orthogonal complement.
TEST(Wavelets, OrthogonalityImprovesWithRings) {
  const TriMesh base = shapes::icosahedron();
  for (Scheme s : {Scheme::Loop, Scheme::Linear}) {
    SCOPED_TRACE(schemeName(s));
    Hierarchy h(base.F, 12, 3);
    double previous = 1e300;
    for (int r : {-1, 0, 1, 2, 3}) {
      const WaveletOptions opt =
          r < 0 ? WaveletOptions{WaveletKind::Lazy, 0} : WaveletOptions{WaveletKind::Quasi, r};
      const auto alphas = waveletCorrections(h, s, opt);
      const double worst = orthogonality(h, s, 2, alphas[2]).worst;
      EXPECT_LT(worst, previous) << "r = " << r;
      previous = worst;
    }
  }
}

TEST(Wavelets, RejectsPreWaveletsOnLargeMeshes) {
  const TriMesh base = shapes::octahedron();
  Hierarchy h(base.F, 6, 6);
  EXPECT_THROW(waveletCorrections(h, Scheme::Loop, {WaveletKind::Pre, 0}), Error);
}

TEST(Wavelets, NeighbourhoodsAreShared) {
  const TriMesh base = shapes::octahedron();
  Hierarchy h(base.F, 6, 6);
  WaveletStats stats;
  waveletCorrections(h, Scheme::Loop, {WaveletKind::Quasi, 1}, {}, &stats);
  // 16k wavelets, almost all regular: a few hundred distinct neighbourhoods at most.
  EXPECT_LT(stats.localSolves, 2000);
  EXPECT_GT(stats.reused, 10 * stats.localSolves);
}

// The wavelet norms reported with alpha (shared per neighbourhood) equal
// sqrt(diag(Q^T I^{j+1} Q)) computed from the assembled matrices.
TEST(Wavelets, NormsMatchAssembledGram) {
  for (const char* name : {"tetrahedron", "disc", "valences", "torus"})
    for (Scheme s : {Scheme::Loop, Scheme::Linear})
      for (WaveletOptions k :
           {WaveletOptions{WaveletKind::Lazy, 0}, WaveletOptions{WaveletKind::Quasi, 1},
            WaveletOptions{WaveletKind::Quasi, 2}, WaveletOptions{WaveletKind::Pre, 0},
            WaveletOptions{WaveletKind::Fixed, 0}}) {
        SCOPED_TRACE(std::string(name) + " " + schemeName(s) + " " + waveletsName(k));
        const TriMesh base = shapes::byName(name);
        const int J = k.kind == WaveletKind::Pre ? 2 : 3;  // pre-wavelets are dense
        Hierarchy h(base.F, static_cast<int>(base.V.rows()), J);
        std::vector<Eigen::VectorXd> norms;
        const auto alphas = waveletCorrections(h, s, k, {}, nullptr, &norms);
        ElementGram elements(s);
        for (int j = 0; j < J; ++j) {
          const SparseMatrix Q = synthesisMatrix(h, s, j, alphas[j]);
          const SparseMatrix I = gram(h.connectivity(j + 1), j + 1, elements);
          // diag(Q^T I Q): column c's q_c^T (I q_c), summed over the rows of Q .* (I Q)
          // (the whole product Q^T I Q, most of it off the diagonal, was most of the time).
          const SparseMatrix QIQ = Q.cwiseProduct(SparseMatrix(I * Q));
          const Eigen::VectorXd expected =
              (SparseMatrix(QIQ.transpose()) * Eigen::VectorXd::Ones(Q.rows())).cwiseSqrt();
          ASSERT_EQ(norms[j].size(), expected.size());
          EXPECT_LT((norms[j] - expected).cwiseAbs().maxCoeff(), 1e-12 * expected.maxCoeff())
              << "level " << j;
        }
      }
}

// Fixed wavelets are the quasi-wavelets of the regular lattice written out: on the
// torus's level 3, where every edge's neighbourhood is the lattice's, they equal the
// Galerkin quasi-wavelets with r = 1 column for column; where an end is irregular
// (the valences shape) the column is the two ends with the lattice's r = 0 weight;
// they need no local solve, and asking for their norms leaves alpha unchanged.
TEST(Wavelets, FixedWeightsAreTheLatticeQuasiWavelets) {
  const TriMesh torus = shapes::torus(), valences = shapes::valences();
  const Hierarchy lattice(torus.F, static_cast<int>(torus.V.rows()), 4);
  const Hierarchy irregular(valences.F, static_cast<int>(valences.V.rows()), 2);
  const WaveletOptions fixed{WaveletKind::Fixed, 0};
  for (Scheme s : {Scheme::Loop, Scheme::Linear}) {
    SCOPED_TRACE(schemeName(s));
    WaveletStats stats;
    const AlphaMatrix f = waveletCorrections(lattice, s, fixed, {}, &stats)[3];
    EXPECT_EQ(stats.localSolves + stats.reused, 0);
    const AlphaMatrix q1 = waveletCorrections(lattice, s, quasi(1))[3];
    ASSERT_EQ(f.nonZeros(), q1.nonZeros());
    EXPECT_LT(Eigen::MatrixXd(Eigen::MatrixXd(f) - Eigen::MatrixXd(q1)).cwiseAbs().maxCoeff(),
              1e-12);
    // The lattice's r = 0 weight, and where fixed wavelets use it.
    const AlphaMatrix q0 = waveletCorrections(lattice, s, quasi(0))[3];
    const double pair = q0.valuePtr()[0];
    for (Eigen::Index k = 0; k < q0.nonZeros(); ++k) EXPECT_NEAR(q0.valuePtr()[k], pair, 1e-12);
    const std::vector<AlphaMatrix> fi = waveletCorrections(irregular, s, fixed);
    int twoPoint = 0;
    for (int j = 0; j < 2; ++j) {
      const Connectivity& c = irregular.connectivity(j);
      for (int e = 0; e < fi[j].cols(); ++e) {
        const auto [a, b] = irregular.parentEdge(j, e);
        const bool regular = !c.isBoundaryVertex(a) && !c.isBoundaryVertex(b) &&
                             c.valence(a) == 6 && c.valence(b) == 6;
        const std::set<int> expected = regular ? ringsAround(c, a, b, 1) : std::set<int>{a, b};
        EXPECT_EQ(pattern(fi[j], e), expected);
        if (regular) continue;
        ++twoPoint;
        EXPECT_NEAR(fi[j].coeff(a, e), pair, 1e-12);
        EXPECT_NEAR(fi[j].coeff(b, e), pair, 1e-12);
      }
    }
    EXPECT_GT(twoPoint, 0);
    std::vector<Eigen::VectorXd> norms;
    const std::vector<AlphaMatrix> withNorms =
        waveletCorrections(irregular, s, fixed, {}, nullptr, &norms);
    for (int j = 0; j < 2; ++j)
      EXPECT_EQ(Eigen::MatrixXd(withNorms[j]), Eigen::MatrixXd(fi[j])) << "level " << j;
  }
}

// Edges take their neighbourhood's class from their parent edge's (wavelets.cpp): level j
// of a hierarchy has the corrections and norms of a hierarchy whose base is that level,
// where every key is built, on shapes with boundaries, irregular vertices and a torus
// whose coarse balls wrap around, for every radius the classes pass down from (K >= 3).
TEST(Wavelets, ALevelsCorrectionsAreThoseOfItsLevelAsABase) {
  for (const char* name : {"disc", "valences", "torus"}) {
    const TriMesh base = shapes::byName(name);
    const int J = std::string(name) == "valences" ? 3 : 4;  // its levels grow fastest
    const Hierarchy h(base.F, static_cast<int>(base.V.rows()), J);
    for (Scheme s : {Scheme::Loop, Scheme::Linear})
      for (const WaveletOptions& k :
           {kLazy, quasi(0), quasi(1), quasi(2), WaveletOptions{WaveletKind::Fixed, 0}}) {
        SCOPED_TRACE(std::string(name) + " " + schemeName(s) + " " + waveletsName(k));
        std::vector<Eigen::VectorXd> norms;
        const std::vector<AlphaMatrix> alphas = waveletCorrections(h, s, k, {}, nullptr, &norms);
        for (int j = 1; j < J; ++j) {
          SCOPED_TRACE("level " + std::to_string(j));
          // The same vertices; the new ones (edges) numbered in another order.
          const Hierarchy own(h.faces(j), h.numVertices(j), 1);
          std::vector<Eigen::VectorXd> ownNorms;
          const AlphaMatrix ownAlpha = waveletCorrections(own, s, k, {}, nullptr, &ownNorms)[0];
          ASSERT_EQ(ownAlpha.nonZeros(), alphas[j].nonZeros());
          for (int e = 0; e < ownAlpha.cols(); ++e) {
            const auto [a, b] = own.parentEdge(0, e);
            const int m = h.midpoint(j, a, b) - h.numVertices(j);
            ASSERT_GE(m, 0);
            const Eigen::SparseVector<double> d = ownAlpha.col(e) - alphas[j].col(m);
            double worst = 0;
            for (Eigen::SparseVector<double>::InnerIterator it(d); it; ++it)
              worst = std::max(worst, std::abs(it.value()));
            EXPECT_LE(worst, 1e-12) << "edge " << a << "-" << b;
            // Norms scale by 2^-j with the level (the Gram matrices by 4^-j).
            EXPECT_NEAR(std::ldexp(ownNorms[0](e), -j), norms[j](m), 1e-12 * norms[j](m));
          }
        }
      }
  }
}

// Neighbourhoods stop being new: once the balls around the disc's irregular vertices and
// boundary no longer meet, a further level builds no key (each edge's class comes from
// its parent's), though it has four times the edges.
TEST(Wavelets, AFurtherLevelBuildsNoKeyOnceBallsStopMeeting) {
  const TriMesh base = shapes::disc();
  for (Scheme s : {Scheme::Loop, Scheme::Linear}) {
    SCOPED_TRACE(schemeName(s));
    long long keys[2] = {0, 0};
    for (int J : {5, 6}) {
      const Hierarchy h(base.F, static_cast<int>(base.V.rows()), J);
      WaveletStats stats;
      waveletCorrections(h, s, quasi(1), {}, &stats);
      EXPECT_EQ(stats.localSolves + stats.reused, h.numVertices(J) - h.numVertices(0));
      keys[J - 5] = stats.keys;
    }
    EXPECT_GT(keys[0], 0);
    EXPECT_EQ(keys[1], keys[0]);
  }
}
