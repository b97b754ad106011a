// The base flips and splits (base_flips.h): each is one more step of the
// parameterisation, so the map stays a bijection and its inverse exact; on a flat input
// the flattened quad is the pair itself, so every point keeps its place in space; caps
// get narrower.
#include <gtest/gtest.h>

#include <algorithm>

#include "osdmra/remesh/base_flips.h"
#include "osdmra/remesh/features.h"
#include "osdmra/subdivision/shapes.h"
#include "parameterisation_checks.h"
#include "support.h"

using namespace osdmra;
using namespace osdmra::remeshing;
using namespace osdmra::test;

namespace {

// Where point v's place on the base is in space.
Vec3 onBase(const Simplification& s, int v) {
  const Param& p = s.params[v];
  Vec3 at = Vec3::Zero();
  for (int i = 0; i < 3; ++i) at += p.bary[i] * s.base.V.row(s.base.F(p.face, i)).transpose();
  return at;
}

// The widest angle of a base face, degrees.
double widestAngle(const TriMesh& m, int f) {
  double widest = 0;
  for (int i = 0; i < 3; ++i) {
    const Vec3 a = m.V.row(m.F(f, i)), b = m.V.row(m.F(f, (i + 1) % 3)),
               c = m.V.row(m.F(f, (i + 2) % 3));
    widest = std::max(widest, angleBetween(b - a, c - a) * 180 / kPi);
  }
  return widest;
}

int capsOver(const TriMesh& m, double angle) {
  int caps = 0;
  for (int f = 0; f < m.F.rows(); ++f) caps += widestAngle(m, f) > angle;
  return caps;
}

// `input` simplified to 40 base faces, the set-up of every test here.
Simplification simplified40(const TriMesh& input) {
  return simplify(input, detectFeatures(input, 70.0), 40);
}

// Flips or splits checked on grids of `levels` sampled from `input`, at most `maxSplits`.
BaseFlipOptions checkedOn(const TriMesh& input, int levels, int maxSplits = 0) {
  BaseFlipOptions options;
  options.levels = levels;
  options.input = &input;
  options.maxSplits = maxSplits;
  return options;
}

// A flat disc, its interior vertices moved within the plane (a base with caps).
TriMesh jitteredFlatDisc() {
  TriMesh m = subdivide(shapes::disc(4), 3, Scheme::Linear);
  const Connectivity c(m.F, static_cast<int>(m.V.rows()));
  std::vector<char> rim(m.V.rows(), 0);
  for (int h = 0; h < 3 * c.numFaces(); ++h)
    if (c.twin(h) < 0) rim[c.from(h)] = rim[c.to(h)] = 1;
  m.V.col(2).setZero();  // shapes::disc is not flat
  for (int v = 0; v < m.V.rows(); ++v)
    if (!rim[v]) {
      m.V(v, 0) += 0.012 * std::sin(7.0 * v);
      m.V(v, 1) += 0.012 * std::cos(5.0 * v);
    }
  return m;
}

}  // namespace

TEST(BaseFlips, OnAFlatInputEveryPointKeepsItsPlaceInSpace) {
  const TriMesh input = jitteredFlatDisc();
  Simplification s = simplified40(input);
  std::vector<Vec3> before(input.V.rows());
  for (int v = 0; v < input.V.rows(); ++v) before[v] = onBase(s, v);
  const int faces = static_cast<int>(s.base.F.rows());
  BaseFlipOptions options;
  options.capAngle = 90;
  const BaseFlipReport report = flipCaps(s, options);
  EXPECT_GT(report.flips, 0);
  EXPECT_EQ(s.base.F.rows(), faces);
  EXPECT_EQ(topology(s.base), topology(input));
  validate(s.base, "flipped base");
  for (int v = 0; v < input.V.rows(); ++v)
    EXPECT_LT((onBase(s, v) - before[v]).norm(), 1e-12) << "input vertex " << v;
  expectBijection(input, s, static_cast<int>(input.F.rows() / 4));
}

