// The filter bank (filter_bank.h, math.md section 4): analysis then synthesis gives
// back every surface, for every shape, scheme and kind of wavelet; a singular block is
// an Error naming its level. The wavelets themselves: test_wavelets.cpp.
#include <gtest/gtest.h>

#include <cmath>

#include "osdmra/base/error.h"
#include "osdmra/mra/filter_bank.h"
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

struct Case {
  std::string shape;
  Scheme scheme;
  WaveletOptions wavelets;
};

std::vector<Case> reconstructionCases() {
  std::vector<Case> cases;
  const std::vector<WaveletOptions> kinds = {{WaveletKind::Lazy, 0},  {WaveletKind::Quasi, 0},
                                             {WaveletKind::Quasi, 1}, {WaveletKind::Quasi, 2},
                                             {WaveletKind::Quasi, 4}, {WaveletKind::Pre, 0},
                                             {WaveletKind::Fixed, 0}};
  for (auto& [name, mesh] : shapes::all())
    for (Scheme s : {Scheme::Loop, Scheme::Linear})
      for (const WaveletOptions& k : kinds) cases.push_back({name, s, k});
  return cases;
}

std::string caseName(const testing::TestParamInfo<Case>& info) {
  return info.param.shape + "_" + schemeName(info.param.scheme) + "_" +
         waveletsName(info.param.wavelets);
}

// Readable parameters in test listings (ctest names) instead of raw bytes.
void PrintTo(const Case& c, std::ostream* os) {
  *os << c.shape << " " << schemeName(c.scheme) << " " << waveletsName(c.wavelets);
}

class Reconstruction : public testing::TestWithParam<Case> {};

}  // namespace

TEST_P(Reconstruction, AnalysisThenSynthesisIsIdentity) {
  const Case& c = GetParam();
  const TriMesh base = shapes::byName(c.shape);
  int J = levelsFor(base);
  if (c.wavelets.kind == WaveletKind::Pre)
    while ((base.F.rows() << (2 * J)) / 2 + 2 > kMaxPreWaveletVertices) --J;
  if (c.wavelets.kind == WaveletKind::Quasi && c.wavelets.rings == 4) J = std::min(J, 4);
  const TriMesh surface = subdivide(base, J, c.scheme, 0.05, 7);
  Hierarchy h(base.F, static_cast<int>(base.V.rows()), J);
  const FilterBank bank = makeFilterBank(h, c.scheme, c.wavelets);
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
