// The pipeline (pipeline.h): a file to a validated surface, or through the remesher to
// one with subdivision connectivity; a surface in any order to its decomposition and
// back in that order; a stored decomposition to the same surface; levels of detail
// and their errors; and an AnalysedSurface that keeps working when moved.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "osdmra/base/error.h"
#include "osdmra/mesh/io.h"
#include "osdmra/mra/mra_file.h"
#include "osdmra/pipeline.h"
#include "osdmra/subdivision/shapes.h"
#include "support.h"

using namespace osdmra;
using namespace osdmra::test;

namespace {

constexpr int kLevels = 3;

// A displaced octahedron refined kLevels times (Loop), vertices, faces and corners
// shuffled: a surface with subdivision connectivity that does not show it.
TriMesh shuffledSurface() {
  return shuffle(subdivide(shapes::octahedron(), kLevels, Scheme::Loop, 0.05, 5), 31);
}

double maxDifference(const Points& a, const Points& b) {
  return (a - b).cwiseAbs().maxCoeff();
}

// The analysed surface every test below starts from, made once.
const AnalysedSurface& analysed() {
  static const AnalysedSurface a(shuffledSurface(), {}, "octahedron.ply");
  return a;
}

}  // namespace

TEST(LoadSurface, ReadsAndValidatesAFile) {
  TempDir dir;
  const TriMesh mesh = subdivide(shapes::torus(), 2, Scheme::Loop, 0.05, 2);
  const std::string path = dir.file("torus.ply");
  writeMesh(path, mesh);
  const LoadedSurface s = loadSurface(path);
  EXPECT_EQ(s.source, path);
  EXPECT_EQ(s.mesh.V, mesh.V);  // binary PLY is exact
  EXPECT_EQ(s.mesh.F, mesh.F);
  EXPECT_FALSE(s.remeshing.has_value());
  EXPECT_GE(s.seconds, 0.0);
}

// What the remesher is given: the file repaired (here a face turned over, turned back)
// and validated, the repairs counted; what cannot be repaired, an error naming the file.
TEST(LoadSurface, ReadsTheRemesherInputRepaired) {
  TempDir dir;
  TriMesh flipped = cornerTetrahedron();
  std::swap(flipped.F(3, 1), flipped.F(3, 2));
  const std::string path = dir.file("flipped.obj");
  writeMesh(path, flipped);
  RemeshReport report;
  const TriMesh input = readRemeshInput(path, {}, &report);
  EXPECT_EQ(report.reorientedFaces, 1);
  EXPECT_NO_THROW(validate(input, "repaired"));
  EXPECT_EQ(input.F.rows(), flipped.F.rows());
  EXPECT_EQ(readRemeshInput(path).F, input.F);  // the report is optional
  const std::string strip = dir.file("moebius.obj");
  writeMesh(strip, moebiusStrip(8));
  expectContains(errorOf([&] { readRemeshInput(strip); }),
                 {strip + ": ", "oriented inconsistently"});
}

TEST(LoadSurface, ErrorsNameTheFile) {
  TempDir dir;
  const std::string missing = dir.file("missing.obj");
  expectContains(errorOf([&] { loadSurface(missing); }), {missing, "cannot open"});
  InputOptions remeshing;
  remeshing.remesh = true;
  expectContains(errorOf([&] { loadSurface(missing, remeshing); }), {missing, "cannot open"});
  // An invalid mesh, named by the file: a flipped face (which the remesher's repairs
  // turn back), a Moebius strip (which nothing orients).
  TriMesh flipped = cornerTetrahedron();
  std::swap(flipped.F(3, 1), flipped.F(3, 2));
  const std::string path = dir.file("flipped.obj");
  writeMesh(path, flipped);
  expectContains(errorOf([&] { loadSurface(path); }), {path + ": ", "face 3"});
  const std::string strip = dir.file("moebius.obj");
  writeMesh(strip, moebiusStrip(8));
  expectContains(errorOf([&] { loadSurface(strip, remeshing); }),
                 {strip + ": ", "oriented inconsistently"});
  // Options the remesher refuses, named by the file and the option.
  writeMesh(path, subdivide(shapes::icosahedron(), 1, Scheme::Loop));
  remeshing.remeshing.baseFaces = 2;
  expectContains(errorOf([&] { loadSurface(path, remeshing); }),
                 {path + ": ", "RemeshOptions::baseFaces"});
}

