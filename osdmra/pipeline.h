// Pipeline: the path every front end takes from a mesh file to levels of detail, and
// the top layer of osdmra (it uses every layer below; nothing below uses it).
//
//   loadSurface      read a mesh (any vertex and face order) and validate it, or,
//                    with `remesh`, bring any manifold mesh to subdivision
//                    connectivity (remesh/remesh.h) and measure how far that went;
//   AnalysedSurface  recover the subdivision structure (subdivision/recovery.h),
//                    build the filter bank (mra/filter_bank.h), analyse, and hold
//                    the Approximator (mra/approximation.h).
//
// AnalysedSurface owns the whole chain, because its parts refer to each other (the
// filter bank to the hierarchy, the approximator to the filter bank and the
// decomposition): they are built together and die together, and the object can be
// moved freely, as libigl's ARAPData holds the state between precomputation and
// solve. The command-line tool, the viewer and the benchmarks use only this to go
// from a file to a decomposition or a level of detail.
#pragma once

#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "osdmra/base/progress.h"
#include "osdmra/codec/codec.h"
#include "osdmra/geometry/distance.h"
#include "osdmra/mesh/mesh.h"
#include "osdmra/mesh/zero_area.h"
#include "osdmra/mra/approximation.h"
#include "osdmra/mra/decomposition.h"
#include "osdmra/mra/filter_bank.h"
#include "osdmra/remesh/remesh.h"
#include "osdmra/subdivision/recovery.h"

