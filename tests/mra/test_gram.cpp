// Properties of the inner products (math.md section 2) on every test shape.
#include <gtest/gtest.h>

#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <random>
#include <utility>
#include <vector>

#include "osdmra/mra/gram.h"
#include "osdmra/subdivision/shapes.h"

using namespace osdmra;

namespace {

struct GramCase {
  std::string shape;
  Scheme scheme;
};

std::string gramCaseName(const testing::TestParamInfo<GramCase>& info) {
  return info.param.shape + "_" + schemeName(info.param.scheme);
}

// Readable parameters in test listings (ctest names) instead of raw bytes.
void PrintTo(const GramCase& c, std::ostream* os) {
  *os << c.shape << " " << schemeName(c.scheme);
}

std::vector<GramCase> allGramCases() {
  std::vector<GramCase> cases;
  for (auto& [name, mesh] : shapes::all())
    for (Scheme s : {Scheme::Loop, Scheme::Linear}) cases.push_back({name, s});
  return cases;
}

class GramProperties : public testing::TestWithParam<GramCase> {};

double maxAbs(const SparseMatrix& A) {
  double m = 0;
  for (int k = 0; k < A.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(A, k); it; ++it) m = std::max(m, std::abs(it.value()));
  return m;
}

}  // namespace

TEST_P(GramProperties, SymmetricDefiniteRefinableAndPartitionOfUnity) {
  const TriMesh base = shapes::byName(GetParam().shape);
  const Scheme scheme = GetParam().scheme;
  const int J = 3;
  Hierarchy h(base.F, static_cast<int>(base.V.rows()), J);
  ElementGram elements(scheme);
  std::vector<SparseMatrix> I;
  for (int j = 0; j <= J; ++j) I.push_back(gram(h.connectivity(j), j, elements));
  for (int j = 0; j <= J; ++j) {
    SCOPED_TRACE("level " + std::to_string(j));
    const SparseMatrix& G = I[j];
    // 1. Symmetric positive definite.
    EXPECT_LT(maxAbs(SparseMatrix(G - SparseMatrix(G.transpose()))), 1e-15);
    Eigen::SimplicialLLT<Eigen::SparseMatrix<double>> llt{Eigen::SparseMatrix<double>(G)};
    EXPECT_EQ(llt.info(), Eigen::Success);
    // 3. Partition of unity: all entries sum to the number of base faces.
    EXPECT_NEAR(G.sum(), static_cast<double>(base.F.rows()), 1e-12 * base.F.rows());
    // 2. Refinement relation I^j = P^T I^{j+1} P (paper eq. 3).
    if (j < J) {
      const SparseMatrix& P = h.refinement(scheme, j);
      const SparseMatrix pulled = SparseMatrix(P.transpose()) * I[j + 1] * P;
      EXPECT_LT(maxAbs(SparseMatrix(pulled - G)), 1e-14 * std::ldexp(1.0, -2 * j))
          << "refinement relation";
    }
  }
}

INSTANTIATE_TEST_SUITE_P(AllShapes, GramProperties, testing::ValuesIn(allGramCases()),
                         gramCaseName);

namespace {
double maxAbsDiff(const SparseMatrix& A, const SparseMatrix& B) {
  return maxAbs(SparseMatrix(A - B));
}
}  // namespace

// math.md 2.4: diagonal valence * 4^-j / 6 (faces around the vertex), 4^-j/6 per
// interior edge, 4^-j/12 per boundary edge, zero elsewhere.
TEST(PolyhedralGram, ClosedForm) {
  for (auto& [name, base] : shapes::all()) {
    SCOPED_TRACE(name);
    Hierarchy h(base.F, static_cast<int>(base.V.rows()), 2);
    ElementGram elements(Scheme::Linear);
    for (int j = 0; j <= 2; ++j) {
      const Connectivity& c = h.connectivity(j);
      const SparseMatrix I = gram(c, j, elements);
      const double a = std::ldexp(1.0, -2 * j);
      int entries = 0;
      for (int v = 0; v < c.numVertices(); ++v) {
        EXPECT_DOUBLE_EQ(I.coeff(v, v), c.numVertexFaces(v) * a / 6.0);
        ++entries;
      }
      for (int e = 0; e < c.numEdges(); ++e) {
        const auto [x, y] = c.edgeVertices(e);
        EXPECT_DOUBLE_EQ(I.coeff(x, y), (c.isBoundaryEdge(e) ? a / 12.0 : a / 6.0));
        entries += 2;
      }
      EXPECT_EQ(I.nonZeros(), entries);
    }
  }
}