TEST(AnalysedSurface, RecoversTheStructureOfAShuffledSurface) {
  const TriMesh input = shuffledSurface();
  const AnalysedSurface& a = analysed();
  EXPECT_EQ(a.levels(), kLevels);
  ASSERT_NE(a.recovery(), nullptr);
  EXPECT_EQ(a.recovery()->levels, kLevels);
  EXPECT_EQ(a.recovery()->numBaseVertices, 6);
  EXPECT_EQ(a.recovery()->baseFaces.rows(), 8);
  EXPECT_EQ(a.hierarchy().levels(), kLevels);
  EXPECT_EQ(a.hierarchy().numVertices(kLevels), input.V.rows());
  // The canonical positions are the input's, reordered.
  const Decomposition& d = a.decomposition();
  ASSERT_EQ(d.inputOrder.size(), static_cast<std::size_t>(input.V.rows()));
  const Points& canonical = a.canonicalPositions();
  ASSERT_EQ(canonical.rows(), input.V.rows());
  for (Eigen::Index i = 0; i < canonical.rows(); ++i)
    EXPECT_EQ(canonical.row(i), input.V.row(d.inputOrder[i])) << "canonical vertex " << i;
  EXPECT_EQ(d.inputFaces, input.F);
  EXPECT_EQ(d.scheme, Scheme::Loop);
  EXPECT_GE(a.times().total(), a.times().analysis);
}

TEST(AnalysedSurface, ReconstructsTheInputInItsOwnOrder) {
  const TriMesh input = shuffledSurface();
  const AnalysedSurface& a = analysed();
  const TriMesh back = a.reconstruct(a.decomposition(), kLevels);
  EXPECT_EQ(back.F, input.F);
  ASSERT_EQ(back.V.rows(), input.V.rows());
  EXPECT_LT(maxDifference(back.V, input.V), 1e-12 * boundingBoxDiagonal(input.V));
  // Below J: the canonical mesh of that level, the base mesh at level 0.
  const TriMesh base = a.reconstruct(a.decomposition(), 0);
  EXPECT_EQ(base.F, a.hierarchy().faces(0));
  EXPECT_EQ(base.V, a.decomposition().base);
  const TriMesh level2 = a.reconstruct(a.decomposition(), 2);
  EXPECT_EQ(level2.F, a.hierarchy().faces(2));
  EXPECT_EQ(level2.V.rows(), a.hierarchy().numVertices(2));
  EXPECT_THROW(a.reconstruct(a.decomposition(), kLevels + 1), Error);
}

TEST(AnalysedSurface, AStoredDecompositionGivesTheSameSurface) {
  const AnalysedSurface& a = analysed();
  const TriMesh expected = a.reconstruct(a.decomposition(), kLevels);
  // Directly, and through a .mra file as the command-line tool does.
  TempDir dir;
  const std::string path = dir.file("octahedron.mra");
  writeMra(path, a.decomposition());
  for (const bool fromFile : {false, true}) {
    SCOPED_TRACE(fromFile ? "from the file" : "from memory");
    const AnalysedSurface stored(fromFile ? readMra(path) : a.decomposition());
    EXPECT_EQ(stored.recovery(), nullptr);
    EXPECT_EQ(stored.canonicalPositions().rows(), 0);
    EXPECT_EQ(stored.levels(), kLevels);
    const TriMesh back = stored.reconstruct(stored.decomposition(), kLevels);
    EXPECT_EQ(back.F, expected.F);
    EXPECT_EQ(back.V, expected.V);  // the same filter bank, the same arithmetic
    // Made without the approximator (the default here): asking for it is an Error
    // that names the option; setApproximation builds it.
    AnalysedSurface withLod(fromFile ? readMra(path) : a.decomposition());
    expectContains(errorOf([&] { withLod.approximator(); }), {"AnalysisOptions::approximator"});
    withLod.setApproximation({});
    EXPECT_EQ(withLod.approximator().budget(100).triangles(),
              a.approximator().budget(100).triangles());
  }
}

TEST(AnalysedSurface, ApproximatorOnlyWhenAskedFor) {
  AnalysisOptions options;
  options.approximator = false;
  AnalysedSurface a(shuffledSurface(), options);
  expectContains(errorOf([&] { a.approximator(); }), {"AnalysisOptions::approximator"});
  EXPECT_EQ(a.times().approximator, 0.0);
  // Analysis and synthesis do not need it.
  EXPECT_EQ(a.reconstruct(a.decomposition(), kLevels).F, shuffledSurface().F);
  // setApproximation builds it, with its options: without saturation exactly the
  // selected coefficients are kept, with it more (and the same mesh).
  ApproximationOptions exact;
  exact.saturate = false;
  a.setApproximation(exact);
  const Approximation fewer = a.approximator().keepCount(50);
  EXPECT_EQ(fewer.selected, 50);
  EXPECT_EQ(fewer.kept, 50);
  a.setApproximation({});
  const Approximation more = a.approximator().keepCount(50);
  EXPECT_EQ(more.selected, 50);
  EXPECT_GT(more.kept, 50);
  EXPECT_EQ(more.mesh.F, fewer.mesh.F);
}