namespace osdmra {

// ---- Input -------------------------------------------------------------------------

struct InputOptions {
  /// Remesh the input first: any manifold triangle mesh, with or without subdivision
  /// connectivity (a scan, a model).
  bool remesh = false;
  RemeshOptions remeshing;
  /// Connected components of fewer faces than this are dropped before remeshing (a
  /// scan's debris); 0 keeps every component, as the remesher keeps the topology.
  int minComponentFaces = 0;
  /// How the remeshing's distance to the input is sampled.
  DistanceOptions distance;
};

/// A remeshing and what it cost, reported apart from any truncation error.
struct RemeshReport {
  int inputVertices = 0, inputFaces = 0;  ///< after dropping and welding vertices
  int droppedVertices = 0;                ///< unreferenced input vertices dropped
  int duplicateFaces = 0;  ///< copies of earlier faces dropped (removeDuplicateFaces)
  /// Faces naming one vertex twice, dropped (removeFacesWithRepeatedCorners).
  int repeatedCornerFaces = 0;
  /// Coincident boundary vertices merged first (weldBoundaryVertices: a triangle soup,
  /// a mesh split along texture seams).
  Welding welding;
  /// Copies made of pinched ("bowtie") vertices, one per fan after the first
  /// (splitNonManifoldVertices).
  int splitVertices = 0;
  /// Edges of three faces or more cut open (cutNonManifoldEdges).
  int cutEdges = 0;
  /// Boundary edges split at the vertices lying on them (zipTJunctions).
  int zippedEdges = 0;
  /// Faces reversed to agree with their neighbours (orientConsistently).
  int reorientedFaces = 0;
  /// Components of fewer than InputOptions::minComponentFaces faces dropped.
  int smallComponentsDropped = 0;
  /// Zero-area faces mended (removeZeroAreaFaces: CAD exports' caps and needles).
  ZeroAreaRepair zeroArea;
  int requestedBaseFaces = 0;
  Remeshing result;
  SurfaceDistance distance;  ///< between result.mesh and the input (the reference)
  /// The input as repaired, the reference of `distance` (loadSurface keeps it, so that
  /// what is made from the remeshing can be measured against what the user gave).
  TriMesh input;
  /// Crossing pairs of the input itself (findSelfIntersections), counted only when the
  /// result has some (-1 otherwise): a surface that crosses itself, or touches itself
  /// at a split pinch, cannot be remeshed without.
  long long inputSelfIntersections = -1;
  double seconds = 0;  ///< remesh() alone
  /// What a user should know before relying on the result: defects left, a base
  /// larger than asked, a result far from the input somewhere. Advice names the
  /// RemeshOptions fields (front ends map them to their own option names).
  std::vector<std::string> warnings;
};

/// The surface a front end works on.
struct LoadedSurface {
  std::string source;  ///< the path, which every message about the surface names
  TriMesh mesh;        ///< validated (manifold, oriented); remeshed with `remesh`
  std::optional<RemeshReport> remeshing;
  double seconds = 0;  ///< reading, validation and remeshing
};

/// Reads `path` (OBJ, OFF or PLY) and validates it, or with options.remesh reads it
/// (polygons as fans of triangles), drops faces naming a vertex twice and unreferenced
/// vertices, welds coincident boundary vertices, zips T-junctions, cuts non-manifold
/// edges open, orients the faces consistently, splits pinched vertices, mends zero-area
/// faces, validates and remeshes it. Throws Error naming the file and what is wrong.
LoadedSurface loadSurface(const std::string& path, const InputOptions& options = {},
                          const Progress& progress = {});

/// What loadSurface() remeshes with options.remesh: `path` read (polygons as fans of
/// triangles), repaired as said there and validated; what the repairs did goes into
/// `report` (its counts and warnings) if given.
TriMesh readRemeshInput(const std::string& path, const InputOptions& options = {},
                        RemeshReport* report = nullptr);

/// A remeshing of a valid mesh, measured (loadSurface's second half). `source` names
/// the input in messages.
RemeshReport remeshMeasured(const TriMesh& input, const std::string& source,
                            const InputOptions& options, const Progress& progress = {});

/// How far a remeshing may be from its input before it is worth a warning, as a
/// fraction of the input's bounding-box diagonal.
constexpr double kFarRemeshing = 0.01;

/// The base size to remesh with for a level of detail of at most `triangles`: a
/// quarter of them by default (triangles / divisor), at least 4. The base is where the remesher's
/// simplification puts its vertices where the surface needs them, and the level of detail refines
/// it isotropically, so the base should grow with the budget: on the bunny at 2,084 and 6,945
/// triangles a base of a quarter gave 0.75x the RMS of the 300-face default, on armadillo at 8,648
/// 0.73x (docs/LOD.md); a quarter leaves room for a base somewhat larger than asked, which the
/// remesher makes where features need it.
int baseFacesForBudget(long long triangles, int divisor = 4);

/// The size lodForBudget keeps each remeshing within (RemeshOptions::maxFaces), as the
/// default 5 levels over 300 base faces do (307,200 faces).
constexpr long long kLodRemeshingFaces = 1 << 19;

// ---- Analysis ----------------------------------------------------------------------

struct AnalysisOptions {
  /// Subdivision levels J to use; < 0 takes the largest the connectivity has.
  int levels = -1;
  Scheme scheme = Scheme::Loop;
  WaveletOptions wavelets;
  ApproximationOptions approximation;
  /// Build the Approximator (every level-of-detail query needs it). Analysis and
  /// synthesis alone do not, and skip its cost (limit stencils, sorting).
  bool approximator = true;
  /// Compute the wavelets' norms ||psi^j_m|| (FilterBank::norms), which truncation,
  /// importance and the Approximator weigh coefficients by. A codec needs none, and
  /// without them fixed and lazy wavelets need no local solve.
  bool norms = true;
};

/// `options` for analysing `s`: as given, and where `s` is a remeshing, its levels of
/// detail matched to the input it was made from (ApproximationOptions::closestTarget,
/// unless one is given), which they are measured against, as lodForBudget matches its
/// trials' (BudgetSearchOptions::fitToInput).
AnalysisOptions analysisOptionsFor(const LoadedSurface& s, const AnalysisOptions& options);

/// Seconds spent in each stage of AnalysedSurface's construction.
struct AnalysisTimes {
  double recover = 0, precompute = 0, analysis = 0, approximator = 0;
  double total() const { return recover + precompute + analysis + approximator; }
};

/// The errors of a level of detail against the full-resolution surface, relative to
/// its bounding-box diagonal where so named.
struct LodErrors {
  double l2 = 0;                 ///< exact parametric L2 (Approximator::l2Error)
  double l2RmsRelative = 0;      ///< the same as an RMS over the base domain
  double rmsRelative = 0;        ///< sampled symmetric RMS distance
  double hausdorffRelative = 0;  ///< sampled symmetric Hausdorff distance
};

class AnalysedSurface {
 public:
  /// Recovers the structure of a valid mesh (in any vertex and face order), builds the
  /// filter bank, analyses the mesh and, with options.approximator, prepares levels of
  /// detail. Errors are prefixed with `source` (a file name) when it is not empty.
  AnalysedSurface(const TriMesh& mesh, const AnalysisOptions& options = {},
                  const std::string& source = "", const Progress& progress = {});
  /// A stored decomposition (a .mra file): the hierarchy over its base and the filter
  /// bank of its scheme and wavelets. There is no recovery; levels of detail need
  /// `approximator`.
  explicit AnalysedSurface(Decomposition d, bool approximator = false,
                           const Progress& progress = {});
  ~AnalysedSurface();
  AnalysedSurface(AnalysedSurface&&) noexcept;
  AnalysedSurface& operator=(AnalysedSurface&&) noexcept;

