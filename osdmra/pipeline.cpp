#include "osdmra/pipeline.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <future>

#include "osdmra/base/error.h"
#include "osdmra/geometry/self_intersection.h"
#include "osdmra/mesh/io.h"
#include "osdmra/mesh/t_junctions.h"

namespace osdmra {
namespace {

using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

void report(const Progress& progress, const char* stage, double fraction) {
  if (progress) progress(stage, fraction);
}

// Runs `f`, prefixing the message of any Error with `source` (when there is one).
template <class F>
auto naming(const std::string& source, F&& f) -> decltype(f()) {
  if (source.empty()) return f();
  try {
    return f();
  } catch (const Error& e) {
    throw Error(source + ": " + e.what());
  }
}

std::vector<std::string> remeshWarnings(const RemeshReport& r) {
  std::vector<std::string> out;
  const Remeshing& x = r.result;
  if (x.flippedTriangles + x.degenerateTriangles > 0 || x.selfIntersections > 0)
    out.push_back(std::to_string(x.flippedTriangles) + " flipped, " +
                  std::to_string(x.degenerateTriangles) + " zero-area triangles and " +
                  std::to_string(x.selfIntersections) + " crossing pairs are left" +
                  (x.selfIntersectionsAtInputCrossings > 0
                       ? ", " + std::to_string(x.selfIntersectionsAtInputCrossings) +
                             " of them where the input crosses itself"
                       : std::string()) +
                  (r.inputSelfIntersections > 0
                       ? " (the input itself has " + std::to_string(r.inputSelfIntersections) +
                             " crossing pairs)"
                       : std::string()) +
                  "; another RemeshOptions::baseFaces or RemeshOptions::levels may avoid them");
  const int baseFaces = static_cast<int>(x.base.F.rows());
  if (baseFaces > r.requestedBaseFaces)
    out.push_back("the base has " + std::to_string(baseFaces) + " faces, more than the " +
                  std::to_string(r.requestedBaseFaces) + " asked for: " +
                  (x.baseSizeReason.empty() ? std::string("the simplification stopped early")
                                            : x.baseSizeReason));
  if (r.distance.hausdorffRelative > kFarRemeshing) {
    char buf[360];
    std::snprintf(buf, sizeof buf,
                  "the remeshed surface is %.2f%% of the bounding-box diagonal from the input "
                  "at its farthest (over %.0f%%): raise RemeshOptions::levels for finer "
                  "sampling, or RemeshOptions::baseFaces if thin or protruding parts of the "
                  "input are missed",
                  100 * r.distance.hausdorffRelative, 100 * kFarRemeshing);
    out.push_back(buf);
  }
  return out;
}

}  // namespace

// ---- Input -------------------------------------------------------------------------

namespace {

// Remeshes `input` into `r`, which may already hold what was done to the input.
void measureRemeshing(const TriMesh& input, const std::string& source, const InputOptions& options,
                      const Progress& progress, RemeshReport& r) {
  r.inputVertices = static_cast<int>(input.V.rows());
  r.inputFaces = static_cast<int>(input.F.rows());
  r.requestedBaseFaces = options.remeshing.baseFaces;
  const auto t0 = Clock::now();
  r.result = naming(source, [&] { return remesh(input, options.remeshing, progress); });
  r.seconds = secondsSince(t0);
  report(progress, "measuring the remeshing", 0);
  r.distance = surfaceDistance(r.result.mesh, input, options.distance);
  if (r.result.selfIntersections > 0)
    r.inputSelfIntersections = findSelfIntersections(input, 0).count;
  for (std::string& w : remeshWarnings(r)) r.warnings.push_back(std::move(w));
}

// Components too small to be simplified (a scan's debris: a triangle is a base face of
// its own) take base faces from the surface: said when they take a tenth of those asked.
void warnOfDebris(const TriMesh& input, const InputOptions& options, RemeshReport& r) {
  constexpr int kDebris = 16;  // faces
  if (options.minComponentFaces >= kDebris || input.F.rows() == 0) return;
  std::vector<int> size;
  for (int c : componentOfFaces(input.F, static_cast<int>(input.V.rows()))) {
    if (c >= static_cast<int>(size.size())) size.resize(c + 1, 0);
    ++size[c];
  }
  int components = 0, faces = 0;
  for (int n : size)
    if (n < kDebris) {
      ++components;
      faces += n;
    }
  if (10 * faces < options.remeshing.baseFaces) return;
  r.warnings.push_back(std::to_string(components) + " components of fewer than " +
                       std::to_string(kDebris) + " faces (" + std::to_string(faces) +
                       " faces in all; debris?) take up to " + std::to_string(faces) + " of the " +
                       std::to_string(options.remeshing.baseFaces) +
                       " base faces asked for; InputOptions::minComponentFaces " +
                       std::to_string(kDebris) + " drops them");
}

// The repairs loadSurface makes to an input before remeshing it (mesh/mesh.h,
// mesh/t_junctions.h, mesh/zero_area.h), in this order: each counted in `r`, and said
// in a warning where a user should know.
void repairInput(TriMesh& input, const InputOptions& options, RemeshReport& r) {
  r.repeatedCornerFaces = removeFacesWithRepeatedCorners(input);
  r.droppedVertices = removeUnreferencedVertices(input);
  r.duplicateFaces = removeDuplicateFaces(input);
  r.welding = weldBoundaryVertices(input);
  r.zippedEdges = zipTJunctions(input);
  r.cutEdges = cutNonManifoldEdges(input);
  r.reorientedFaces = orientConsistently(input);
  r.splitVertices = splitNonManifoldVertices(input);
  r.zeroArea = removeZeroAreaFaces(input);
  r.smallComponentsDropped = removeSmallComponents(input, options.minComponentFaces);
  const auto warn = [&](bool when, const std::string& what) {
    if (when) r.warnings.push_back(what);
  };
  warnOfDebris(input, options, r);
  warn(!r.welding.refused.empty(),
       "boundary vertices at the same position were left apart: welding them fails (" +
           r.welding.refused + ")");
  warn(r.cutEdges > 0, std::to_string(r.cutEdges) +
                           " non-manifold edges (three faces or more) were cut open: the "
                           "sheets that met there are remeshed apart, touching along them");
  warn(r.reorientedFaces > 0,
       std::to_string(r.reorientedFaces) +
           " faces were reversed to agree with their neighbours' winding (the winding most "
           "faces of each component had is kept)");
  warn(r.zeroArea.left > 0,
       std::to_string(r.zeroArea.left) +
           " zero-area input faces could not be mended (no flip or collapse keeps a manifold "
           "there): the surface has no normal there, and the remeshing may fold");
}

}  // namespace

RemeshReport remeshMeasured(const TriMesh& input, const std::string& source,
                            const InputOptions& options, const Progress& progress) {
  RemeshReport r;
  measureRemeshing(input, source, options, progress, r);
  return r;
}

TriMesh readRemeshInput(const std::string& path, const InputOptions& options,
                        RemeshReport* report) {
  // The remesher takes quad and polygon meshes too, as triangles.
  ReadOptions reading;
  reading.triangulate = true;
  TriMesh input = readMesh(path, reading);
  RemeshReport r;
  repairInput(input, options, report ? *report : r);
  validate(input, path);
  return input;
}

int baseFacesForBudget(long long triangles, int divisor) {
  return static_cast<int>(std::clamp<long long>(triangles / std::max(divisor, 1), 4, 1 << 24));
}

LoadedSurface loadSurface(const std::string& path, const InputOptions& options,
                          const Progress& progress) {
  const auto t0 = Clock::now();
  LoadedSurface s;
  s.source = path;
  report(progress, "reading", 0);
  if (!options.remesh) {
    s.mesh = readValidMesh(path);
  } else {
    RemeshReport r;
    TriMesh input = readRemeshInput(path, options, &r);
    measureRemeshing(input, path, options, progress, r);
    r.input = std::move(input);
    s.remeshing = std::move(r);
    s.mesh = s.remeshing->result.mesh;
  }
  s.seconds = secondsSince(t0);
  return s;
}

// ---- Analysis ----------------------------------------------------------------------

struct AnalysedSurface::State {
  // Exactly one of the two: a recovered mesh, or a stored decomposition's hierarchy.
  std::optional<CanonicalSurface> surface;
  std::optional<Hierarchy> hierarchy;
  FilterBank bank;
  Decomposition d;
  std::unique_ptr<Approximator> approximator;
  AnalysisTimes times;
  const Hierarchy& h() const { return surface ? surface->hierarchy : *hierarchy; }
};

namespace {

// `options` with levels of detail matched to `input` (ApproximationOptions::closestTarget),
// unless they are matched to another surface already.
AnalysisOptions matchedTo(const TriMesh& input, AnalysisOptions options) {
  if (!options.approximation.closestTarget)
    options.approximation.closestTarget = std::make_shared<const TriMesh>(input);
  return options;
}

}  // namespace

AnalysisOptions analysisOptionsFor(const LoadedSurface& s, const AnalysisOptions& options) {
  const bool remeshed = s.remeshing && s.remeshing->input.F.rows() > 0;
  return remeshed ? matchedTo(s.remeshing->input, options) : options;
}

AnalysedSurface::AnalysedSurface(const TriMesh& mesh, const AnalysisOptions& options,
                                 const std::string& source, const Progress& progress)
    : state_(std::make_unique<State>()) {
  State& s = *state_;
  auto t = Clock::now();
  report(progress, "recovering the subdivision structure", 0);
  s.surface = naming(source, [&] { return canonicalSurface(mesh, options.levels); });
  s.times.recover = secondsSince(t);
  t = Clock::now();
  s.bank = makeFilterBank(s.surface->hierarchy, options.scheme, options.wavelets, progress,
                          options.norms || options.approximator);
  s.times.precompute = secondsSince(t);
  t = Clock::now();
  s.d = analyze(s.bank, s.surface->V, progress);
  s.d.inputOrder = s.surface->inputOrder;
  s.d.inputFaces = s.surface->inputFaces;
  s.times.analysis = secondsSince(t);
  if (options.approximator) {
    t = Clock::now();
    report(progress, "preparing extraction", 0);
    s.approximator = std::make_unique<Approximator>(s.bank, s.d, options.approximation);
    s.times.approximator = secondsSince(t);
  }
}

AnalysedSurface::AnalysedSurface(Decomposition d, bool approximator, const Progress& progress)
    : state_(std::make_unique<State>()) {
  State& s = *state_;
  auto t = Clock::now();
  s.hierarchy.emplace(d.baseFaces, static_cast<int>(d.base.rows()), d.levels);
  s.bank = makeFilterBank(*s.hierarchy, d.scheme, d.wavelets, progress);
  s.times.precompute = secondsSince(t);
  s.d = std::move(d);
  if (approximator) {
    t = Clock::now();
    s.approximator = std::make_unique<Approximator>(s.bank, s.d);
    s.times.approximator = secondsSince(t);
  }
}

AnalysedSurface::~AnalysedSurface() = default;
AnalysedSurface::AnalysedSurface(AnalysedSurface&&) noexcept = default;
AnalysedSurface& AnalysedSurface::operator=(AnalysedSurface&&) noexcept = default;

const Hierarchy& AnalysedSurface::hierarchy() const {
  return state_->h();
}
const Recovery* AnalysedSurface::recovery() const {
  return state_->surface ? &state_->surface->recovery : nullptr;
}
const Points& AnalysedSurface::canonicalPositions() const {
  static const Points none;
  return state_->surface ? state_->surface->V : none;
}
const FilterBank& AnalysedSurface::bank() const {
  return state_->bank;
}
const Decomposition& AnalysedSurface::decomposition() const {
  return state_->d;
}
const Approximator& AnalysedSurface::approximator() const {
  if (!state_->approximator)
    throw Error("this analysis was made without levels of detail (AnalysisOptions::approximator)");
  return *state_->approximator;
}
void AnalysedSurface::setApproximation(const ApproximationOptions& options) {
  State& s = *state_;
  const auto t = Clock::now();
  s.approximator.reset();
  s.approximator = std::make_unique<Approximator>(s.bank, s.d, options);
  s.times.approximator = secondsSince(t);
}

const AnalysisTimes& AnalysedSurface::times() const {
  return state_->times;
}

TriMesh AnalysedSurface::reconstruct(const Decomposition& d, int level,
                                     const Progress& progress) const {
  TriMesh mesh;
  mesh.V = synthesize(state_->bank, d, level, progress);
  mesh.F = hierarchy().faces(level);
  if (level == d.levels && !d.inputOrder.empty()) {
    // Back to the input's own vertex numbering and faces.
    Points V(mesh.V.rows(), 3);
    for (Eigen::Index i = 0; i < mesh.V.rows(); ++i) V.row(d.inputOrder[i]) = mesh.V.row(i);
    mesh.V = std::move(V);
    if (d.inputFaces.rows()) mesh.F = d.inputFaces;
  }
  return mesh;
}

double AnalysedSurface::l2RmsRelative(const Approximation& a) const {
  const Approximator& x = approximator();
  const double diagonal = boundingBoxDiagonal(x.fullResolution().V);
  // An RMS over the base domain, where every base triangle has area 1.
  const double rms =
      x.l2Error(a) / std::sqrt(static_cast<double>(decomposition().baseFaces.rows()));
  return diagonal > 0 ? rms / diagonal : 0.0;
}

LodErrors AnalysedSurface::errors(const Approximation& a, const DistanceOptions& distance) const {
  const Approximator& x = approximator();
  LodErrors e;
  e.l2 = x.l2Error(a);
  const double diagonal = boundingBoxDiagonal(x.fullResolution().V);
  const double rms = e.l2 / std::sqrt(static_cast<double>(decomposition().baseFaces.rows()));
  e.l2RmsRelative = diagonal > 0 ? rms / diagonal : 0.0;
  const SurfaceDistance sd = surfaceDistance(a.mesh, x.fullResolution(), distance);
  e.rmsRelative = sd.rmsRelative;
  e.hausdorffRelative = sd.hausdorffRelative;
  return e;
}

Compressed compress(const AnalysedSurface& a, const RateTarget& target, const CodecOptions& codec) {
  return compress(a.bank(), a.decomposition(), a.canonicalPositions(), target, codec);
}

namespace {

// Whether a scheme's stream at the target is better than the other's: at a size the
// closer one, else the shorter; a stream that cannot meet a PSNR target loses.
bool better(const std::optional<Compressed>& a, const std::optional<Compressed>& b,
            const RateTarget& target) {
  if (!a || !b) return a.has_value();
  if (target.kind == RateTarget::Kind::Bytes) return a->psnrSurface > b->psnrSurface;
  if (target.kind == RateTarget::Kind::Whole) return a->wholeBytes < b->wholeBytes;
  return a->bytes.size() < b->bytes.size();
}

// Whether the stream of `a` cut to `bytes` reaches the PSNR `target` asks for.
bool reaches(const AnalysedSurface& a, std::size_t bytes, const RateTarget& target,
             CodecOptions codec) {
  codec.measureSurface = target.measure == PsnrMeasure::Surface;
  const Compressed z = compress(a, RateTarget::bytes(static_cast<double>(bytes)), codec);
  return (codec.measureSurface ? z.psnrSurface : z.psnrVertices) >= target.value;
}

}  // namespace

CodingSchemeChoice chooseCodingScheme(const TriMesh& mesh, AnalysisOptions options,
                                      CodecOptions codec, const std::string& source,
                                      const RateTarget& target) {
  const bool whole = target.kind == RateTarget::Kind::Whole;
  const bool measureWinner = codec.measureSurface;
  // What the choice needs: at a size both distances; at a PSNR the search measures
  // anyway; whole streams only their sizes.
  codec.measureSurface = !whole && (target.kind == RateTarget::Kind::Bytes || measureWinner);
  auto analysed = [&](Scheme scheme) {
    options.scheme = scheme;
    return AnalysedSurface(mesh, options, source);
  };
  // The stream at the target, or none where the whole stream cannot reach a PSNR asked.
  auto coded = [&](const AnalysedSurface& a) -> std::optional<Compressed> {
    try {
      return compress(a, target, codec);
    } catch (const Error&) {
      if (target.kind != RateTarget::Kind::Psnr) throw;
      return std::nullopt;
    }
  };
  AnalysedSurface loop = analysed(Scheme::Loop), linear = analysed(Scheme::Linear);
  std::optional<Compressed> byLinear = coded(linear), byLoop;
  // At a PSNR, Loop searches only where its stream of the polyhedral one's length
  // reaches it (the polyhedral scheme wins on scans' remeshes: one search, not two).
  if (target.kind != RateTarget::Kind::Psnr || !byLinear ||
      reaches(loop, byLinear->bytes.size(), target, codec))
    byLoop = coded(loop);
  if (!byLoop && !byLinear)  // neither reaches the PSNR: say so as compress does
    compress(loop, target, codec);
  CodingSchemeChoice c;
  c.loopBytes = byLoop ? (whole ? byLoop->wholeBytes : byLoop->bytes.size()) : 0;
  c.linearBytes = byLinear ? (whole ? byLinear->wholeBytes : byLinear->bytes.size()) : 0;
  if (target.kind == RateTarget::Kind::Bytes) {
    c.loopPsnr = byLoop->psnrSurface;
    c.linearPsnr = byLinear->psnrSurface;
  }
  c.scheme = better(byLinear, byLoop, target) ? Scheme::Linear : Scheme::Loop;
  c.surface.emplace(std::move(c.scheme == Scheme::Linear ? linear : loop));
  c.compressed = std::move(c.scheme == Scheme::Linear ? byLinear : byLoop);
  // The whole stream was coded without its surface distance; measure the winner's.
  if (whole && measureWinner) {
    codec.measureSurface = true;
    c.compressed = compress(*c.surface, target, codec);
  }
  return c;
}

// ---- A level of detail of any mesh, for a budget ---------------------------------------

namespace {

// One trial of lodForBudget: a remeshing of the input, or the input itself, cut at the
// budget and measured against the input.
struct Trial {
  BaseTrial row;
  BudgetLod lod;
};

// A trial's surface (t.lod.surface.mesh) analysed, cut at the budget and measured
// against the input.
void cutAndMeasure(const TriMesh& input, long long budget, const AnalysisOptions& analysis,
                   const BudgetSearchOptions& search, const Progress& progress, Trial& t) {
  const AnalysedSurface& a =
      t.lod.analysed.emplace(t.lod.surface.mesh, analysis, t.lod.surface.source, progress);
  const auto t1 = Clock::now();
  t.lod.lod = a.approximator().budget(budget);
  t.lod.extractSeconds = secondsSince(t1);
  t.row.triangles = t.lod.lod.triangles();
  t.row.crossingPairs = findSelfIntersections(t.lod.lod.mesh, 0).count;
  t.row.rmsRelative = surfaceDistance(t.lod.lod.mesh, input, search.selection).rmsRelative;
}

// One remeshing lodForBudget tries: over `baseFaces`, with skinny faces where flat
// (RemeshOptions::skinnyWhereFlat) or not, its base's edges flipped towards the input
// (RemeshOptions::flipTowardsInput: this stretch) or not, its vertices removed in order of
// the error they make (RemeshOptions::orderByError) or not.
struct Ask {
  int baseFaces = 0;
  double skinnyWhereFlat = 0;
  double flipTowardsInput = 0;
  bool orderByError = false;
};

// The trial of `input` remeshed as `ask` says.
Trial tryBase(const TriMesh& input, const RemeshReport& repairs, const std::string& path,
              long long budget, Ask ask, InputOptions options, const AnalysisOptions& analysis,
              const BudgetSearchOptions& search, const Progress& progress) {
  const auto t0 = Clock::now();
  const int baseFaces = ask.baseFaces;
  options.remeshing.baseFaces = baseFaces;
  if (search.stagesPerVertex) options.remeshing.stages = StageRelaxation::perVertex;
  if (search.retriangulateByError) options.remeshing.retriangulateByError = true;
  options.remeshing.skinnyWhereFlat = ask.skinnyWhereFlat;
  options.remeshing.flipTowardsInput = ask.flipTowardsInput;
  options.remeshing.orderByError = ask.orderByError;
  // A level of detail within the budget may be the base itself: no splits past the size
  // asked.
  options.remeshing.splitFoldingFaces = false;
  if (search.levelsForEachBase && options.remeshing.maxFaces == 0)
    options.remeshing.maxFaces = kLodRemeshingFaces;
  Trial t;
  LoadedSurface& s = t.lod.surface;
  s.source = path;
  s.remeshing = repairs;
  measureRemeshing(input, path, options, progress, *s.remeshing);
  s.mesh = s.remeshing->result.mesh;
  s.seconds = secondsSince(t0);
  t.row.baseFacesAsked = baseFaces;
  t.row.skinnyWhereFlat = ask.skinnyWhereFlat;
  t.row.orderByError = ask.orderByError;
  t.row.flipsTowardsInput = s.remeshing->result.baseFlipsTowardsInput;
  t.row.baseFaces = static_cast<int>(s.remeshing->result.base.F.rows());
  t.row.levels = s.remeshing->result.levels;
  cutAndMeasure(input, budget, analysis, search, progress, t);
  t.row.seconds = secondsSince(t0);
  return t;
}

// The trial of the input's own hierarchy, where it has one whose base fits in the
// budget (BudgetSearchOptions::inputHierarchy): the input analysed as it is, with every
// level it has. A base over the budget is no trial: a remeshing can go coarser.
std::optional<Trial> tryInputHierarchy(const TriMesh& input, const std::string& path,
                                       long long budget, AnalysisOptions analysis,
                                       const BudgetSearchOptions& search) {
  const auto t0 = Clock::now();
  const Recovery r = recoverSubdivision(input.F, static_cast<int>(input.V.rows()));
  if (r.levels < 1 || r.baseFaces.rows() > budget) return std::nullopt;
  Trial t;
  t.lod.surface.source = path;
  t.lod.surface.mesh = input;
  t.row.inputHierarchy = true;
  analysis.levels = -1;
  cutAndMeasure(input, budget, analysis, search, {}, t);
  t.row.baseFaces = t.lod.analysed->hierarchy().numFaces(0);
  t.row.levels = t.lod.analysed->levels();
  t.row.seconds = secondsSince(t0);
  return t;
}

// The remeshings of search.divisors for `budget`, each base smaller than the one before
// (tiny budgets give the same size for several), and the whole budget's again with
// skinny faces where flat (BudgetSearchOptions::skinnyWhereFlat), and a third time with
// those and its edges flipped towards the input (BudgetSearchOptions::flipTowardsInput),
// and a fourth and a fifth as the first and the second, their vertices removed in order
// of error (BudgetSearchOptions::orderByError).
std::vector<Ask> remeshingsToTry(long long budget, const BudgetSearchOptions& search) {
  std::vector<Ask> asks;
  for (int divisor : search.divisors) {
    const int ask = baseFacesForBudget(budget, divisor);
    if (asks.empty() || ask < asks.back().baseFaces) asks.push_back({ask, 0});
  }
  if (asks.empty()) throw Error("lodForBudget: no base size to try");
  const int whole = baseFacesForBudget(budget, 1);
  if (search.skinnyWhereFlat > 0 && asks.front().baseFaces == whole)
    asks.insert(asks.begin() + 1, Ask{whole, search.skinnyWhereFlat});
  const int flipped = search.skinnyWhereFlat > 0 ? 2 : 1;
  if (search.flipTowardsInput > 0 && asks.front().baseFaces == whole)
    asks.insert(asks.begin() + flipped,
                Ask{whole, search.skinnyWhereFlat, search.flipTowardsInput});
  if (search.orderByError && asks.front().baseFaces == whole) {
    const int ordered = flipped + (search.flipTowardsInput > 0 ? 1 : 0);
    asks.insert(asks.begin() + ordered, Ask{whole, 0, 0, true});
    if (search.skinnyWhereFlat > 0)
      asks.insert(asks.begin() + ordered + 1, Ask{whole, search.skinnyWhereFlat, 0, true});
  }
  return asks;
}

// The remeshings lodForBudget tries for `budget`; throws Error for a budget under 1.
std::vector<Ask> checkBudget(const std::string& source, long long budget,
                             const BudgetSearchOptions& search) {
  if (budget < 1) throw Error(source + ": a level of detail needs a budget of 1 triangle or more");
  return remeshingsToTry(budget, search);
}

// Whether trial a's level of detail is to be kept over b's: within the budget first,
// then one that does not cross itself, then the closer to the input (the larger base on
// a tie, tried first). A remeshing's own defects do not count: they lie in fine
// triangles a level of detail seldom keeps, and preferring a clean remeshing cost the
// horse at 970 triangles 0.84 -> 0.93x meshoptimizer's RMS, beetle-alt at 3,866
// 1.22 -> 1.52x (docs/LOD.md).
bool better(const BaseTrial& a, const BaseTrial& b, long long budget) {
  const bool aFits = a.triangles <= budget, bFits = b.triangles <= budget;
  if (aFits != bFits) return aFits;
  if ((a.crossingPairs == 0) != (b.crossingPairs == 0)) return a.crossingPairs == 0;
  return a.rmsRelative < b.rmsRelative;
}

}  // namespace

BudgetLod lodForBudget(const std::string& path, long long budget, InputOptions input,
                       const AnalysisOptions& analysis, const BudgetSearchOptions& search,
                       const Progress& progress) {
  checkBudget(path, budget, search);  // before the reading
  const auto t0 = Clock::now();
  input.remesh = true;
  RemeshReport repairs;
  report(progress, "reading", 0);
  const TriMesh mesh = readRemeshInput(path, input, &repairs);
  BudgetLod out = lodForBudget(mesh, repairs, path, budget, input, analysis, search, progress);
  out.surface.seconds = secondsSince(t0);
  return out;
}

BudgetLod lodForBudget(const TriMesh& mesh, const RemeshReport& repairs, const std::string& path,
                       long long budget, const InputOptions& input, const AnalysisOptions& analysis,
                       const BudgetSearchOptions& search, const Progress& progress) {
  const std::vector<Ask> asks = checkBudget(path, budget, search);
  const auto t0 = Clock::now();
  const AnalysisOptions fitted = search.fitToInput ? matchedTo(mesh, analysis) : analysis;
  const auto run = [&](Ask ask, const Progress& p) {
    return tryBase(mesh, repairs, path, budget, ask, input, fitted, search, p);
  };
  // The first trial in this thread, reporting progress; the others beside it.
  const auto policy = search.concurrently ? std::launch::async : std::launch::deferred;
  std::vector<std::future<Trial>> others;
  for (std::size_t i = 1; i < asks.size(); ++i)
    others.push_back(std::async(policy, run, asks[i], Progress{}));
  std::future<std::optional<Trial>> own;
  if (search.inputHierarchy)
    own = std::async(policy, tryInputHierarchy, std::cref(mesh), std::cref(path), budget, fitted,
                     std::cref(search));
  std::vector<Trial> trials;
  trials.push_back(run(asks[0], progress));
  if (!others.empty()) report(progress, "waiting for the other base sizes", 0);
  for (std::future<Trial>& f : others) trials.push_back(f.get());
  if (own.valid())
    if (std::optional<Trial> t = own.get()) trials.push_back(std::move(*t));
  int chosen = 0;
  for (int i = 1; i < static_cast<int>(trials.size()); ++i)
    if (better(trials[i].row, trials[chosen].row, budget)) chosen = i;
  BudgetLod out = std::move(trials[chosen].lod);
  out.chosen = chosen;
  for (const Trial& t : trials) out.trials.push_back(t.row);
  // What the level of detail is measured against.
  if (out.surface.remeshing) out.surface.remeshing->input = mesh;
  out.surface.seconds = secondsSince(t0);
  return out;
}

}  // namespace osdmra