TEST(AnalysedSurface, ErrorsOfLevelsOfDetail) {
  const AnalysedSurface& a = analysed();
  const Approximator& x = a.approximator();
  DistanceOptions sampling;
  sampling.samples = 5000;
  // Everything kept: the full-resolution surface itself.
  const Approximation all = x.keepFraction(1.0);
  const LodErrors full = a.errors(all, sampling);
  EXPECT_LT(full.l2, 1e-12);
  EXPECT_LT(full.l2RmsRelative, 1e-12);
  EXPECT_LT(full.rmsRelative, 1e-12);
  EXPECT_LT(full.hausdorffRelative, 1e-12);
  // A small budget: every error is positive, the largest deviation at least the RMS.
  const Approximation small = x.budget(64);
  EXPECT_LE(small.triangles(), 64);
  const LodErrors e = a.errors(small, sampling);
  EXPECT_GT(e.l2, 0.0);
  EXPECT_GT(e.l2RmsRelative, 0.0);
  EXPECT_GT(e.rmsRelative, 0.0);
  EXPECT_GE(e.hausdorffRelative, e.rmsRelative);
  EXPECT_EQ(e.l2, x.l2Error(small));
  EXPECT_EQ(a.l2RmsRelative(small), e.l2RmsRelative);
  // The parametric RMS over the base domain (8 faces of area 1), relative to the
  // diagonal of the full-resolution surface.
  EXPECT_NEAR(e.l2RmsRelative, e.l2 / std::sqrt(8.0) / boundingBoxDiagonal(x.fullResolution().V),
              1e-15 * e.l2RmsRelative);
}

TEST(AnalysedSurface, KeepsWorkingWhenMoved) {
  AnalysedSurface a(shuffledSurface());
  const Approximation before = a.approximator().budget(200);
  const double errorBefore = a.l2RmsRelative(before);
  const TriMesh surface = a.reconstruct(a.decomposition(), kLevels);
  // The approximator refers to the filter bank and the decomposition inside the
  // object: a move must carry them along.
  AnalysedSurface moved(std::move(a));
  std::vector<AnalysedSurface> many;
  many.push_back(std::move(moved));
  many.emplace_back(shuffledSurface(), AnalysisOptions{}, "second");
  many.emplace_back(many.front().decomposition(), true);  // grows: moves the first two
  AnalysedSurface assigned = std::move(many.back());
  assigned = std::move(many.front());
  const Approximation after = assigned.approximator().budget(200);
  EXPECT_EQ(after.mesh.F, before.mesh.F);
  EXPECT_EQ(after.mesh.V, before.mesh.V);
  EXPECT_EQ(assigned.reconstruct(assigned.decomposition(), kLevels).V, surface.V);
  EXPECT_EQ(assigned.l2RmsRelative(after), errorBefore);
}

TEST(AnalysedSurface, ErrorsArePrefixedWithTheSource) {
  // The base mesh itself has no levels; more levels than there are is refused.
  expectContains(errorOf([] { AnalysedSurface(shapes::icosahedron(), {}, "ico.obj"); }),
                 {"ico.obj: ", "no subdivision connectivity"});
  AnalysisOptions tooDeep;
  tooDeep.levels = kLevels + 1;
  expectContains(errorOf([&] { AnalysedSurface(shuffledSurface(), tooDeep, "octahedron.ply"); }),
                 {"octahedron.ply: ", "3 levels over a base of 6 vertices and 8 faces",
                  "4 levels were asked for"});
  // Fewer levels than there are: a coarser base, the rest as before.
  AnalysisOptions two;
  two.levels = 2;
  const AnalysedSurface a(shuffledSurface(), two);
  EXPECT_EQ(a.levels(), 2);
  EXPECT_EQ(a.decomposition().baseFaces.rows(), 32);
  const TriMesh input = shuffledSurface();
  EXPECT_LT(maxDifference(a.reconstruct(a.decomposition(), 2).V, input.V),
            1e-12 * boundingBoxDiagonal(input.V));
}

TEST(LoadSurface, RemeshesAnyManifoldMesh) {
  // A torus of 27 x 13 vertices, every one moved at random: no subdivision
  // connectivity (an odd grid is no split of a coarser one), and one vertex that no
  // face uses, as scans have.
  TriMesh input = shapes::torus(27, 13);
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> jitter(-0.01, 0.01);
  for (Eigen::Index v = 0; v < input.V.rows(); ++v)
    input.V.row(v) += Eigen::RowVector3d(jitter(rng), jitter(rng), jitter(rng));
  const int n = static_cast<int>(input.V.rows()), faces = static_cast<int>(input.F.rows());
  ASSERT_EQ(recoverSubdivision(input.F, n).levels, 0);
  input.V.conservativeResize(n + 1, 3);
  input.V.row(n) << 9, 9, 9;
  TempDir dir;
  const std::string path = dir.file("torus.obj");
  writeMesh(path, input);
  InputOptions options;
  options.remesh = true;
  options.remeshing.baseFaces = 40;
  options.remeshing.levels = 3;
  options.distance.samples = 5000;
  const LoadedSurface s = loadSurface(path, options);
  ASSERT_TRUE(s.remeshing.has_value());
  const RemeshReport& r = *s.remeshing;
  EXPECT_EQ(r.droppedVertices, 1);
  EXPECT_EQ(r.inputVertices, n);
  EXPECT_EQ(r.inputFaces, faces);
  EXPECT_EQ(r.requestedBaseFaces, 40);
  EXPECT_LT(r.distance.hausdorffRelative, kFarRemeshing);
  // Warnings, if any, say what to change (in RemeshOptions terms) or why the base is
  // larger than asked; a far result always gets one.
  bool far = false;
  for (const std::string& w : r.warnings) {
    EXPECT_TRUE(w.find("RemeshOptions::") != std::string::npos || w.rfind("the base has", 0) == 0)
        << w;
    far = far || w.find("from the input at its farthest") != std::string::npos;
  }
  EXPECT_EQ(far, r.distance.hausdorffRelative > kFarRemeshing);
  EXPECT_GE(r.seconds, 0.0);
  // The loaded mesh is the remeshing: a valid mesh with subdivision connectivity of
  // RemeshOptions::levels levels over the base.
  EXPECT_EQ(s.mesh.V, r.result.mesh.V);
  EXPECT_EQ(s.mesh.F, r.result.mesh.F);
  EXPECT_NO_THROW(validate(s.mesh, "remeshed"));
  EXPECT_EQ(topology(s.mesh), topology(input.F, n));
  EXPECT_EQ(s.mesh.F.rows(), r.result.base.F.rows() << (2 * options.remeshing.levels));
  AnalysisOptions analysis;
  analysis.levels = options.remeshing.levels;
  const AnalysedSurface a(s.mesh, analysis, path);
  EXPECT_EQ(a.levels(), 3);
  EXPECT_EQ(a.decomposition().baseFaces.rows(), r.result.base.F.rows());
  EXPECT_LT(maxDifference(a.reconstruct(a.decomposition(), 3).V, s.mesh.V),
            1e-12 * boundingBoxDiagonal(s.mesh.V));
}