  const Hierarchy& hierarchy() const;
  /// What recovery found (levels, base, why it stopped); null for a stored
  /// decomposition.
  const Recovery* recovery() const;
  /// The input's positions in canonical order (empty for a stored decomposition).
  const Points& canonicalPositions() const;
  const FilterBank& bank() const;
  const Decomposition& decomposition() const;
  /// The approximator; throws Error when it was not built.
  const Approximator& approximator() const;
  /// Builds the approximator again with other options (ranking, saturation), without
  /// analysing again.
  void setApproximation(const ApproximationOptions& options);
  const AnalysisTimes& times() const;
  int levels() const { return decomposition().levels; }

  /// The surface of `d` (this decomposition or a truncation of it) at `level`,
  /// as a mesh: canonical order below J; at J, the input's own vertex order and
  /// faces when it had them.
  TriMesh reconstruct(const Decomposition& d, int level, const Progress& progress = {}) const;

  /// The parametric RMS of a level of detail's error relative to the diagonal of the
  /// full-resolution surface (one synthesis; no sampling).
  double l2RmsRelative(const Approximation& a) const;
  /// Every error of a level of detail, sampled ones included (surfaceDistance).
  LodErrors errors(const Approximation& a, const DistanceOptions& distance = {}) const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

/// The scheme a surface codes better with (`osdmra compress` without --scheme): each
/// analyses `mesh` and codes it, and the better stream at the rate asked wins: at a
/// size (RateTarget::Kind::Bytes) the one closer to `mesh` by the sampled surface
/// distance, at a PSNR the shorter one, and for the whole stream the shorter whole
/// stream at `codec`'s precision (which bounds the error either way, though not
/// equally: Loop's synthesis averages quantisation errors where the polyhedral
/// scheme's does not). The polyhedral scheme wins on remeshes of scans, flat inside
/// every input triangle, where a midpoint predicts the new vertex exactly and Loop's
/// smoothing does not (at 2 bits per vertex on 15 of the 16 shared scans' J = 5
/// remeshes, by 1.7-21.9 dB; armadillo's went to Loop by 0.2); on the bundled head Loop wins at low
/// rates and the two are level from 1.5 bits per vertex up (docs/COMPRESSION.md). Costs two
/// analyses and two codings; at a size one more surface distance; at a PSNR the polyhedral scheme's
/// search and one distance of Loop's stream at that length, and Loop's search only where that
/// reaches the PSNR.
struct CodingSchemeChoice {
  Scheme scheme = Scheme::Loop;
  /// What the choice compared: the streams' sizes (whole, or cut at a PSNR: 0 for a
  /// scheme not searched, whose stream did not reach the PSNR at the other's length or
  /// at all), and at a size their surface PSNR (NaN otherwise).
  std::size_t loopBytes = 0, linearBytes = 0;
  double loopPsnr = std::numeric_limits<double>::quiet_NaN(), linearPsnr = loopPsnr;
  /// The surface analysed with `scheme`, ready to code (not analysed again).
  std::optional<AnalysedSurface> surface;
  /// Its stream at the target with `codec`'s options (a PSNR measured as they say).
  std::optional<Compressed> compressed;
};
/// compress() of an analysed surface: its bank, decomposition and canonical positions.
Compressed compress(const AnalysedSurface& a, const RateTarget& target = {},
                    const CodecOptions& codec = {});

CodingSchemeChoice chooseCodingScheme(const TriMesh& mesh, AnalysisOptions options,
                                      CodecOptions codec, const std::string& source = "",
                                      const RateTarget& target = RateTarget::whole());

// ---- A level of detail of any mesh, for a budget ---------------------------------------

/// The base sizes lodForBudget tries.
struct BudgetSearchOptions {
  /// Each trial remeshes over baseFacesForBudget(budget, divisor) base faces, in this
  /// order (largest base first).
  /// The whole budget makes the level of detail the base itself (the remesher's
  /// simplification, its faces placed by the error they make), a half leaves it one level
  /// of splits to choose among, a quarter two, a sixteenth three: which is closer depends
  /// on the mesh, and nothing measured predicts it, so all four are made. On the 48 rows
  /// of docs/LOD.md ("A scan as a user gives it") a sixteenth was closer than a quarter on
  /// 10, by up to 32% RMS, a quarter on 31, by up to 2.5x; a half was closer than both on
  /// 12 (fandisk at 388 triangles 0.55x, the screwdriver at 68 0.76x, armadillo at 2,594
  /// and the lion at 1,667 0.83x). The whole budget, added on 2026-11-29, brought 21 of
  /// 42 rows closer (RMS 0.92x geometric mean, fandisk at 1% 0.63x, the elephant at 3%
  /// 0.70x), one farther by 3%, at the cost of a fourth remeshing.
  std::vector<int> divisors = {1, 2, 4, 16};
  /// Match each trial's level of detail to the input (ApproximationOptions::
  /// closestTarget: at its vertices and at as many area samples of it as the remeshing
  /// has vertices), which it is measured against, rather than to its remeshing, whose
  /// own error would add to its own (placements Closest and Levels). docs/LOD.md,
  /// 2026-12-01: on the five J = 5 remeshes and the head, RMS 0.925x (geometric mean
  /// over 36 rows; spot at 12,310 triangles 5.95e-5 -> 4.80e-5; fandisk at 4,054
  /// 1.024x); on the 16 scans (lod_scans) 0.979x, 42 of 48 rows closer, spot at 59
  /// 1.04x farther. Matched at the input's vertices alone it was 1.037x on the scans,
  /// whose vertices crowd.
  bool fitToInput = true;
  /// Remesh each base with as many levels, up to InputOptions::remeshing.levels, as
  /// keep the remeshing within kLodRemeshingFaces (or RemeshOptions::maxFaces when
  /// given), counted on the base the remesher made; off keeps InputOptions::remeshing.levels for
  /// every trial (a user's --levels).
  bool levelsForEachBase = true;
  /// Run the trials at once, each on its own thread (the remesher's simplification is
  /// serial: two trials on two cores take about the time of one and a half), holding
  /// their memory together; off, one after the other (the same result).
  bool concurrently = true;
  /// How each trial's level of detail is measured against the input. It only ranks the
  /// trials, so it samples less than a report does.
  DistanceOptions selection{20000, 1, true};
  /// Remesh with StageRelaxation::perVertex, whatever InputOptions say: the
  /// coarse levels of a level of detail are the base, which then spreads by importance
  /// (on the 48 rows of docs/LOD.md, RMS at most meshoptimizer's on 38 instead of 35).
  bool stagesPerVertex = true;
  /// Remesh with RemeshOptions::retriangulateByError on, whatever InputOptions say: the
  /// base's faces chosen by the error they make, as a quadric simplifier's are (with
  /// stagesPerVertex, on the same rows: within 1.3x of CGAL Garland-Heckbert's RMS on 38
  /// instead of 34, both of issue 14's targets on 37 instead of 34).
  bool retriangulateByError = true;
  /// Where the input has subdivision connectivity, cut its own hierarchy at the budget
  /// too (no remeshing: a trial of its own, BaseTrial::inputHierarchy), so that
  /// remeshing a semi-regular input is kept only where it brings the level of detail
  /// closer (docs/LOD.md's comparison on the bundled head and five J = 5 remeshes: the
  /// remeshing closer on 32 of 36 rows, the input's own hierarchy on the head at 4,054
  /// to 16,098 triangles and fandisk's remesh at 30,720).
  bool inputHierarchy = true;
  /// Where over 0, the whole budget is tried twice, the second time with
  /// RemeshOptions::skinnyWhereFlat at this fraction: its level of detail is its base,
  /// which then keeps a CAD model's flat sides and cylinders in long thin faces, as a
  /// quadric simplifier does (on the 48 rows of docs/LOD.md: fandisk at 129, 388 and
  /// 1,295 triangles 0.63-0.74x RMS). Not instead of the first: skinny faces change the
  /// simplification's path, which can leave a base farther or over the budget (the
  /// alligator at 60 triangles 1.24x farther, the half tunnel at 16 over it), and not
  /// in the other trials, whose bases are domains the wavelets refine, where a skinny
  /// face samples the surface worse (with it on every trial the lion at 500 came 1.13x
  /// farther and crossing itself).
  double skinnyWhereFlat = 0.1;
  /// Where over 0, the whole budget is tried a third time, as the second and with its
  /// base's edges flipped where the input points a pair holds lie nearer the flipped
  /// faces' planes (RemeshOptions::flipTowardsInput, each new face within this stretch
  /// of its flat shape): a data-dependent triangulation of the same vertices, whose
  /// edges follow the surface's curvature as a quadric simplifier's do. On the 48 rows
  /// of docs/LOD.md's scans table: RMS 0.971x (geometric mean; 24 rows closer, 2
  /// farther), at most meshoptimizer's on all 44 rows within the budget instead of 43
  /// (fandisk at 388 1.10 -> 0.72x), for 1.48x the time. Beside the second trial, not
  /// instead of it: flipped, fandisk's base at 1,295 came 1.39x farther (its fit to
  /// the points as they are is not its fit once its vertices are matched to the input).
  double flipTowardsInput = 2;
  /// Where on, the whole budget is tried twice more, as the first and the second trial
  /// (without and with skinny faces where flat; never flipped: flips took the head's
  /// level of detail at 16,098 triangles from 5.7e-5 to 7.8e-5 of the diagonal) and with
  /// the input's vertices removed in order of the error each removal makes, measured
  /// (RemeshOptions::orderByError), as a quadric simplifier chooses its collapses: the
  /// head's level of detail at 16,098 triangles 8.87e-5 -> 5.40e-5 (RMS; meshoptimizer
  /// 9.10e-5, CGAL Garland-Heckbert 6.61e-5; docs/LOD.md), for 1.5-2.5x the time of
  /// the other trials each. Beside them, not instead of them: that was not measured.
  bool orderByError = true;
};

/// One base size lodForBudget tried.
struct BaseTrial {
  /// The input's own hierarchy rather than a remeshing (BudgetSearchOptions::
  /// inputHierarchy); baseFacesAsked is then 0.
  bool inputHierarchy = false;
  int baseFacesAsked = 0, baseFaces = 0, levels = 0;
  /// RemeshOptions::skinnyWhereFlat of its remeshing (BudgetSearchOptions::skinnyWhereFlat).
  double skinnyWhereFlat = 0;
  /// Base edges of its remeshing flipped towards the input
  /// (BudgetSearchOptions::flipTowardsInput).
  int flipsTowardsInput = 0;
  /// RemeshOptions::orderByError of its remeshing (BudgetSearchOptions::orderByError).
  bool orderByError = false;
  int triangles = 0;  ///< of its level of detail at the budget
  /// Pairs of its level of detail's triangles that cross without being neighbours
  /// (findSelfIntersections).
  long long crossingPairs = 0;
  double rmsRelative = 0;  ///< of that level of detail to the input (selection's samples)
  double seconds = 0;      ///< remeshing, analysis, extraction and measurement
};

/// What lodForBudget kept.
struct BudgetLod {
  /// The remeshing kept, its RemeshReport::input the repaired input; or the input
  /// itself, without a RemeshReport, where its own hierarchy was kept.
  LoadedSurface surface;
  std::optional<AnalysedSurface> analysed;  ///< its analysis
  Approximation lod;                        ///< its level of detail at the budget
  double extractSeconds = 0;                ///< that extraction's time
  std::vector<BaseTrial> trials;            ///< in the order tried
  int chosen = 0;                           ///< the trial kept
};

/// `osdmra lod IN --remesh --budget N` without --base-faces: reads and repairs `path`
/// once (readRemeshInput), then for each of search.divisors (sizes that coincide on a
/// tiny budget tried once) remeshes it over that base size, analyses the remeshing with
/// `analysis`, extracts the level of detail of at most `budget` triangles and measures
/// it against the input; keeps the closest (one within the budget before one over it,
/// then one that does not cross itself before one that does). Where the input has
/// subdivision connectivity, its own hierarchy is one more trial (search.inputHierarchy).
/// The remesher's simplification places the base's vertices and the level of detail
/// only splits its faces, so the base's size and layout decide much of the error, and
/// no rule predicts the better one per mesh. Each trial costs one remeshing and
/// analysis; `progress` follows the first. Throws Error as loadSurface does.
BudgetLod lodForBudget(const std::string& path, long long budget, InputOptions input,
                       const AnalysisOptions& analysis, const BudgetSearchOptions& search = {},
                       const Progress& progress = {});
/// The same on a mesh already read and repaired by readRemeshInput (`repairs` its
/// report), named `path` in messages: a caller making several levels of detail of one
/// file reads it once.
BudgetLod lodForBudget(const TriMesh& mesh, const RemeshReport& repairs, const std::string& path,
                       long long budget, const InputOptions& input, const AnalysisOptions& analysis,
                       const BudgetSearchOptions& search = {}, const Progress& progress = {});

}  // namespace osdmra
