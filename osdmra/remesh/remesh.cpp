#include "osdmra/remesh/remesh.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <functional>
#include <future>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "osdmra/base/error.h"
#include "osdmra/geometry/normals.h"
#include "osdmra/geometry/self_intersection.h"
#include "osdmra/geometry/surface_walk.h"
#include "osdmra/mesh/spatial_order.h"
#include "osdmra/remesh/base_flips.h"
#include "osdmra/remesh/charts.h"
#include "osdmra/remesh/cleanup.h"
#include "osdmra/remesh/features.h"
#include "osdmra/remesh/resample.h"
#include "osdmra/remesh/simplify.h"
#include "osdmra/remesh/smoothing.h"
#include "osdmra/remesh/unfold.h"

namespace osdmra {

namespace {

// The simplification indexes by vertex and walks one-rings: an invalid mesh would make
// it read out of bounds, so the precondition is checked, not assumed.
void checkInput(const TriMesh& input, const RemeshOptions& options) {
  validate(input, "remesh input");
  if (options.baseFaces < 4)
    throw Error("remesh: RemeshOptions::baseFaces must be at least 4, got " +
                std::to_string(options.baseFaces));
  if (options.levels < 0 || options.levels > 8)
    throw Error("remesh: RemeshOptions::levels must be in 0..8, got " +
                std::to_string(options.levels));
  if (options.maxFaces < 0)
    throw Error("remesh: RemeshOptions::maxFaces must be 0 (no limit) or more, got " +
                std::to_string(options.maxFaces));
  if (input.F.rows() < 4) throw Error("remesh: the input has fewer than 4 faces");
  // Areas and normals square the coordinates' differences: beyond 1e150 they overflow.
  const double diagonal = boundingBoxDiagonal(input.V);
  if (!(diagonal < 1e150))
    throw Error("remesh: the input's bounding box spans " + std::to_string(diagonal) +
                ", too large for its areas to be computed (at most 1e150)");
}

// The edge of an equilateral base face when `baseFaces` of them cover the input.
double baseEdgeLength(const TriMesh& input, int baseFaces) {
  double area = 0;
  for (Eigen::Index f = 0; f < input.F.rows(); ++f) area += 0.5 * faceNormal(input, f).norm();
  return std::sqrt(4 * area / (std::sqrt(3.0) * baseFaces));
}

// Step 2 through one map (resample.h's GridMap), which grid triangles it folds (flipped
// or of no area, as the clean-up counts them) and how many.
struct Sampling {
  remeshing::GridMap map = remeshing::GridMap::straightened;
  remeshing::Resampled grid;
  std::vector<char> folded;
  long long folds = 0;
};

const char* nameOf(remeshing::GridMap map) {
  return map == remeshing::GridMap::exact ? "exact" : "straightened";
}

// Step 3 on one map's grid (`lastResort` as in cleanUp()).
Remeshing cleaned(const Remeshing& common, Sampling sampling, const TriMesh& input,
                  const CrossingPairs* inputCrossings, const SurfaceWalker& walker,
                  const Progress& progress, const std::function<void()>& lastResort = {}) {
  Remeshing out = common;
  out.gridMap = nameOf(sampling.map);
  out.gridRefinementMoves = sampling.grid.refinementMoves;
  (sampling.map == remeshing::GridMap::exact ? out.exactFolds : out.straightenedFolds) =
      sampling.folds;
  remeshing::Resampled& grid = sampling.grid;
  out.mesh = std::move(grid.mesh);
  remeshing::cleanUp(out, input, grid.free, grid.line, grid.where, walker, progress, lastResort,
                     inputCrossings);
  return out;
}

// The other map's remeshing, started on a second core when the first map's repairs
// leave defects (and only then: most inputs need one map, and most repairs succeed;
// started as soon as there was anything to repair, it slowed the corpus's runs whose
// repairs then came out clean), and abandoned through its progress callback if the last
// resort leaves the first one clean after all. Its result is the one a sequential run
// would get: the maps share nothing that changes.
class OtherMapBeside {
 public:
  template <class Run>
  void start(Run run) {
    if (result_.valid() || std::thread::hardware_concurrency() < 2) return;
    result_ = std::async(std::launch::async, [this, run] {
      return run([this](const char*, double) {
        if (abandon_) throw Abandoned{};
      });
    });
  }
  bool started() const { return result_.valid(); }
  Remeshing get() { return result_.get(); }
  ~OtherMapBeside() {
    abandon_ = true;
    if (!result_.valid()) return;
    try {
      result_.get();
    } catch (...) {  // abandoned, or failed where nothing needs it any more
    }
  }