TEST(BaseFacesForBudget, AQuarterOfTheBudgetAndAtLeastATetrahedron) {
  EXPECT_EQ(baseFacesForBudget(100), 25);
  EXPECT_EQ(baseFacesForBudget(103), 25);
  EXPECT_EQ(baseFacesForBudget(8648), 2162);
  EXPECT_EQ(baseFacesForBudget(15), 4);
  EXPECT_EQ(baseFacesForBudget(1), 4);
  EXPECT_EQ(baseFacesForBudget(1LL << 40), 1 << 24);
  EXPECT_EQ(baseFacesForBudget(400, 16), 25);  // lodForBudget's second trial
  EXPECT_EQ(baseFacesForBudget(60, 16), 4);
}

// The input as repaired stays with the remeshing: what is made from the remeshing (a
// level of detail) can be measured against what the user gave, and is matched to it
// (analysisOptionsFor: lod --remesh --base-faces, sweep, the viewer); a surface read as
// it is, or a target already given, keeps its own.
TEST(LoadSurface, KeepsTheRemeshedInputAsTheReference) {
  const TriMesh input = shapes::torus(27, 13);
  TempDir dir;
  const std::string path = dir.file("torus.ply");
  writeMesh(path, input);
  InputOptions o;
  o.remesh = true;
  o.remeshing.baseFaces = 40;
  o.remeshing.levels = 2;
  o.distance.samples = 2000;
  const LoadedSurface s = loadSurface(path, o);
  ASSERT_TRUE(s.remeshing.has_value());
  EXPECT_EQ(s.remeshing->input.F, input.F);
  EXPECT_EQ(s.remeshing->input.V, input.V);  // binary PLY is exact
  EXPECT_NE(s.mesh.F.rows(), input.F.rows());
  const AnalysisOptions matched = analysisOptionsFor(s, {});
  ASSERT_TRUE(matched.approximation.closestTarget);
  EXPECT_EQ(matched.approximation.closestTarget->V, input.V);
  EXPECT_EQ(matched.approximation.closestTarget->F, input.F);
  EXPECT_FALSE(analysisOptionsFor(loadSurface(path), {}).approximation.closestTarget);
  AnalysisOptions given;
  given.approximation.closestTarget = std::make_shared<const TriMesh>(s.mesh);
  EXPECT_EQ(analysisOptionsFor(s, given).approximation.closestTarget,
            given.approximation.closestTarget);
}

// The set-up the LodForBudget tests share: a torus in a file, remeshed over `levels`
// levels (each trial the same, as with --levels), distances sampled sparsely.
struct BudgetCase {
  explicit BudgetCase(int levels, int samples) : path(dir.file("torus.ply")) {
    writeMesh(path, shapes::torus(27, 13));
    input.remeshing.levels = levels;
    input.distance.samples = 500;
    search.selection.samples = samples;
    search.levelsForEachBase = false;
  }
  TempDir dir;
  std::string path;
  InputOptions input;
  BudgetSearchOptions search;
};