TEST(BaseFlips, TracingBackIsStillTheExactInverse) {
  const TriMesh input = subdivide(shapes::torus(), 3, Scheme::Loop, 0.01, 5);
  Simplification s = simplify(input, detectFeatures(input, 70.0), 60);
  BaseFlipOptions options;
  options.capAngle = 90;
  const int capsBefore = capsOver(s.base, 100);
  const BaseFlipReport report = flipCaps(s, options);
  EXPECT_GT(report.flips, 0);
  EXPECT_LT(capsOver(s.base, 100), capsBefore);
  EXPECT_EQ(topology(s.base), topology(input));
  expectTracingBackIsTheIdentity(input, s);
  expectBijection(input, s, static_cast<int>(input.F.rows() / 8));
}

TEST(BaseFlips, NeverFlipsAFeatureOrBoundaryEdge) {
  // A cube's edges are feature lines, a disc's rim its boundary: with every pair the flip
  // narrows flipped, each is still an edge of the base.
  for (const TriMesh& input : {subdivide(unitCube(), 3, Scheme::Linear), jitteredFlatDisc()}) {
    SCOPED_TRACE(input.F.rows());
    Simplification s = simplified40(input);
    const Connectivity before(s.base.F, static_cast<int>(s.base.V.rows()));
    std::vector<std::uint64_t> kept;
    for (int h = 0; h < 3 * before.numFaces(); ++h) {
      const int a = before.from(h), b = before.to(h);
      bool feature = false;
      for (int v = 0; v < input.V.rows(); ++v)
        for (int w = 0; w < input.V.rows() && s.baseOf[v] == a; ++w)
          feature = feature || (s.baseOf[w] == b && s.featureEdges.count(edgeKey(v, w)));
      if (before.twin(h) < 0 || feature) kept.push_back(edgeKey(a, b));
    }
    std::sort(kept.begin(), kept.end());
    kept.erase(std::unique(kept.begin(), kept.end()), kept.end());
    ASSERT_FALSE(kept.empty());
    BaseFlipOptions options;
    options.capAngle = 60;
    const BaseFlipReport report = flipCaps(s, options);
    EXPECT_GT(report.flips, 0);
    const Connectivity after(s.base.F, static_cast<int>(s.base.V.rows()));
    std::vector<char> found(kept.size(), 0);
    for (int h = 0; h < 3 * after.numFaces(); ++h) {
      const auto at = std::find(kept.begin(), kept.end(), edgeKey(after.from(h), after.to(h)));
      if (at != kept.end()) found[at - kept.begin()] = 1;
    }
    for (std::size_t k = 0; k < kept.size(); ++k) EXPECT_TRUE(found[k]) << "edge " << k;
  }
}

TEST(BaseFlips, NoFlipWhereTheSampledGridDoesNotFold) {
  // The same flat disc with the fold check: its grid sampled through the exact map
  // folds nowhere, so no candidate is flipped (each is refused), where without the
  // check the flips' shape alone made some.
  const TriMesh input = jitteredFlatDisc();
  Simplification s = simplified40(input);
  const Faces before = s.base.F;
  const BaseFlipReport report = flipCaps(s, checkedOn(input, 3));
  EXPECT_EQ(report.flips, 0);
  EXPECT_GT(report.refused, 0);
  EXPECT_EQ(s.base.F, before);
}

namespace {

// The squared distances of the input's points (its vertices that are no base vertex) to
// the planes of the base faces that hold them: what flipTowardsInput lowers.
double planeError(const TriMesh& input, const Simplification& s) {
  double sum = 0;
  for (int v = 0; v < input.V.rows(); ++v) {
    if (s.baseOf[v] >= 0) continue;
    const int f = s.params[v].face;
    const Vec3 a = s.base.V.row(s.base.F(f, 0)), b = s.base.V.row(s.base.F(f, 1)),
               c = s.base.V.row(s.base.F(f, 2));
    const Vec3 n = (b - a).cross(c - a).normalized();
    const double d = n.dot(input.V.row(v).transpose() - a);
    sum += d * d;
  }
  return sum;
}

}  // namespace