 private:
  struct Abandoned {};
  std::atomic<bool> abandon_{false};
  std::future<Remeshing> result_;
};

// What another grid map could mend: the input's own crossings stay under any.
long long defectsLeft(const Remeshing& r) {
  return r.flippedTriangles + r.degenerateTriangles + r.selfIntersections -
         r.selfIntersectionsWhereSheetsCross;
}

// What the other stage relaxation could mend: the crossings away from the input's own
// (near them, a fold of the input leaves knots that neither undoes).
long long defectsBeyondInput(const Remeshing& r) {
  return r.flippedTriangles + r.degenerateTriangles + r.selfIntersections -
         r.selfIntersectionsAtInputCrossings;
}

// The input's features (features.h), and on first need the same without the feature
// lines on their own shorter than a base edge of the size asked. Such a line pins two base
// vertices (three around a loop) closer together than the base's edges: scans with short
// creases came out with bases far over the size asked (the boot of odedstein/meshes, genus
// 12 and 86 such lines: 858 faces for 150). Dropping them everywhere made the corpus's
// remeshes no better and moved which of them fold (the bunny's two creases under its
// base), so they are dropped only where the base would otherwise be over size.
class FeatureChoice {
 public:
  FeatureChoice(const TriMesh& input, const RemeshOptions& options)
      : input_(input),
        angle_(options.featureAngle),
        span_(0.5 * baseEdgeLength(input, options.baseFaces)),
        all_(remeshing::detectFeatures(input, angle_, span_)) {}
  const remeshing::Features& all() const { return all_; }
  const remeshing::Features& withoutShortLines() const {
    std::call_once(
        made_, [this] { shorter_ = remeshing::detectFeatures(input_, angle_, span_, 2 * span_); });
    return shorter_;
  }

 private:
  const TriMesh& input_;
  double angle_, span_;
  remeshing::Features all_;
  mutable std::once_flag made_;
  mutable remeshing::Features shorter_;
};

// Whether a base is over the size asked by more than 10% (what docs/REMESH.md counts).
bool overSize(const remeshing::Simplification& s, const RemeshOptions& options) {
  return s.base.F.rows() > 1.1 * options.baseFaces;
}

// Step 1: the simplification with every feature line, and where its base is over size,
// without the short lines on their own as well, the smaller base kept (`chosen`: the
// features it was made with).
remeshing::Simplification simplifiedWithin(const TriMesh& input, const FeatureChoice& choice,
                                           const RemeshOptions& options,
                                           const remeshing::SimplifyOptions& how,
                                           const Progress& progress,
                                           const remeshing::Features*& chosen) {
  using namespace remeshing;
  chosen = &choice.all();
  Simplification s = simplify(input, *chosen, options.baseFaces, progress, kStages, how);
  if (!overSize(s, options) || choice.withoutShortLines().list.size() == chosen->list.size())
    return s;
  Simplification t =
      simplify(input, choice.withoutShortLines(), options.baseFaces, progress, kStages, how);
  if (t.base.F.rows() >= s.base.F.rows()) return s;
  chosen = &choice.withoutShortLines();
  return t;
}

// Per base face, the triangles of its grid that fold (the grid's triangles come base
// face by base face, 4^levels each).
std::vector<int> foldsPerBaseFace(const Sampling& sampling, int levels) {
  const long long per = 1LL << (2 * levels);
  std::vector<int> folds(sampling.folded.size() / per, 0);
  for (std::size_t t = 0; t < sampling.folded.size(); ++t) folds[t / per] += sampling.folded[t];
  return folds;
}

// How the base faces whose grid folds are split (base_flips.h): checked on grids of the
// same levels, at most `room` splits.
remeshing::BaseFlipOptions splitOptions(const TriMesh& input, int levels, int room) {
  remeshing::BaseFlipOptions options;
  options.levels = levels;
  options.input = &input;
  options.maxSplits = room;
  return options;
}

// Step 2 over a base: the grid sampled through one map, and its folds.
struct GridSampler {
  const TriMesh& input;
  const SurfaceWalker& walker;
  const remeshing::Features& features;
  int levels = 0;
  bool refine = true;  // RemeshOptions::refineGrid