// lod --remesh --budget: every base tried is remeshed, cut at the budget and measured
// against the input; the one kept is the closest of those within the budget, and what
// is returned is that trial's level of detail, its remeshing and the repaired input.
TEST(LodForBudget, KeepsTheClosestBaseAndItsRemeshing) {
  const TriMesh input = shapes::torus(27, 13);
  BudgetCase c3(3, 5000);  // --levels 3
  AnalysisOptions a;
  a.scheme = Scheme::Linear;
  const long long budget = 400;
  const BudgetLod b = lodForBudget(c3.path, budget, c3.input, a, c3.search);
  // The budget, again with skinny faces where flat, a third time with those and its
  // edges flipped towards the input, a fourth and a fifth as the first and the second
  // with their removals in order of error, a half, a quarter and a sixteenth.
  ASSERT_EQ(b.trials.size(), 8u);
  const std::vector<int> asked = {400, 400, 400, 400, 400, 200, 100, 25};
  for (std::size_t i = 0; i < asked.size(); ++i) {
    EXPECT_EQ(b.trials[i].baseFacesAsked, asked[i]);
    EXPECT_EQ(b.trials[i].skinnyWhereFlat,
              i == 1 || i == 2 || i == 4 ? c3.search.skinnyWhereFlat : 0.0);
    EXPECT_EQ(b.trials[i].orderByError, i == 3 || i == 4);
    if (i != 2) {
      EXPECT_EQ(b.trials[i].flipsTowardsInput, 0);
    }
  }
  EXPECT_GT(b.trials[2].flipsTowardsInput, 0);
  EXPECT_GT(c3.search.skinnyWhereFlat, 0.0);
  ASSERT_TRUE(b.chosen >= 0 && b.chosen < 8);
  const BaseTrial& kept = b.trials[b.chosen];
  for (const BaseTrial& t : b.trials) {
    EXPECT_LE(t.triangles, budget);
    EXPECT_EQ(t.levels, 3);
    EXPECT_LE(kept.rmsRelative, t.rmsRelative);
  }
  EXPECT_EQ(b.lod.triangles(), kept.triangles);
  EXPECT_EQ(b.surface.remeshing->result.base.F.rows(), kept.baseFaces);
  EXPECT_EQ(b.surface.remeshing->requestedBaseFaces, kept.baseFacesAsked);
  EXPECT_EQ(b.surface.mesh.F.rows(), kept.baseFaces * 64);
  EXPECT_EQ(b.analysed->hierarchy().numFaces(3), b.surface.mesh.F.rows());
  EXPECT_EQ(b.surface.remeshing->input.F, input.F);
  // The level of detail is the kept trial's: measured again with its samples, the same.
  EXPECT_DOUBLE_EQ(surfaceDistance(b.lod.mesh, input, c3.search.selection).rmsRelative,
                   kept.rmsRelative);
  // levelsForEachBase (no --levels): each base made gets the levels that keep it within
  // 2^19 faces, up to the maximum.
  c3.search.levelsForEachBase = true;
  c3.input.remeshing.levels = 4;
  const BudgetLod c = lodForBudget(c3.path, budget, c3.input, a, c3.search);
  for (const BaseTrial& t : c.trials)
    EXPECT_EQ(t.levels, levelsWithin(t.baseFaces, 4, kLodRemeshingFaces));
}

// Base sizes that coincide on a tiny budget (a half, a quarter and a sixteenth of 8 are
// all the 4 faces of the smallest base) are tried once (the whole budget's five times,
// the second with skinny faces where flat, the third with those and flips towards the
// input, the fourth and the fifth as the first and the second with their removals in
// order of error); a budget under 1 is refused.
TEST(LodForBudget, TriesCoincidingSizesOnce) {
  BudgetCase t(1, 500);
  const BudgetLod b = lodForBudget(t.path, 8, t.input, AnalysisOptions{}, t.search);
  ASSERT_EQ(b.trials.size(), 6u);
  EXPECT_EQ(b.trials[0].baseFacesAsked, 8);
  EXPECT_EQ(b.trials[1].baseFacesAsked, 8);
  EXPECT_GT(b.trials[1].skinnyWhereFlat, 0.0);
  EXPECT_EQ(b.trials[2].baseFacesAsked, 8);
  EXPECT_GT(b.trials[2].skinnyWhereFlat, 0.0);
  EXPECT_EQ(b.trials[3].baseFacesAsked, 8);
  EXPECT_TRUE(b.trials[3].orderByError);
  EXPECT_EQ(b.trials[3].skinnyWhereFlat, 0.0);
  EXPECT_EQ(b.trials[4].baseFacesAsked, 8);
  EXPECT_TRUE(b.trials[4].orderByError);
  EXPECT_GT(b.trials[4].skinnyWhereFlat, 0.0);
  EXPECT_EQ(b.trials[5].baseFacesAsked, 4);
  for (const BaseTrial& trial : b.trials)
    EXPECT_GT(trial.baseFaces, 8);  // a torus needs more: over the budget, said later
  EXPECT_EQ(b.lod.triangles(), b.trials[b.chosen].baseFaces);
  EXPECT_THROW(lodForBudget(t.path, 0, t.input, AnalysisOptions{}, t.search), Error);
  t.search.divisors.clear();
  EXPECT_THROW(lodForBudget(t.path, 8, t.input, AnalysisOptions{}, t.search), Error);
}