TEST(BaseFlips, TowardsTheInputTheBaseComesNearerAndTheMapStaysABijection) {
  // A torus displaced by noise: flips where the points a pair holds lie nearer the
  // flipped faces' planes lower the sum over the base, keep its vertices and topology,
  // and the parameterisation is still a bijection with an exact inverse.
  const TriMesh input = subdivide(shapes::torus(), 3, Scheme::Loop, 0.01, 5);
  Simplification s = simplify(input, detectFeatures(input, 70.0), 60);
  const Eigen::Index vertices = s.base.V.rows(), faces = s.base.F.rows();
  const double before = planeError(input, s);
  BaseFlipOptions options;
  options.input = &input;
  options.stretch = 2;
  const BaseFlipReport report = flipTowardsInput(s, options);
  EXPECT_GT(report.flips, 0);
  EXPECT_LT(planeError(input, s), before);
  EXPECT_EQ(s.base.V.rows(), vertices);
  EXPECT_EQ(s.base.F.rows(), faces);
  EXPECT_EQ(topology(s.base), topology(input));
  validate(s.base, "flipped base");
  expectTracingBackIsTheIdentity(input, s);
  expectBijection(input, s, static_cast<int>(input.F.rows() / 8));
}

TEST(BaseFlips, TowardsTheInputNoFlipOnAFlatInput) {
  // Every point of a flat input lies in every base face's plane: no flip fits it better.
  const TriMesh input = jitteredFlatDisc();
  Simplification s = simplified40(input);
  const Faces before = s.base.F;
  BaseFlipOptions options;
  options.input = &input;
  options.stretch = 2;
  EXPECT_EQ(flipTowardsInput(s, options).flips, 0);
  EXPECT_EQ(s.base.F, before);
}

namespace {

// The checks every split base must pass: `splits` more vertices and twice as many more
// faces (one split on the boundary adds one face fewer), the same topology, every base
// vertex an input vertex where it was, and the map still a bijection whose inverse is
// exact.
void expectSplitBase(const TriMesh& input, const Simplification& s, Eigen::Index faces,
                     Eigen::Index vertices, int splits) {
  EXPECT_EQ(s.base.V.rows(), vertices + splits);
  EXPECT_LE(s.base.F.rows(), faces + 2 * splits);
  EXPECT_GE(s.base.F.rows(), faces + splits);
  EXPECT_EQ(topology(s.base), topology(input));
  validate(s.base, "split base");
  for (int v = 0; v < input.V.rows(); ++v) {
    if (s.baseOf[v] >= 0) {
      EXPECT_EQ(s.base.V.row(s.baseOf[v]), input.V.row(v)) << "vertex " << v;
    }
  }
  expectTracingBackIsTheIdentity(input, s);
  expectBijection(input, s, static_cast<int>(input.F.rows() / 8));
}

int boundaryVertices(const TriMesh& m) {
  const Connectivity c(m.F, static_cast<int>(m.V.rows()));
  std::vector<char> rim(m.V.rows(), 0);
  for (int h = 0; h < 3 * c.numFaces(); ++h)
    if (c.twin(h) < 0) rim[c.from(h)] = 1;
  return static_cast<int>(std::count(rim.begin(), rim.end(), 1));
}

}  // namespace

TEST(BaseSplits, SplitsFoldingFacesAndTracingBackIsStillTheExactInverse) {
  // A torus displaced by noise: its faces' longest edges split (input vertices made base
  // vertices again), and the parameterisation is still a bijection with an exact inverse.
  const TriMesh input = subdivide(shapes::torus(), 3, Scheme::Loop, 0.03, 5);
  Simplification s = simplified40(input);
  const Eigen::Index faces = s.base.F.rows(), vertices = s.base.V.rows();
  const BaseFlipOptions options = checkedOn(input, 4, 4);
  const std::vector<int> folds(faces, 1);  // every face a candidate
  const BaseFlipReport report = splitFoldingFaces(s, folds, options);
  EXPECT_EQ(report.splits, options.maxSplits);
  expectSplitBase(input, s, faces, vertices, report.splits);
}

TEST(BaseSplits, WithoutTheFoldCheckTheMapIsStillABijection) {
  // The check of the exact grid over the new faces is the only one dropped: the splits
  // are still recorded steps of the parameterisation, the map a bijection with an exact
  // inverse.
  const TriMesh input = subdivide(shapes::torus(), 3, Scheme::Loop, 0.03, 5);
  Simplification s = simplified40(input);
  const Eigen::Index faces = s.base.F.rows(), vertices = s.base.V.rows();
  BaseFlipOptions options = checkedOn(input, 4, 6);
  options.splitFoldCheck = false;
  const BaseFlipReport report = splitFoldingFaces(s, std::vector<int>(faces, 1), options);
  EXPECT_EQ(report.splits, options.maxSplits);
  EXPECT_EQ(report.splitsFoldingMore, 0);
  expectSplitBase(input, s, faces, vertices, report.splits);
}