// math.md 2.5: (P...P)^T L^s (P...P), with L^s the polyhedral Gram at level s,
// converges to the exact Loop Gram about 4x per level; Richardson extrapolation
// of two successive levels agrees with it far more closely.
TEST(LoopGram, ConvergenceOfPolyhedralSumsOnFinerLevels) {
  for (const char* name : {"octahedron", "disc", "valences"}) {
    SCOPED_TRACE(name);
    const TriMesh base = shapes::byName(name);
    const int S = 6;
    Hierarchy h(base.F, static_cast<int>(base.V.rows()), S);
    ElementGram loop(Scheme::Loop), linear(Scheme::Linear);
    const SparseMatrix exact = gram(h.connectivity(0), 0, loop);
    SparseMatrix chain = h.refinement(Scheme::Loop, 0);  // n_s x n_0
    double previousError = 0;
    SparseMatrix previous;
    for (int s = 1; s <= S; ++s) {
      if (s > 1) chain = SparseMatrix(h.refinement(Scheme::Loop, s - 1) * chain);
      const SparseMatrix Is =
          SparseMatrix(chain.transpose()) * gram(h.connectivity(s), s, linear) * chain;
      const double err = maxAbsDiff(Is, exact);
      if (s >= 3) {
        EXPECT_GT(previousError / err, 3.0) << "level " << s;
        EXPECT_LT(previousError / err, 5.0) << "level " << s;
        const SparseMatrix richardson = SparseMatrix((4.0 * Is - previous) / 3.0);
        EXPECT_LT(maxAbsDiff(richardson, exact), err * 0.05) << "level " << s;
      }
      previousError = err;
      previous = Is;
    }
    EXPECT_LT(previousError, 2e-4);
  }
}

// LocalGram (what the wavelet construction reads around one edge) gives the entries of
// the assembled I^j: blocks on any vertex set, columns with their rows ascending.
TEST(LocalGram, BlocksAndColumnsAreTheAssembledGram) {
  for (const char* name : {"valences", "disc", "cylinder"})
    for (Scheme s : {Scheme::Loop, Scheme::Linear}) {
      SCOPED_TRACE(std::string(name) + " " + schemeName(s));
      const TriMesh base = shapes::byName(name);
      Hierarchy h(base.F, static_cast<int>(base.V.rows()), 1);
      ElementGram elements(s);
      const Connectivity& c = h.connectivity(1);
      const SparseMatrix I = gram(c, 1, elements);
      const double tolerance = 1e-15 * maxAbs(I);
      LocalGram local(c, 1, elements);
      std::mt19937 rng(4);
      for (int trial = 0; trial < 20; ++trial) {
        std::vector<int> S;  // distinct vertices, in no particular order
        for (int v = 0; v < c.numVertices(); ++v)
          if (rng() % 5 == 0) S.push_back(v);
        std::shuffle(S.begin(), S.end(), rng);
        const Eigen::MatrixXd B = local.block(S);
        ASSERT_EQ(B.rows(), static_cast<Eigen::Index>(S.size()));
        for (std::size_t a = 0; a < S.size(); ++a)
          for (std::size_t b = 0; b < S.size(); ++b)
            EXPECT_NEAR(B(a, b), I.coeff(S[a], S[b]), tolerance);
      }
      for (int k = 0; k < c.numVertices(); ++k) {
        std::vector<std::pair<int, double>> expected;
        for (int r = 0; r < I.rows(); ++r)
          if (I.coeff(r, k) != 0) expected.emplace_back(r, I.coeff(r, k));
        const std::vector<std::pair<int, double>> column = local.column(k);
        ASSERT_EQ(column.size(), expected.size()) << "column " << k;
        for (std::size_t i = 0; i < column.size(); ++i) {
          EXPECT_EQ(column[i].first, expected[i].first) << "column " << k;
          EXPECT_NEAR(column[i].second, expected[i].second, tolerance) << "column " << k;
        }
      }
    }
}