// The trials run at once or one after the other to the same result.
TEST(LodForBudget, ConcurrentTrialsGiveTheSequentialResult) {
  BudgetCase t(2, 2000);
  const BudgetLod at = lodForBudget(t.path, 300, t.input, AnalysisOptions{}, t.search);
  t.search.concurrently = false;
  const BudgetLod after = lodForBudget(t.path, 300, t.input, AnalysisOptions{}, t.search);
  ASSERT_EQ(at.trials.size(), 8u);  // more trials than cores
  ASSERT_EQ(after.trials.size(), 8u);
  EXPECT_EQ(at.chosen, after.chosen);
  for (std::size_t i = 0; i < 8; ++i) {
    EXPECT_EQ(at.trials[i].baseFaces, after.trials[i].baseFaces);
    EXPECT_EQ(at.trials[i].triangles, after.trials[i].triangles);
    EXPECT_EQ(at.trials[i].rmsRelative, after.trials[i].rmsRelative);
  }
  EXPECT_EQ(at.lod.mesh.V, after.lod.mesh.V);
  EXPECT_EQ(at.lod.mesh.F, after.lod.mesh.F);
}

// A semi-regular input's own hierarchy is one more trial: at a budget of the whole
// input it is the input itself (no error at all), which no remeshing matches, so it is
// kept without a remeshing; without inputHierarchy, or on an input without subdivision
// connectivity (the torus of the tests above), or whose base is over the budget, there
// is no such trial.
TEST(LodForBudget, TriesTheInputsOwnHierarchy) {
  const TriMesh input = subdivide(shapes::octahedron(), 3, Scheme::Loop);  // 512 faces
  TempDir dir;
  const std::string path = dir.file("loop.ply");
  writeMesh(path, input);
  InputOptions io;
  io.remeshing.levels = 2;
  io.distance.samples = 500;
  BudgetSearchOptions search;
  search.selection.samples = 2000;
  search.levelsForEachBase = false;
  AnalysisOptions a;
  a.scheme = Scheme::Linear;
  const BudgetLod whole = lodForBudget(path, 512, io, a, search);
  ASSERT_EQ(whole.trials.size(), 9u);  // eight remeshings, then the input's own
  const BaseTrial& own = whole.trials.back();
  EXPECT_TRUE(own.inputHierarchy);
  EXPECT_EQ(own.baseFacesAsked, 0);
  EXPECT_EQ(own.baseFaces, 8);
  EXPECT_EQ(own.levels, 3);
  EXPECT_EQ(own.triangles, 512);
  EXPECT_LT(own.rmsRelative, 1e-12);  // the input itself, up to rounding
  EXPECT_EQ(whole.chosen, 8);
  EXPECT_FALSE(whole.surface.remeshing.has_value());
  EXPECT_EQ(whole.surface.mesh.F.rows(), 512);
  EXPECT_EQ(whole.lod.triangles(), 512);
  for (std::size_t i = 0; i + 1 < whole.trials.size(); ++i) {
    EXPECT_FALSE(whole.trials[i].inputHierarchy);
    EXPECT_GT(whole.trials[i].rmsRelative, 0.0);
  }
  // At a smaller budget the closest within it is kept, whichever it is.
  const BudgetLod part = lodForBudget(path, 100, io, a, search);
  ASSERT_TRUE(part.trials.back().inputHierarchy);
  EXPECT_LE(part.trials.back().triangles, 100);
  for (const BaseTrial& t : part.trials) {
    if (t.triangles <= 100) {
      EXPECT_LE(part.trials[part.chosen].rmsRelative, t.rmsRelative);
    }
  }
  EXPECT_EQ(part.surface.remeshing.has_value(), !part.trials[part.chosen].inputHierarchy);
  EXPECT_FALSE(lodForBudget(path, 6, io, a, search).trials.back().inputHierarchy);  // 8 faces
  search.inputHierarchy = false;
  const BudgetLod without = lodForBudget(path, 512, io, a, search);
  ASSERT_EQ(without.trials.size(), 8u);
  for (const BaseTrial& t : without.trials) EXPECT_FALSE(t.inputHierarchy);
  EXPECT_TRUE(without.surface.remeshing.has_value());
}

TEST(LoadSurface, MendsZeroAreaFacesBeforeRemeshing) {
  // A cube as CAD exports write it, each side fanned from a point of its first edge:
  // 12 zero-area caps, and every vertex on a sharp edge. Mended (removeZeroAreaFaces),
  // every cube edge is a feature line (48 segments) and the remesh is the cube itself.
  // Before the caps were mended (2026-11-26) the cube had 27 feature edges, its base
  // stopped at 64 faces for the 30 asked, the clean-up moved 2,027 grid points and the
  // result was 0.52% of the diagonal from the cube; with the caps mended but corner
  // triangles' sides measured across the cube's edges (features.h), 36 and 42 faces.
  TempDir dir;
  const std::string path = dir.file("cube.off");
  writeMesh(path, fannedCube(4));
  InputOptions options;
  options.remesh = true;
  options.remeshing.baseFaces = 30;
  options.remeshing.levels = 3;
  options.distance.samples = 5000;
  const LoadedSurface s = loadSurface(path, options);
  const RemeshReport& r = *s.remeshing;
  EXPECT_EQ(r.zeroArea.flipped, 12);
  EXPECT_EQ(r.zeroArea.left, 0);
  EXPECT_EQ(r.result.featureEdges, 48);
  EXPECT_LE(r.result.base.F.rows(), 30);
  EXPECT_GT(r.result.base.F.rows(), 27);
  EXPECT_EQ(r.result.flippedTriangles + r.result.degenerateTriangles + r.result.selfIntersections,
            0);
  EXPECT_LT(r.distance.hausdorffRelative, 1e-12);
  EXPECT_TRUE(r.warnings.empty());
}