namespace {

Vec3 pointOn(const TriMesh& m, const SurfacePoint& p) {
  Vec3 at = Vec3::Zero();
  for (int i = 0; i < 3; ++i) at += p.bary[i] * m.V.row(m.F(p.triangle, i)).transpose();
  return at;
}

}  // namespace

TEST(BaseSplits, WhereThePairHoldsNoInputVertexAPointOfTheInputIsMadeOne) {
  // A coarse torus (256 faces) simplified to 40: many pairs of base faces hold no input
  // vertex that fits, so splits are made at points of the input (Simplification::added),
  // which the history maps as any other: the base vertex lies where the exact map puts
  // its corner from each of its faces, at no input vertex, and the map is still a
  // bijection with an exact inverse.
  const TriMesh input = shapes::torus(16, 8);
  Simplification s = simplified40(input);
  const Eigen::Index faces = s.base.F.rows(), vertices = s.base.V.rows();
  BaseFlipOptions options = checkedOn(input, 3, 6);
  options.splitAtPoints = true;
  const std::vector<int> folds(faces, 1);
  Simplification without = s;
  const BaseFlipReport report = splitFoldingFaces(s, folds, options);
  ASSERT_FALSE(s.added.empty());
  expectSplitBase(input, s, faces, vertices, report.splits);
  for (std::size_t k = 0; k < s.added.size(); ++k) {
    const auto& added = s.added[k];
    const Vec3 at = pointOn(input, added.at);
    EXPECT_EQ(s.base.V.row(added.base).transpose(), at);
    EXPECT_LT(*std::max_element(added.at.bary.begin(), added.at.bary.end()), 1 - 1e-9);
    int seen = 0;
    for (Eigen::Index f = 0; f < s.base.F.rows(); ++f)
      for (int i = 0; i < 3; ++i) {
        if (s.base.F(f, i) != added.base) continue;
        std::array<double, 3> corner{};
        corner[i] = 1;
        const Vec3 traced = pointOn(input, traceToInput(s.history, static_cast<int>(f), corner));
        EXPECT_LT((traced - at).norm(), 1e-9) << "added vertex " << k << ", base face " << f;
        ++seen;
      }
    EXPECT_GE(seen, 3);
  }
  // Without the option the same candidates split at input vertices alone.
  options.splitAtPoints = false;
  splitFoldingFaces(without, folds, options);
  EXPECT_TRUE(without.added.empty());
  // Flips over such a base (by shape alone) keep the map's inverse exact too.
  const Eigen::Index added = static_cast<Eigen::Index>(s.added.size());
  EXPECT_GT(flipCaps(s).flips, 0);
  EXPECT_EQ(static_cast<Eigen::Index>(s.added.size()), added);
  expectTracingBackIsTheIdentity(input, s);
  validate(s.base, "flipped split base");
}

TEST(BaseSplits, ABoundaryEdgeIsSplitAtAVertexOfItsLine) {
  // A flat disc: where a face's longest edge is on the rim, the vertex made a base vertex
  // is one of the rim's, so the boundary stays the input's.
  const TriMesh input = jitteredFlatDisc();
  Simplification s = simplified40(input);
  const Eigen::Index faces = s.base.F.rows(), vertices = s.base.V.rows();
  const int rim = boundaryVertices(s.base);
  const BaseFlipReport report =
      splitFoldingFaces(s, std::vector<int>(faces, 1), checkedOn(input, 3, 40));
  EXPECT_GT(report.splits, 0);
  EXPECT_GT(boundaryVertices(s.base), rim);
  expectSplitBase(input, s, faces, vertices, report.splits);
}

TEST(BaseSplits, NoSplitWithoutFoldsOrRoom) {
  const TriMesh input = jitteredFlatDisc();
  Simplification s = simplified40(input);
  const Faces before = s.base.F;
  EXPECT_EQ(
      splitFoldingFaces(s, std::vector<int>(before.rows(), 0), checkedOn(input, 3, 40)).splits, 0);
  EXPECT_EQ(splitFoldingFaces(s, std::vector<int>(before.rows(), 1), checkedOn(input, 3, 0)).splits,
            0);
  EXPECT_EQ(s.base.F, before);
}
