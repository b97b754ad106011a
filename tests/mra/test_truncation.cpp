// Truncation (math.md 5): importance, selection, and the exact L2 error.
#include <gtest/gtest.h>

#include "osdmra/base/error.h"
#include "osdmra/mra/filter_bank.h"
#include "osdmra/mra/gram.h"
#include "osdmra/mra/truncation.h"
#include "osdmra/subdivision/shapes.h"

using namespace osdmra;

namespace {

// A named shape refined J = 3 times with noise, analysed with quasi-wavelets (r = 1),
// and its coefficients' importance: what each test below truncates. Built in place
// (the filter bank points at the hierarchy).
struct AnalysedShape {
  static constexpr int J = 3;
  AnalysedShape(const char* name, Scheme s)
      : base(shapes::byName(name)),
        surface(subdivide(base, J, s, 0.05, 3)),
        h(base.F, static_cast<int>(base.V.rows()), J),
        bank(makeFilterBank(h, s, {WaveletKind::Quasi, 1})),
        d(analyze(bank, surface.V)),
        imp(importance(d, bank.norms)) {
    for (const auto& level : imp) total += level.size();
  }
  const TriMesh base;
  const TriMesh surface;
  const Hierarchy h;
  const FilterBank bank;
  const Decomposition d;
  const std::vector<Eigen::VectorXd> imp;
  long long total = 0;
};

}  // namespace

TEST(Truncation, EndsAndExactL2Error) {
  for (const char* name : {"icosahedron", "cylinder"})
    for (Scheme s : {Scheme::Loop, Scheme::Linear}) {
      SCOPED_TRACE(std::string(name) + " " + schemeName(s));
      const AnalysedShape a(name, s);
      const int J = AnalysedShape::J;
      // Everything kept: the input; nothing kept: the base mesh refined.
      const KeepMask all = keepLargest(a.imp, a.total), none = keepLargest(a.imp, 0);
      EXPECT_EQ(countKept(all), a.total);
      EXPECT_EQ(countKept(none), 0);
      EXPECT_LT((synthesize(a.bank, truncate(a.d, all), J) - a.surface.V).cwiseAbs().maxCoeff(),
                1e-12);
      Points coarse = a.d.base;
      for (int j = 0; j < J; ++j) coarse = a.h.refinement(s, j) * coarse;
      EXPECT_LT((synthesize(a.bank, truncate(a.d, none), J) - coarse).cwiseAbs().maxCoeff(), 1e-12);
      // keepAbove and keepLargest agree at the k-th largest importance.
      const KeepMask half = keepLargest(a.imp, a.total / 2);
      double threshold = 1e300;
      for (std::size_t j = 0; j < a.imp.size(); ++j)
        for (Eigen::Index i = 0; i < a.imp[j].size(); ++i)
          if (half[j][i]) threshold = std::min(threshold, a.imp[j](i));
      EXPECT_EQ(countKept(keepAbove(a.imp, threshold)), a.total / 2);
      // The L2 error equals e^T I^J e with the assembled Gram matrix.
      const Points approx = synthesize(a.bank, truncate(a.d, half), J);
      ElementGram elements(s);
      const SparseMatrix I = gram(a.h.connectivity(J), J, elements);
      const Points e = approx - a.surface.V;
      const double expected = std::sqrt((e.transpose() * I * e).trace());
      EXPECT_NEAR(l2Distance(a.h, s, approx, a.surface.V), expected, 1e-12 * expected);
      // Quasi-wavelets are not orthogonal, so fewer coefficients need not mean a larger
      // error in general; on this noise, 5% is farther than 50%, and all is exact.
      const double err5 =
          l2Distance(a.h, s, synthesize(a.bank, truncate(a.d, keepLargest(a.imp, a.total / 20)), J),
                     a.surface.V);
      EXPECT_GT(err5, expected);
    }
}

// synthesizeTruncated is the synthesis of the truncated decomposition bit for bit (the
// same sums in the same order, less the zero terms), at every level, on closed and open
// shapes, for both schemes and masks from empty to full.
TEST(Truncation, SynthesisOfTheKeptCoefficientsIsExact) {
  for (const char* name : {"icosahedron", "cylinder"})
    for (Scheme s : {Scheme::Loop, Scheme::Linear}) {
      SCOPED_TRACE(std::string(name) + " " + schemeName(s));
      const AnalysedShape a(name, s);
      const int J = AnalysedShape::J;
      for (long long count : {0LL, 1LL, a.total / 20, a.total / 2, a.total}) {
        const KeepMask keep = keepLargest(a.imp, count);
        for (int level = 0; level <= J; ++level) {
          const Points expected = synthesize(a.bank, truncate(a.d, keep), level);
          const Points got = synthesizeTruncated(a.bank, a.d, keep, level);
          ASSERT_EQ(got.rows(), expected.rows());
          EXPECT_EQ((got - expected).cwiseAbs().maxCoeff(), 0.0)
              << count << " kept, level " << level;
        }
      }
      KeepMask shortMask = keepLargest(a.imp, a.total);
      shortMask.back().pop_back();
      EXPECT_THROW(synthesizeTruncated(a.bank, a.d, shortMask, J), Error);
      EXPECT_THROW(synthesizeTruncated(a.bank, a.d, keepLargest(a.imp, a.total), J + 1), Error);
    }
}

// Surface-metric weights: 1 wherever the parameterisation preserves area (the
// octahedron refined linearly: every level-J triangle has the same area), the same
// for a scaled copy; with one vertex pulled outwards, above 1 on the edges at it and
// below 1 on the edges whose faces do not touch it.
TEST(Truncation, SurfaceAreaWeights) {
  TriMesh base = shapes::byName("octahedron");
  const int J = 3;
  const Hierarchy h(base.F, static_cast<int>(base.V.rows()), J);
  const Points even = subdivide(base, J, Scheme::Linear).V;
  for (double scale : {1.0, 7.0}) {
    const auto w = surfaceAreaWeights(h, scale * even);
    ASSERT_EQ(static_cast<int>(w.size()), J);
    for (int j = 0; j < J; ++j) {
      ASSERT_EQ(w[j].size(), h.numVertices(j + 1) - h.numVertices(j));
      EXPECT_NEAR(w[j].minCoeff(), 1.0, 1e-12);
      EXPECT_NEAR(w[j].maxCoeff(), 1.0, 1e-12);
    }
  }
  base.V.row(0) *= 3.0;  // the four faces around vertex 0 grow
  const auto w = surfaceAreaWeights(h, subdivide(base, J, Scheme::Linear).V);
  const Connectivity& c = h.connectivity(0);
  for (int e = 0; e < static_cast<int>(w[0].size()); ++e) {
    const auto ab = h.parentEdge(0, e);
    const bool touches = ab[0] == 0 || ab[1] == 0;
    const int he = c.edgeHalfedge(c.findEdge(ab[0], ab[1]));
    const bool faceTouches =
        c.to(Connectivity::next(he)) == 0 || c.to(Connectivity::next(c.twin(he))) == 0;
    if (touches) {
      EXPECT_GT(w[0](e), 1.1) << "edge " << ab[0] << "-" << ab[1];
    } else if (!faceTouches) {
      EXPECT_LT(w[0](e), 0.9) << "edge " << ab[0] << "-" << ab[1];
    }
  }
  EXPECT_THROW(surfaceAreaWeights(h, even.topRows(5)), Error);
  EXPECT_THROW(surfaceAreaWeights(h, Points::Zero(even.rows(), 3)), Error);
}