TEST(LoadSurface, CutsNonManifoldEdgesOpenBeforeRemeshing) {
  // A cube refined twice (linear) with a fin on one of its edges: the edge has three
  // faces, which validate() refuses. With the remesher the edge is cut open, the fin
  // is remeshed apart, and a warning says so.
  TriMesh m = subdivide(unitCube(), 2, Scheme::Linear);
  const int a = m.F(0, 0), b = m.F(0, 1), n = static_cast<int>(m.V.rows());
  m.V.conservativeResize(n + 1, 3);
  m.V.row(n) = 0.5 * (m.V.row(a) + m.V.row(b)) + Eigen::RowVector3d(0.3, -0.4, 0.5);
  m.F.conservativeResize(m.F.rows() + 1, 3);
  m.F.row(m.F.rows() - 1) << a, b, n;
  TempDir dir;
  const std::string path = dir.file("finned.obj");
  writeMesh(path, m);
  EXPECT_THROW(loadSurface(path), Error);
  InputOptions options;
  options.remesh = true;
  options.remeshing.baseFaces = 60;
  options.remeshing.levels = 2;
  options.distance.samples = 5000;
  const LoadedSurface s = loadSurface(path, options);
  const RemeshReport& r = *s.remeshing;
  EXPECT_EQ(r.cutEdges, 1);
  EXPECT_NO_THROW(validate(s.mesh, "remeshed"));
  EXPECT_EQ(topology(s.mesh).components, 2);
  EXPECT_LT(r.distance.hausdorffRelative, 1e-12);
  bool said = false;
  for (const std::string& w : r.warnings)
    said = said || w.find("were cut open") != std::string::npos;
  EXPECT_TRUE(said);
}

TEST(LoadSurface, SaysWhenDebrisTakesBaseFacesAndDropsItWhenAsked) {
  // A sphere and 20 loose triangles: each would be a base face of its own.
  TriMesh m = subdivide(shapes::icosahedron(), 3, Scheme::Loop);
  const int n = static_cast<int>(m.V.rows()), faces = static_cast<int>(m.F.rows());
  m.V.conservativeResize(n + 60, 3);
  m.F.conservativeResize(faces + 20, 3);
  for (int t = 0; t < 20; ++t) {
    for (int c = 0; c < 3; ++c)
      m.V.row(n + 3 * t + c) << 3 + 0.1 * t, 0.05 * (c == 1), 0.05 * (c == 2);
    m.F.row(faces + t) << n + 3 * t, n + 3 * t + 1, n + 3 * t + 2;
  }
  TempDir dir;
  const std::string path = dir.file("debris.obj");
  writeMesh(path, m);
  InputOptions options;
  options.remesh = true;
  options.remeshing.baseFaces = 80;
  options.remeshing.levels = 2;
  options.distance.samples = 2000;
  auto said = [](const RemeshReport& r) {
    for (const std::string& w : r.warnings)
      if (w.find("20 components of fewer than 16 faces") != std::string::npos &&
          w.find("InputOptions::minComponentFaces 16") != std::string::npos)
        return true;
    return false;
  };
  const LoadedSurface kept = loadSurface(path, options);
  EXPECT_TRUE(said(*kept.remeshing));
  EXPECT_EQ(topology(kept.mesh).components, 21);
  options.minComponentFaces = 16;
  const LoadedSurface dropped = loadSurface(path, options);
  EXPECT_FALSE(said(*dropped.remeshing));
  EXPECT_EQ(dropped.remeshing->smallComponentsDropped, 20);
  EXPECT_EQ(topology(dropped.mesh).components, 1);
}

// The codec's scheme by default: a surface refined by midpoints (flat inside every base
// face, as a remesh of a scan is inside every input triangle) codes shorter with the
// polyhedral scheme, whose details are all zero there; a Loop surface with Loop, whose
// are. Either way the choice is the shorter whole stream.
TEST(ChooseCodingScheme, TheSchemeThatRefinedTheSurfaceCodesItShorter) {
  AnalysisOptions options;
  options.approximator = false;
  options.norms = false;
  options.wavelets = {WaveletKind::Fixed, 0};
  const CodecOptions codec;
  for (const Scheme scheme : {Scheme::Loop, Scheme::Linear}) {
    SCOPED_TRACE(schemeName(scheme));
    // Offsets well below the other scheme's prediction error: at 0.02 both streams are
    // mostly noise and the coder's context modelling decides (since the signs have
    // contexts, the polyhedral scheme coded the Loop surface 0.8% shorter, its details
    // there having one sign over the convex shape); at 0.005 each scheme's own wins by
    // 2% (Loop) and 13% (polyhedral).
    const TriMesh mesh = subdivide(shapes::icosahedron(), 4, scheme, 0.005, 3);
    const CodingSchemeChoice c = chooseCodingScheme(mesh, options, codec);
    EXPECT_EQ(c.scheme, scheme);
    EXPECT_EQ(c.scheme == Scheme::Linear, c.linearBytes < c.loopBytes);
    EXPECT_GT(c.loopBytes, 0u);
    EXPECT_GT(c.linearBytes, 0u);
    ASSERT_TRUE(c.compressed.has_value());
    EXPECT_EQ(c.compressed->wholeBytes, std::min(c.loopBytes, c.linearBytes));
  }
}

