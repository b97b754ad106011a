// Levels of detail from truncated expansions (math.md 5): exact at both ends,
// monotone in epsilon, within budget, vertices on the truncated surface.
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>

#include "osdmra/mra/approximation.h"
#include "osdmra/subdivision/shapes.h"

using namespace osdmra;

namespace {

struct Fixture {
  TriMesh base, surface;
  Hierarchy h;
  FilterBank bank;
  Decomposition d;
  Fixture(const std::string& name, Scheme s, int J)
      : base(shapes::byName(name)),
        surface(subdivide(base, J, s, 0.04, 21)),
        h(base.F, static_cast<int>(base.V.rows()), J),
        bank(makeFilterBank(h, s, {WaveletKind::Quasi, 1})),
        d(analyze(bank, surface.V)) {}
};

}  // namespace

TEST(Approximation, ExactAtBothEndsMonotoneAndWithinBudget) {
  for (const auto& [name, shape] : shapes::all())
    for (Scheme s : {Scheme::Loop, Scheme::Linear}) {
      SCOPED_TRACE(name + " " + schemeName(s));
      const int J = 3;
      const Fixture f(name, s, J);
      const Approximator approx(f.bank, f.d);
      const TriMesh& full = approx.fullResolution();
      // Everything kept: the full-resolution surface (polyhedral: the input itself).
      const Approximation all = approx.keepFraction(1.0);
      EXPECT_EQ(all.triangles(), f.h.numFaces(J));
      EXPECT_LT(approx.l2Error(all), 1e-12);
      for (int i = 0; i < static_cast<int>(all.lod.vertices.size()); ++i)
        EXPECT_LT((all.mesh.V.row(i) - full.V.row(all.lod.vertices[i])).norm(), 1e-12);
      if (s == Scheme::Linear) {
        EXPECT_LT((full.V - f.surface.V).cwiseAbs().maxCoeff(), 1e-12);
      } else {
        Points p, n;
        f.h.loopLimit(J, f.surface.V, p, n);
        EXPECT_LT((full.V - p).cwiseAbs().maxCoeff(), 1e-12);
        for (int i = 0; i < all.mesh.N.rows(); ++i)
          EXPECT_NEAR(all.mesh.N.row(i).norm(), 1.0, 1e-12);
      }
      // Nothing kept: the base mesh, on the base surface.
      const Approximation none = approx.keepCount(0);
      EXPECT_EQ(none.triangles(), f.base.F.rows());
      Points basePoints = f.d.base;
      if (s == Scheme::Loop) {
        Points n;
        f.h.loopLimit(0, f.d.base, basePoints, n);
      }
      for (int i = 0; i < static_cast<int>(none.lod.vertices.size()); ++i)
        EXPECT_LT((none.mesh.V.row(i) - basePoints.row(none.lod.vertices[i])).norm(), 1e-12);
      // Lowering epsilon never lowers the triangle count.
      int previous = 0;
      for (double eps : {1.0, 1e-2, 3e-3, 1e-3, 3e-4, 1e-4, 0.0}) {
        const int t = approx.keepAbove(eps).triangles();
        EXPECT_GE(t, previous) << "epsilon " << eps;
        previous = t;
      }
      EXPECT_EQ(previous, f.h.numFaces(J));
      // Budgets: never above, and adding the next coefficient would exceed it.
      for (long long budget : {f.h.numFaces(J) / 8, f.h.numFaces(J) / 3, f.h.numFaces(J) / 2}) {
        const Approximation a = approx.budget(budget);
        EXPECT_LE(a.triangles(), budget);
        if (a.selected < a.total) {
          EXPECT_GT(approx.keepCount(a.selected + 1).triangles(), budget);
        }
        EXPECT_GE(a.kept, a.selected);
      }
    }
}