  Sampling operator()(const remeshing::Simplification& s, const remeshing::BaseCharts& charts,
                      remeshing::GridMap map, const Progress& progress) const {
    Sampling sampling;
    sampling.map = map;
    sampling.grid = remeshing::resample(input, walker.connectivity(), features.list, s, charts,
                                        levels, map, progress, refine);
    sampling.folded = remeshing::foldedTriangleFlags(sampling.grid.mesh, sampling.grid.where, input,
                                                     walker.connectivity());
    sampling.folds = std::count(sampling.folded.begin(), sampling.folded.end(), 1);
    return sampling;
  }
};

// A base with faces split (base_flips.h), its charts, its straightened grid and, where
// it was sampled to be checked, its exact one.
struct SplitBase {
  std::unique_ptr<remeshing::Simplification> s;
  std::unique_ptr<remeshing::BaseCharts> charts;
  Sampling straightened;
  std::optional<Sampling> exact;
};

// A copy of `from` whose base faces with `folds` are split as `how` says
// (splitFoldingFaces, its report in `report`), with its charts and straightened grid;
// none where no split was made.
std::optional<SplitBase> splitCopy(const GridSampler& sample, const remeshing::Simplification& from,
                                   const std::vector<int>& folds,
                                   const remeshing::BaseFlipOptions& how,
                                   remeshing::BaseFlipReport& report, const Progress& progress) {
  using namespace remeshing;
  SplitBase next{std::make_unique<Simplification>(from), nullptr, {}, std::nullopt};
  report = splitFoldingFaces(*next.s, folds, how);
  if (report.splits == 0) return std::nullopt;
  next.charts = std::make_unique<BaseCharts>(next.s->base);
  next.straightened = sample(*next.s, *next.charts, GridMap::straightened, progress);
  return next;
}

// One more round of splits over `from` (the base as split by splitWhereBothFold, or
// as simplified where it kept none), of the base faces holding the folds of its
// straightened grid `grid`: at an input vertex or, where the pair holds none that fits,
// at a point of the input (BaseFlipOptions::splitAtPoints), each checked not to fold the
// exact grid over its new faces more; kept where its straightened grid folds less. After
// the splits at input vertices, not with them: in the same trials the splits at points
// made the cow's trial over 300 at J = 5 fold more, and its splits were lost (over the
// 96 corpus runs of docs/REMESH.md 32 runs cleaned up and 12,321 points moved, against
// 32 and 11,213 before; this way 31 and 11,085, the arm over 150 at J = 5 spared).
std::optional<SplitBase> splitAtPoints(const GridSampler& sample,
                                       const remeshing::Simplification& from, const Sampling& grid,
                                       int room, const Progress& progress) {
  remeshing::BaseFlipOptions how = splitOptions(sample.input, sample.levels, room);
  how.splitAtPoints = true;
  remeshing::BaseFlipReport report;
  std::optional<SplitBase> next =
      splitCopy(sample, from, foldsPerBaseFace(grid, sample.levels), how, report, progress);
  if (next && next->straightened.folds >= grid.folds) return std::nullopt;
  return next;
}

// Where both grids fold (`straightened`, `exact`), the base faces holding the straightened
// grid's folds split, twice: each split checked not to fold the exact grid over its new
// faces more, and without that check. Each split base is sampled again and kept where
// its straightened grid folds less; the unchecked one only where that grid folds nothing
// or the exact one, the clean-up's other grid, folds no more than before. Over the 96
// corpus runs of docs/REMESH.md the unchecked splits spared the clean-up two runs more
// (fertility over 150), and, without the exact grid's bound, left decimated-max over
// 600 at J = 5 to the exact grid's clean-up (951 -> 4,807 points moved). Then, where
// the grid kept still folds, one more round (splitAtPoints). Records the splits made,
// those at points and those refused in `out`.
std::optional<SplitBase> splitWhereBothFold(const GridSampler& sample,
                                            const remeshing::Simplification& simplified,
                                            const Sampling& straightened, const Sampling& exact,
                                            int room, Remeshing& out, const Progress& progress) {
  using namespace remeshing;
  const std::vector<int> folds = foldsPerBaseFace(straightened, sample.levels);
  std::optional<SplitBase> kept;
  int refusedForFolds = 0;  // where the check refused none, the unchecked splits are the same
  for (const bool foldCheck : {true, false}) {
    if (!foldCheck && refusedForFolds == 0) break;
    BaseFlipOptions how = splitOptions(sample.input, sample.levels, room);
    how.splitFoldCheck = foldCheck;
    BaseFlipReport report;
    std::optional<SplitBase> next = splitCopy(sample, simplified, folds, how, report, progress);
    if (foldCheck) {
      out.baseSplitsRefused = report.splitsRefused;
      refusedForFolds = report.splitsFoldingMore;
    }
    if (!next) continue;
    const long long toBeat = kept ? kept->straightened.folds : straightened.folds;
    if (next->straightened.folds >= toBeat) {
      if (foldCheck) out.baseSplitsRefused += report.splits;
      continue;
    }
    if (!foldCheck && next->straightened.folds > 0) {
      next->exact = sample(*next->s, *next->charts, GridMap::exact, progress);
      if (next->exact->folds > exact.folds) continue;
    }
    out.baseSplits = report.splits;
    kept = std::move(next);
  }
  // Then where the grid still folds, splits at points of the input too.
  const Simplification& from = kept ? *kept->s : simplified;
  const Sampling& last = kept ? kept->straightened : straightened;
  const int made = kept ? out.baseSplits : 0;
  if (last.folds > 0 && room > made) {
    std::optional<SplitBase> more = splitAtPoints(sample, from, last, room - made, progress);
    if (more) {
      out.baseSplits = made + static_cast<int>(more->s->base.V.rows() - from.base.V.rows());
      out.baseSplitsAtPoints = static_cast<int>(more->s->added.size());
      kept = std::move(more);
    }
  }
  return kept;
}

// Steps 2 and 3 (remesh()): the grid sampled through the straightened map, or through
// the exact one where only that one folds nothing, then cleaned up; and through the other
// map too where the clean-up leaves defects.
Remeshing sampledAndCleaned(const Remeshing& common, const TriMesh& input,
                            const CrossingPairs* inputCrossings, const SurfaceWalker& walker,
                            const remeshing::Features& features,
                            const remeshing::Simplification& simplified,
                            const remeshing::BaseCharts& simplifiedCharts, int splitRoom,
                            bool refineGrid, const Progress& progress) {
  using namespace remeshing;
  const Simplification* s = &simplified;
  const BaseCharts* charts = &simplifiedCharts;
  // Step 2 through the straightened map, and where its grid folds, through the exact
  // inverse of the removals too; step 3 on the exact map's grid where that folds none,
  // so that the clean-up has nothing to unfold, and on the straightened one otherwise.
  // Each map is a bijection, and neither folds less everywhere: the straightened map on
  // dense scans (the bunny over 600 base faces at J = 5: 51 grid triangles folded
  // against 102), the exact one on scans whose triangles are large against the grid's
  // (spot over 150 at J = 4: 4 against 0; the lion over 300 at J = 5: 12 against 0) and on
  // decimated inputs (the camel head decimated to 3,000 faces: 162 flipped triangles
  // and 265 crossing pairs left through the straightened map after the clean-up, none
  // through the exact one). The exact map samples less evenly (its pieces are the
  // removals' retriangulations, not the input's triangles): cleaning up whichever grid
  // folds less made the shared corpus's remeshes farther from their scans (RMS 1.021x,
  // Hausdorff 1.041x) than cleaning up the exact one only where it folds none (1.012x,
  // 1.008x), for the same 15 runs of 96 spared the clean-up (docs/REMESH.md).
  const GridSampler sampleOver{input, walker, features, common.levels, refineGrid};
  auto sample = [&](GridMap map, const Progress& p) { return sampleOver(*s, *charts, map, p); };
  Remeshing out = common;
  Sampling first = sample(GridMap::straightened, progress);
  std::optional<Sampling> second;
  if (first.folds > 0) second = sample(GridMap::exact, progress);
  std::optional<SplitBase> split;
  if (first.folds > 0 && second->folds > 0 && splitRoom > 0)
    split = splitWhereBothFold(sampleOver, simplified, first, *second, splitRoom, out, progress);
  if (split) {
    s = split->s.get();
    charts = split->charts.get();
    first = std::move(split->straightened);
    second.reset();
    if (first.folds > 0)
      second = split->exact ? std::move(split->exact) : sample(GridMap::exact, progress);
    out.base = s->base;
  }
  out.straightenedFolds = first.folds;
  if (second) {
    out.exactFolds = second->folds;
    if (second->folds == 0) std::swap(first, *second);
  }
  // Where the clean-up leaves defects, the other map's grid is cleaned up too, and the
  // one with fewer defects left kept.
  const GridMap otherMap = first.map == GridMap::exact ? GridMap::straightened : GridMap::exact;
  auto cleanedOther = [&](const Progress& p) {
    return cleaned(out, second ? std::move(*second) : sample(otherMap, p), input, inputCrossings,
                   walker, p);
  };
  const GridMap firstMap = first.map;
  OtherMapBeside beside;
  Remeshing best = cleaned(out, std::move(first), input, inputCrossings, walker, progress,
                           [&] { beside.start(cleanedOther); });
  const long long firstLeft = defectsLeft(best);
  long long otherLeft = -1;
  if (firstLeft > 0) {
    Remeshing other = beside.started() ? beside.get() : cleanedOther(progress);
    otherLeft = defectsLeft(other);
    best.straightenedFolds = other.straightenedFolds;  // the other knows both
    best.exactFolds = other.exactFolds;
    if (otherLeft < firstLeft) best = std::move(other);
  }
  const bool straightenedFirst = firstMap == GridMap::straightened;
  best.straightenedDefects = straightenedFirst ? firstLeft : otherLeft;
  best.exactDefects = straightenedFirst ? otherLeft : firstLeft;
  return best;
}

// Steps 1 to 3 (remesh()) with the simplification's stages relaxed vertex by vertex or
// mesh-wide.
Remeshing remeshedOver(const TriMesh& input, const CrossingPairs* inputCrossings,
                       const FeatureChoice& choice, const RemeshOptions& options,
                       bool stagesPerVertex, const Progress& progress) {
  using namespace remeshing;
  Remeshing out;
  out.stages = stagesPerVertex ? "vertex" : "mesh";

  SimplifyOptions how;
  how.noNewCrossings = options.baseWithoutNewCrossings;
  how.inputCrossings = inputCrossings;
  how.stagesPerVertex = stagesPerVertex;
  how.retriangulateByError = options.retriangulateByError;
  how.skinnyWhereFlat = options.skinnyWhereFlat;
  how.orderByError = options.orderByError;
  const Features* chosen = nullptr;
  Simplification s = simplifiedWithin(input, choice, options, how, progress, chosen);
  const Features& features = *chosen;
  out.featureEdges = static_cast<int>(features.list.size());
  out.featureEdgesDropped = static_cast<int>(choice.all().list.size() - features.list.size());
  out.tips = static_cast<int>(std::count(features.tip.begin(), features.tip.end(), 1));
  out.simplificationRounds = s.rounds;
  out.simplificationStage = s.stage;
  out.baseSizeReason = s.stopReason;
  out.levels = levelsWithin(s.base.F.rows(), options.levels, options.maxFaces);
  // Base edges flipped where the grid over a pair folds less so (base_flips.h).
  if (options.capAngle > 0) {
    BaseFlipOptions flips;
    flips.capAngle = options.capAngle;
    flips.levels = out.levels;
    flips.input = &input;
    const BaseFlipReport report = flipCaps(s, flips);
    out.baseFlips = report.flips;
    out.baseFlipsRefused = report.refused;
  }
  // And, for a level of detail whose coarse levels are the base, where the flipped faces
  // fit the input better (each flip lowers a sum, so the sweeps end; 16 bound the time).
  if (options.flipTowardsInput > 0) {
    BaseFlipOptions flips;
    flips.stretch = options.flipTowardsInput;
    flips.input = &input;
    flips.maxSweeps = 16;
    out.baseFlipsTowardsInput = flipTowardsInput(s, flips).flips;
  }
  out.base = s.base;

  // Walks on the input (the clean-up's last stage) do not cross its feature lines.
  const SurfaceWalker walker(input, features.list);
  const BaseCharts charts(s.base);
  if (options.smoothingSweeps > 0) {
    std::vector<char> pinned(input.V.rows(), 0);
    for (const auto& [a, b] : features.list) pinned[a] = pinned[b] = 1;
    SmoothingOptions smoothing;
    smoothing.sweeps = options.smoothingSweeps;
    smoothing.anisotropy = kStages[s.stage].anisotropy;
    const SmoothingReport report =
        smoothParameters(input, walker.connectivity(), charts, pinned, s, smoothing);
    out.smoothingMoves = report.moves;
    out.smoothingRefused = report.refused;
  }
  // Splits of base faces whose grid folds while the base stays within 10% of `size`
  // (each adds two faces), and the output within maxFaces.
  auto splitRoom = [&](long long size) {
    long long room = static_cast<long long>(1.1 * size) - s.base.F.rows();
    if (options.maxFaces > 0)
      room = std::min(room, (options.maxFaces >> (2 * out.levels)) - s.base.F.rows());
    return options.splitFoldingFaces ? static_cast<int>(std::max(0LL, room / 2)) : 0;
  };
  const int room = splitRoom(options.baseFaces);
  Remeshing best = sampledAndCleaned(out, input, inputCrossings, walker, features, s, charts, room,
                                     options.refineGrid, progress);
  // Where no vertex could go under the last stage, the base is over size whatever the
  // splits. If defects are left, splits up to 10% over the size it stopped at are tried
  // too, and kept where they leave fewer: chosen by the grid's folds alone, as above, they
  // took the scorpion of odedstein/meshes over 150 faces at J = 5 from 25 defects to none
  // and the boot over 300 from 22 to 10, but where the input crosses itself the folds do
  // not see the crossings the clean-up then leaves (the beast of alecjacobson's set over
  // 150 at J = 5: 167 -> 432), hence the choice by what is left (docs/REMESH.md).
  const int overSizeRoom = splitRoom(s.base.F.rows());
  if (overSizeRoom > room && defectsBeyondInput(best) > 0) {
    Remeshing more = sampledAndCleaned(out, input, inputCrossings, walker, features, s, charts,
                                       overSizeRoom, options.refineGrid, progress);
    if (defectsBeyondInput(more) < defectsBeyondInput(best)) best = std::move(more);
  }
  return best;
}

}  // namespace

int levelsWithin(long long baseFaces, int maxLevels, long long maxFaces) {
  int levels = std::min(maxLevels, 2);
  while (levels < maxLevels && (maxFaces == 0 || (baseFaces << (2 * (levels + 1))) <= maxFaces))
    ++levels;
  return levels;
}

Remeshing remesh(const TriMesh& given, const RemeshOptions& options, const Progress& progress) {
  checkInput(given, options);
  // Renumbered along space: the simplification's per-vertex and per-face tables are
  // then read near where they were last read (remesh() on one core 11-15% faster on the
  // bunny and armadillo than in their files' order), and the result depends on the
  // surface alone, not on the file's numbering (which decided ties and the order of
  // the work, and moved single rows of docs/REMESH.md's table either way).
  TriMesh input = inSpatialOrder(given);
  // The input's folds taken out (unfold.h): no grid follows a pleat's layers. Over the
  // 280 runs of docs/REMESH.md's four tables (2026-11-30), runs with defects 34 -> 30,
  // and the camel head's J = 5 remeshes over 300 and 600 faces spared the clean-up.
  remeshing::UnfoldReport unfolded;
  if (options.unfoldInput) unfolded = remeshing::unfoldInput(input);
  const FeatureChoice features(input, options);
  // The input's crossing pairs where the simplification needs them
  // (RemeshOptions::baseWithoutNewCrossings, the default), found once for every
  // simplification and clean-up (three on the bunny: 3% of its remesh); otherwise none,
  // and the clean-up finds them if it needs them.
  CrossingPairs found;
  if (options.baseWithoutNewCrossings) found = crossingPairs(input);
  const CrossingPairs* crossings = options.baseWithoutNewCrossings ? &found : nullptr;
  const bool perVertexFirst = options.stages != StageRelaxation::meshWide;
  Remeshing best = remeshedOver(input, crossings, features, options, perVertexFirst, progress);
  best.unfold = unfolded;
  if (options.stages != StageRelaxation::perVertexElseMeshWide) return best;
  // The fallback (StageRelaxation::perVertexElseMeshWide): on the corpus of
  // docs/REMESH.md the per-vertex remesh had defects on 8 of 96 runs, the mesh-wide one
  // on none of those but the cow's.
  best.perVertexDefects = defectsBeyondInput(best);
  if (best.perVertexDefects == 0) return best;
  Remeshing meshWide = remeshedOver(input, crossings, features, options, false, progress);
  if (defectsBeyondInput(meshWide) >= best.perVertexDefects) return best;
  meshWide.perVertexDefects = best.perVertexDefects;
  meshWide.unfold = unfolded;
  return meshWide;
}

}  // namespace osdmra