// At a rate asked, the choice compares the two streams there: at a size the closer to
// the surface (both measured), at a PSNR the shorter that reaches it; and the stream it
// returns is the winner's, cut at that rate.
TEST(ChooseCodingScheme, ComparesTheStreamsAtTheRateAsked) {
  AnalysisOptions options;
  options.approximator = false;
  options.norms = false;
  options.wavelets = {WaveletKind::Fixed, 0};
  CodecOptions codec;
  codec.distance.samples = 5000;
  // Each surface is coded better by the scheme that refined it (the test above); on
  // the polyhedral one Loop's stream falls short at the winner's length, so Loop is
  // not searched.
  bool searchedLoop = false, skippedLoop = false;
  for (const Scheme refined : {Scheme::Loop, Scheme::Linear}) {
    SCOPED_TRACE(schemeName(refined));
    const TriMesh mesh = subdivide(shapes::icosahedron(), 4, refined, 0.005, 3);
    const std::size_t size = 600;
    const CodingSchemeChoice bySize =
        chooseCodingScheme(mesh, options, codec, "", RateTarget::bytes(size));
    ASSERT_TRUE(std::isfinite(bySize.loopPsnr) && std::isfinite(bySize.linearPsnr));
    EXPECT_EQ(bySize.scheme == Scheme::Linear, bySize.linearPsnr > bySize.loopPsnr);
    ASSERT_TRUE(bySize.compressed.has_value());
    EXPECT_LE(bySize.compressed->bytes.size(), size);
    EXPECT_EQ(bySize.compressed->psnrSurface, std::max(bySize.loopPsnr, bySize.linearPsnr));
    EXPECT_EQ(bySize.surface->bank().scheme, bySize.scheme);

    const double dB = bySize.compressed->psnrSurface;
    const CodingSchemeChoice byPsnr =
        chooseCodingScheme(mesh, options, codec, "", RateTarget::psnr(dB));
    ASSERT_TRUE(byPsnr.compressed.has_value());
    const std::size_t won = byPsnr.compressed->bytes.size();
    if (byPsnr.loopBytes == 0) {  // Loop not searched: short of the PSNR at that length
      skippedLoop = true;
      EXPECT_EQ(byPsnr.scheme, Scheme::Linear);
      AnalysisOptions loopOptions = options;
      loopOptions.scheme = Scheme::Loop;
      const AnalysedSurface loop(mesh, loopOptions);
      const Compressed z = compress(loop, RateTarget::bytes(static_cast<double>(won)), codec);
      EXPECT_LT(z.psnrSurface, dB);
    } else {
      searchedLoop = true;
      EXPECT_EQ(byPsnr.scheme == Scheme::Linear, byPsnr.linearBytes < byPsnr.loopBytes);
      EXPECT_EQ(won, std::min(byPsnr.loopBytes, byPsnr.linearBytes));
    }
    EXPECT_GE(byPsnr.compressed->psnrSurface, dB);
    // The winner at a size reaches its own PSNR within that size.
    EXPECT_LE(won, size);

    test::expectContains(
        test::errorOf([&] { chooseCodingScheme(mesh, options, codec, "", RateTarget::psnr(300)); }),
        {"below the target"});
  }
  EXPECT_TRUE(searchedLoop);
  EXPECT_TRUE(skippedLoop);
}

// On a mesh read once (the bench's scans), lodForBudget gives what it gives on the file.
TEST(LodForBudget, AMeshReadOnceGivesTheFilesResult) {
  BudgetCase t(2, 2000);
  RemeshReport repairs;
  const TriMesh mesh = readRemeshInput(t.path, t.input, &repairs);
  const BudgetLod fromFile = lodForBudget(t.path, 300, t.input, AnalysisOptions{}, t.search);
  const BudgetLod fromMesh =
      lodForBudget(mesh, repairs, t.path, 300, t.input, AnalysisOptions{}, t.search);
  EXPECT_EQ(fromFile.chosen, fromMesh.chosen);
  EXPECT_EQ(fromFile.lod.mesh.V, fromMesh.lod.mesh.V);
  EXPECT_EQ(fromFile.lod.mesh.F, fromMesh.lod.mesh.F);
  EXPECT_EQ(fromMesh.surface.remeshing->input.F, mesh.F);
}
