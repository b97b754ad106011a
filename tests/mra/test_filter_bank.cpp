// Wavelet and filter-bank properties (math.md sections 3 and 4) on every shape.
#include <gtest/gtest.h>

#include <cmath>

#include "osdmra/base/error.h"
#include "osdmra/mra/filter_bank.h"
#include "osdmra/mra/gram.h"
#include "osdmra/subdivision/shapes.h"
#include "support.h"

using namespace osdmra;
using namespace osdmra::test;

namespace {

// Levels per shape: up to 6, keeping the finest mesh near 30k faces or fewer.
int levelsFor(const TriMesh& base) {
  int J = 6;
  while (J > 2 && (base.F.rows() << (2 * J)) > 33000) --J;
  return J;
}

struct Kind {
  WaveletKind kind;
  int rings;
  std::string name() const {
    return kind == WaveletKind::Quasi ? "quasi" + std::to_string(rings) : waveletKindName(kind);
  }
};

struct Case {
  std::string shape;
  Scheme scheme;
  Kind kind;
};

std::vector<Case> reconstructionCases() {
  std::vector<Case> cases;
  const std::vector<Kind> kinds = {{WaveletKind::Lazy, 0},  {WaveletKind::Quasi, 0},
                                   {WaveletKind::Quasi, 1}, {WaveletKind::Quasi, 2},
                                   {WaveletKind::Quasi, 4}, {WaveletKind::Pre, 0}};
  for (auto& [name, mesh] : shapes::all())
    for (Scheme s : {Scheme::Loop, Scheme::Linear})
      for (const Kind& k : kinds) cases.push_back({name, s, k});
  return cases;
}

std::string caseName(const testing::TestParamInfo<Case>& info) {
  return info.param.shape + "_" + schemeName(info.param.scheme) + "_" + info.param.kind.name();
}

// Readable parameters in test listings (ctest names) instead of raw bytes.
void PrintTo(const Case& c, std::ostream* os) {
  *os << c.shape << " " << schemeName(c.scheme) << " " << c.kind.name();
}

class Reconstruction : public testing::TestWithParam<Case> {};

}  // namespace

TEST_P(Reconstruction, AnalysisThenSynthesisIsIdentity) {
  const Case& c = GetParam();
  const TriMesh base = shapes::byName(c.shape);
  int J = levelsFor(base);
  if (c.kind.kind == WaveletKind::Pre)
    while ((base.F.rows() << (2 * J)) / 2 + 2 > kMaxPreWaveletVertices) --J;
  if (c.kind.kind == WaveletKind::Quasi && c.kind.rings == 4) J = std::min(J, 4);
  const TriMesh surface = subdivide(base, J, c.scheme, 0.05, 7);
  Hierarchy h(base.F, static_cast<int>(base.V.rows()), J);
  const FilterBank bank = makeFilterBank(h, c.scheme, {c.kind.kind, c.kind.rings});
  const Decomposition d = analyze(bank, surface.V);
  ASSERT_EQ(d.base.rows(), base.V.rows());
  const Points back = synthesize(bank, d, J);
  const double diag = boundingBoxDiagonal(surface.V);
  EXPECT_LT((back - surface.V).cwiseAbs().maxCoeff(), 1e-12 * diag) << "J = " << J;
  // The details of a displaced surface are not all zero: the test is not vacuous.
  EXPECT_GT(d.details.back().cwiseAbs().maxCoeff(), 1e-6 * diag);
}

INSTANTIATE_TEST_SUITE_P(AllShapes, Reconstruction, testing::ValuesIn(reconstructionCases()),
                         caseName);

// <psi^j_m, phi^j_k> = 0 exactly for every k in S(m) (the Galerkin condition), and
// for every k with pre-wavelets; rows of P sum to one.
TEST(Wavelets, GalerkinOrthogonalityInsideTheSupport) {
  for (auto& [name, base] : shapes::all())
    for (Scheme s : {Scheme::Loop, Scheme::Linear})
      for (Kind k :
           {Kind{WaveletKind::Quasi, 0}, Kind{WaveletKind::Quasi, 2}, Kind{WaveletKind::Pre, 0}}) {
        SCOPED_TRACE(name + " " + schemeName(s) + " " + k.name());
        const int J = 2;
        Hierarchy h(base.F, static_cast<int>(base.V.rows()), J);
        const auto alphas = waveletCorrections(h, s, {k.kind, k.rings});
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
      for (Kind k : {Kind{WaveletKind::Lazy, 0}, Kind{WaveletKind::Quasi, 1},
                     Kind{WaveletKind::Quasi, 2}, Kind{WaveletKind::Pre, 0}}) {
        SCOPED_TRACE(std::string(name) + " " + schemeName(s) + " " + k.name());
        const TriMesh base = shapes::byName(name);
        const int J = k.kind == WaveletKind::Pre ? 2 : 3;  // pre-wavelets are dense
        Hierarchy h(base.F, static_cast<int>(base.V.rows()), J);
        std::vector<Eigen::VectorXd> norms;
        const auto alphas = waveletCorrections(h, s, {k.kind, k.rings}, {}, nullptr, &norms);
        ElementGram elements(s);
        for (int j = 0; j < J; ++j) {
          const SparseMatrix Q = synthesisMatrix(h, s, j, alphas[j]);
          const SparseMatrix I = gram(h.connectivity(j + 1), j + 1, elements);
          const SparseMatrix IQ = I * Q;
          const Eigen::VectorXd expected =
              SparseMatrix(SparseMatrix(Q.transpose()) * IQ).diagonal().cwiseSqrt();
          ASSERT_EQ(norms[j].size(), expected.size());
          EXPECT_LT((norms[j] - expected).cwiseAbs().maxCoeff(), 1e-12 * expected.maxCoeff())
              << "level " << j;
        }
      }
}

TEST(FilterBank, SingularVertexRuleBlockIsReportedWithItsLevel) {
  // Two identical rows: singular. The message must name the level.
  SparseMatrix P(3, 3);
  std::vector<Eigen::Triplet<double>> t = {
      {0, 0, 0.5}, {0, 1, 0.5}, {1, 0, 0.5}, {1, 1, 0.5}, {2, 2, 1.0}};
  P.setFromTriplets(t.begin(), t.end());
  Points rhs = Points::Ones(3, 3);
  rhs(1, 0) = 2.0;  // inconsistent right-hand side
  expectContains(errorOf([&] { solveOldBlock(P, 4, rhs); }), {"level 4", "singular"});
  // A regular block solves to its true residual.
  SparseMatrix Q(3, 3);
  std::vector<Eigen::Triplet<double>> q = {{0, 0, 0.75}, {0, 1, 0.25}, {1, 1, 1.0}, {2, 2, 0.5}};
  Q.setFromTriplets(q.begin(), q.end());
  const Points u = solveOldBlock(Q, 0, rhs);
  EXPECT_LT((Q * u - rhs).cwiseAbs().maxCoeff(), 1e-14);
}
