// Selection orders (selection.h): both are permutations of every coefficient; the
// rate-distortion order puts cheap refinements before expensive ones of the same
// value, and every prefix that ends after a seed's group is saturated.
#include <gtest/gtest.h>

#include <set>

#include "osdmra/base/error.h"
#include "osdmra/mra/lod.h"
#include "osdmra/mra/selection.h"
#include "osdmra/subdivision/shapes.h"

using namespace osdmra;

namespace {

std::vector<Eigen::VectorXd> randomImportance(const Hierarchy& h, unsigned seed) {
  std::vector<Eigen::VectorXd> imp;
  std::srand(seed);
  for (int j = 0; j < h.levels(); ++j)
    imp.push_back(Eigen::VectorXd::Random(h.numVertices(j + 1) - h.numVertices(j)).cwiseAbs() *
                  std::ldexp(1.0, -j));
  return imp;
}

void expectPermutation(const Hierarchy& h, const CoefficientOrder& order) {
  std::set<std::pair<int, int>> seen(order.begin(), order.end());
  long long total = 0;
  for (int j = 0; j < h.levels(); ++j) total += h.numVertices(j + 1) - h.numVertices(j);
  EXPECT_EQ(static_cast<long long>(order.size()), total);
  EXPECT_EQ(static_cast<long long>(seen.size()), total);
  for (const auto& [j, e] : order) {
    ASSERT_GE(j, 0);
    ASSERT_LT(j, h.levels());
    ASSERT_GE(e, 0);
    ASSERT_LT(e, h.numVertices(j + 1) - h.numVertices(j));
  }
}

KeepMask prefixMask(const Hierarchy& h, const CoefficientOrder& order, std::size_t k) {
  KeepMask keep(h.levels());
  for (int j = 0; j < h.levels(); ++j)
    keep[j].assign(static_cast<std::size_t>(h.numVertices(j + 1) - h.numVertices(j)), 0);
  for (std::size_t i = 0; i < k; ++i) keep[order[i].first][order[i].second] = 1;
  return keep;
}

}  // namespace

TEST(Selection, BothOrdersArePermutations) {
  for (const auto& [name, shape] : shapes::all()) {
    SCOPED_TRACE(name);
    const Hierarchy h(shape.F, static_cast<int>(shape.V.rows()), 3);
    const auto imp = randomImportance(h, 3);
    expectPermutation(h, importanceOrder(imp));
    expectPermutation(h, rateDistortionOrder(h, imp));
    // No importance anywhere: still every coefficient, still deterministic.
    std::vector<Eigen::VectorXd> zero = imp;
    for (auto& level : zero) level.setZero();
    const CoefficientOrder a = rateDistortionOrder(h, zero);
    expectPermutation(h, a);
    EXPECT_EQ(a, rateDistortionOrder(h, zero));
  }
}

// Where the rate-distortion order jumps from one triangle count to the next, the
// prefix is saturated: every coefficient whose vertex the mesh has is in it.
TEST(Selection, PrefixesBeforeEachNewTriangleCountAreSaturated) {
  const TriMesh base = shapes::byName("torus");
  const Hierarchy h(base.F, static_cast<int>(base.V.rows()), 3);
  const CoefficientOrder order = rateDistortionOrder(h, randomImportance(h, 5));
  const std::vector<long long> counts = lodTriangleCounts(h, order);
  int checked = 0;
  for (std::size_t k = 1; k < order.size(); ++k) {
    if (counts[k + 1] == counts[k] || k % 7 != 0) continue;  // a sample of group ends
    const KeepMask keep = prefixMask(h, order, k);
    EXPECT_EQ(countKept(saturate(h, keep)), countKept(keep)) << "prefix " << k;
    ++checked;
  }
  EXPECT_GT(checked, 5);
}

// One large coefficient deep in the hierarchy and equal small ones elsewhere: the
// importance order takes the deep one first whatever it costs; the rate-distortion
// order first takes the coarse refinements that remove more error per triangle
// (possibly through a deeper seed whose closure splits several base faces at once).
TEST(Selection, CheapRefinementsBeforeAnExpensiveOneOfLittleMoreValue) {
  const TriMesh base = shapes::byName("octahedron");
  const Hierarchy h(base.F, static_cast<int>(base.V.rows()), 4);
  std::vector<Eigen::VectorXd> imp;
  for (int j = 0; j < h.levels(); ++j)
    imp.push_back(
        Eigen::VectorXd::Constant(h.numVertices(j + 1) - h.numVertices(j), j == 0 ? 1.0 : 0.0));
  imp[3](0) = 1.2;  // a level-3 split needs coarser ones first: about 30 triangles
  EXPECT_EQ(importanceOrder(imp).front(), std::make_pair(3, 0));
  const CoefficientOrder rd = rateDistortionOrder(h, imp);
  const auto deep = std::find(rd.begin(), rd.end(), std::make_pair(3, 0));
  // Every level-0 coefficient (12, each worth 1) comes before the deep one.
  int level0Before = 0;
  for (auto it = rd.begin(); it != deep; ++it) level0Before += it->first == 0;
  EXPECT_EQ(level0Before, 12);
}

TEST(Selection, RejectsImportanceOfTheWrongShape) {
  const TriMesh base = shapes::byName("tetrahedron");
  const Hierarchy h(base.F, static_cast<int>(base.V.rows()), 2);
  std::vector<Eigen::VectorXd> imp = randomImportance(h, 1);
  imp.pop_back();
  EXPECT_THROW(rateDistortionOrder(h, imp), Error);
  imp = randomImportance(h, 1);
  imp[1].conservativeResize(imp[1].size() - 1);
  EXPECT_THROW(rateDistortionOrder(h, imp), Error);
  EXPECT_EQ(parseSelection("rd"), Selection::RateDistortion);
  EXPECT_EQ(parseSelection("importance"), Selection::Importance);
  EXPECT_THROW(parseSelection("quadric"), Error);
}