// The free coefficients change nothing but the positions: the same faces, more kept,
// and with --exact (saturate off) exactly the selection. In the importance order
// (the rate-distortion order lists what each refinement frees right after it, so
// its prefixes are mostly saturated already).
TEST(Approximation, FreeCoefficientsKeepTheMesh) {
  for (Scheme s : {Scheme::Loop, Scheme::Linear}) {
    SCOPED_TRACE(schemeName(s));
    const Fixture f("icosahedron", s, 4);
    ApproximationOptions options;
    options.selection = Selection::Importance;
    const Approximator saturated(f.bank, f.d, options);
    ApproximationOptions exactOptions = options;
    exactOptions.saturate = false;
    const Approximator exact(f.bank, f.d, exactOptions);
    for (long long count : {10LL, 100LL, 1000LL}) {
      const Approximation a = saturated.keepCount(count), b = exact.keepCount(count);
      EXPECT_EQ(a.mesh.F, b.mesh.F);
      EXPECT_EQ(a.selected, count);
      EXPECT_EQ(b.selected, count);
      EXPECT_EQ(b.kept, count);
      EXPECT_GT(a.kept, count);
      EXPECT_EQ(a.lod.vertices, b.lod.vertices);
    }
  }
}

// The rate-distortion order (the default): on every test shape and both schemes, a
// larger budget never gives a larger exact L2 error, the budget still fits, and
// everything kept is exact. (Each prefix's mesh is the one extractLod gives, so the
// conformity checks of test_lod.cpp apply to it unchanged.)
TEST(Approximation, RateDistortionErrorNeverIncreasesWithTheBudget) {
  for (const auto& [name, shape] : shapes::all())
    for (Scheme s : {Scheme::Loop, Scheme::Linear}) {
      SCOPED_TRACE(name + " " + schemeName(s));
      const int J = 3;
      const Fixture f(name, s, J);
      const Approximator approx(f.bank, f.d);
      const auto& counts = approx.triangleCounts();
      ASSERT_EQ(static_cast<long long>(counts.size()), approx.numCoefficients() + 1);
      for (std::size_t k = 1; k < counts.size(); ++k) ASSERT_GE(counts[k], counts[k - 1]);
      double previous = std::numeric_limits<double>::infinity();
      const long long base = f.h.numFaces(0), full = f.h.numFaces(J);
      for (long long budget = base; budget <= full; budget += std::max<long long>(1, full / 64)) {
        const Approximation a = approx.budget(budget);
        ASSERT_LE(a.triangles(), budget);
        const double e = approx.l2Error(a);
        EXPECT_LE(e, previous) << "budget " << budget << ", " << a.triangles() << " triangles";
        previous = std::min(previous, e);
      }
      EXPECT_LT(approx.l2Error(approx.budget(full)), 1e-12);
    }
}

// What the rate-distortion order is for: over the whole range of budgets it removes
// more error per triangle than the importance order, so the exact L2 error summed over
// a sweep of 16 budgets is lower. It is a greedy, so not on every surface: on the
// tetrahedron (4 base faces, where each early refinement is a large share of the mesh)
// with Loop it is 1% higher. Over the 18 cases it is 3.4% lower on average; the
// test asks for a lower sum in at least 16 of them and a mean ratio below 0.98, which
// an order blind to the triangle cost (or a random one) would not reach.
TEST(Approximation, RateDistortionBeatsTheImportanceOrderOverTheRange) {
  int better = 0, cases = 0;
  double ratios = 0;
  for (const auto& [name, shape] : shapes::all())
    for (Scheme s : {Scheme::Loop, Scheme::Linear}) {
      SCOPED_TRACE(name + " " + schemeName(s));
      const Fixture f(name, s, 3);
      ApproximationOptions byImportance;
      byImportance.selection = Selection::Importance;
      const Approximator rd(f.bank, f.d), imp(f.bank, f.d, byImportance);
      const long long base = f.h.numFaces(0), full = f.h.numFaces(3);
      double sumRd = 0, sumImp = 0;
      for (long long budget = base; budget < full; budget += std::max<long long>(1, full / 16)) {
        sumRd += rd.l2Error(rd.budget(budget));
        sumImp += imp.l2Error(imp.budget(budget));
      }
      ASSERT_GT(sumImp, 0);
      better += sumRd < sumImp;
      ratios += sumRd / sumImp;
      ++cases;
    }
  EXPECT_GE(better, cases - 2);
  EXPECT_LT(ratios / cases, 0.98);
}
