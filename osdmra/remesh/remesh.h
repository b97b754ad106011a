// Remeshing: any manifold triangle mesh to a mesh with subdivision connectivity, in
// the spirit of MAPS (Lee, Sweldens, Schroder, Cowsar and Dobkin 1998). The driver,
// remesh(), reads as the algorithm; each stage has its own file and tests:
//
// 0. The input renumbered along space (mesh/spatial_order.h): faster, and the result
//    the same for every numbering of the same surface; its folds taken out (unfold.h),
//    each fold's corners moved a short way on the surface.
// 1. Features (features.h): feature lines, corners of lines and boundaries, tips of
//    protrusions, folds.
// 2. Simplification with a parameterisation (simplify.h): vertices removed in rounds
//    of independent sets, each removal's one-ring flattened and retriangulated so that
//    the old faces map onto the new ones bijectively, checked for every removal
//    (removal.h), with the distortion of every input triangle between its corners'
//    places bounded, in the new faces hinged flat (distortion.h), and the cone of every
//    tip of a protrusion kept shared among the faces around it; the bounds relax in
//    stages only when nothing else can go. Every input vertex keeps its place on the
//    simplified mesh. The result is a base mesh M^0 of about the requested size.
//    Genus, boundary loops and components are kept.
// 3. Smoothing of those places (smoothing.h): each moved to lower the stretch of the
//    map, within the same bounds, so that the grid samples the surface evenly.
// 4. Resampling (resample.h): each base face split J times, every grid point placed on
//    the input through the parameterisation made affine on each input triangle between
//    its corners' places (charts.h): the map whose distortion step 2 bounded. Where
//    that grid folds a triangle, the grid through the exact inverse of the removals is
//    sampled too, and kept where it folds none; where both fold, the base faces holding
//    the folds are split (base_flips.h, within 10% of the size asked) and both grids
//    sampled again, the split base kept where it folds less.
// 5. Clean-up (cleanup.h), a safety net for what sampling still folds; remesh()
//    reports how much of it ran.
//
// The output has subdivision connectivity in its own vertex and face order: the
// rest of osdmra recovers its structure (recovery.h).
#pragma once

#include <string>

#include "osdmra/base/progress.h"
#include "osdmra/mesh/mesh.h"
#include "osdmra/remesh/unfold.h"

namespace osdmra {

/// How the simplification relaxes its stages (simplify.h's kStages, strictest first).
enum class StageRelaxation {
  /// A vertex its stage's limits keep waits until no vertex at all can go, and the size
  /// asked is then reached by removing important vertices: at 1% of their faces the
  /// bases of the camel head, the lion and armadillo come 3.2, 3.3 and 0.65% of the
  /// diagonal from their scans (RMS).
  meshWide,
  /// A vertex kept in a round where a more important one is removed goes on under the
  /// next stage's limits, so that the base spreads by importance (1.2, 2.3 and 0.45% on
  /// the same scans). The parameterisation is more distorted where loose limits went
  /// early: over the corpus of docs/REMESH.md, 21% lower RMS and 11% lower Hausdorff
  /// distances than meshWide, but 6 of its 90 runs other than the cow's with flipped or
  /// crossing triangles instead of none.
  perVertex,
  /// perVertex, and where its remesh has defects beyond the input's own (flipped,
  /// zero-area, or crossing pairs away from the input's crossings) meshWide as well, the
  /// one with fewer defects kept: perVertex's accuracy where it samples cleanly,
  /// meshWide's robustness where it does not, at twice the time there. Over the corpus
  /// of docs/REMESH.md against meshWide: RMS 0.80x, Hausdorff 0.87x, no run but the
  /// cow's with a defect (as meshWide), 99 s in all against 125; but the clean-up moves
  /// points on 56 of the 96 runs instead of 47.
  perVertexElseMeshWide,
};

struct RemeshOptions {
  /// Target number of base faces: simplification stops at or just below it, or
  /// earlier when no vertex can be removed without changing the topology or
  /// flattening the tip of a protrusion (a one-ring whose angles sum to under 192
  /// degrees, such as the bunny's ear tips below about 180 faces).
  int baseFaces = 300;
  /// Rounds of 1-to-4 splitting of the base mesh.
  int levels = 5;
  /// At most this many output faces (0: no limit): when the base comes out larger than
  /// asked (features, topology: see Remeshing::baseSizeReason), fewer levels keep the
  /// output within it (levelsWithin). Without a limit the output grows with the base:
  /// an ogre's 656 base faces for 300 asked give 671,744 faces at 5 levels, and take
  /// as much longer to sample, clean and analyse.
  long long maxFaces = 0;
  /// Edges whose dihedral angle (between face normals) exceeds this, in degrees,
  /// are features that stay edges of the base mesh, if they form chains of at least
  /// 4 edges (shorter ones on scans are noise). 180 turns features off. 70 was best
  /// over the four scans of docs/REMESH.md (60 pins noisy creases of the bunny).
  double featureAngle = 70.0;
  /// Sweeps of the parameterisation's smoothing (smoothing.h: each input vertex's place
  /// moved to lower the stretch of the map from the base to the input, so that a
  /// uniform grid samples the surface evenly) before the resampling; 0 turns it off.
  /// Each sweep moves a place by at most a quarter of its distance to its nearest
  /// neighbour, so a squeezed region spreads out over several: on the corpus of
  /// docs/REMESH.md, 10 sweeps (5 until 2026-11-28) brought the J = 5 runs over 150
  /// faces of the lion, the bunny and armadillo within 0.5% of their diagonals
  /// (0.541 / 0.692 / 0.534% -> 0.409 / 0.481 / 0.474%) with no run gaining a defect; 20
  /// gained little more. About a twentieth of remesh()'s time on dense scans.
  int smoothingSweeps = 10;
  /// Refuse every removal of the simplification whose new faces would cross a face of
  /// the shrinking mesh that the faces they replace did not cross, so that the base
  /// crosses itself no more than the input does: where the input crosses itself, a
  /// removal whose faces hold a point of an input face that crosses another may cross
  /// faces that hold one (refusing those left the bases of the cow and the ogre a third
  /// larger than asked, over knots that are the input's either way). The output's J-fold split is
  /// checked as well; a base that crosses itself over a thin part leaves knots there that the
  /// clean-up may not untangle (the lion over 150 faces of docs/REMESH.md: 4-5 crossing pairs
  /// without it, none with it), and a level of detail near the base inherits them. On by default
  /// since 2026-11-27; it costs about 15% of the simplification (armadillo) and can leave a base
  /// larger than asked over thin parts.
  bool baseWithoutNewCrossings = true;
  /// How the simplification relaxes its stages (simplify.h's kStages): vertex by vertex,
  /// falling back to mesh-wide where that leaves defects (StageRelaxation).
  StageRelaxation stages = StageRelaxation::perVertexElseMeshWide;
  /// Retriangulate each removal's one-ring by the error it makes (simplify.h's
  /// SimplifyOptions::retriangulateByError), not by the shape of the new faces first.
  /// A fan from a ring corner is the collapse of the removed vertex into it, so this
  /// chooses as a quadric simplifier does: at 1% of their faces, with the stages relaxed
  /// vertex by vertex, the bases of armadillo, fandisk and the cow come 4.5e-3, 1.5e-2
  /// and 3.3e-2 of the diagonal from their scans without it, 3.7e-3, 1.3e-2 and 2.2e-2
  /// with it. Fans make skinnier faces than ear clipping, which sample worse: with the
  /// mesh-wide stages over the corpus of docs/REMESH.md, Hausdorff distances 10% larger
  /// and 4 runs at J = 5 over 0.5% of the diagonal instead of none. lodForBudget uses it
  /// (BudgetSearchOptions::retriangulateByError).
  bool retriangulateByError = false;
  /// Let new base faces go skinnier than the simplification's stages allow where the
  /// input they hold is flat across them (simplify.h's SimplifyOptions::skinnyWhereFlat:
  /// the fraction of a face's width its points may stray from its plane; 0, the
  /// default, never). lodForBudget uses it (BudgetSearchOptions::skinnyWhereFlat).
  double skinnyWhereFlat = 0;
  /// Remove the input's vertices in order of the error their removal makes, as a quadric
  /// simplifier orders its collapses (simplify.h's SimplifyOptions::orderByError), not
  /// by one-ring area and curvature; off by default. lodForBudget uses it for two trials
  /// (BudgetSearchOptions::orderByError).
  bool orderByError = false;
  /// Flip a base edge opposite an angle wider than this, in degrees, where the flip
  /// narrows the pair's widest angle and the grid of `levels` splits sampled over the
  /// pair through the exact map folds less after it (base_flips.h); 0: no flips. Over
  /// the corpus of docs/REMESH.md (2026-11-30) the bunny's per-vertex remeshes at J = 5
  /// come out clean (so its mesh-wide one is no longer run, and no longer kept: RMS
  /// 0.0160% -> 0.0056% over 300 faces), one fewer run with defects, 22 of 96 rows
  /// changed, RMS 0.977x and Hausdorff 0.982x.
  double capAngle = 90;
  /// Then flip base edges where the input points the pair holds lie nearer the flipped
  /// faces' planes (base_flips.h's flipTowardsInput), each new face within this
  /// stretch of its flat shape; 0: none. lodForBudget uses it
  /// (BudgetSearchOptions::flipTowardsInput): a level of detail whose coarse levels are
  /// the base wants the base that fits the input best.
  double flipTowardsInput = 0;
  /// Where the grids sampled through both maps fold, split the longest edge of the base
  /// faces holding the straightened grid's folds (base_flips.h's splitFoldingFaces), while
  /// the base stays within 10% of `baseFaces`, and keep the split base where its grid folds
  /// less; where a split was refused for the exact grid's folds over its new faces, try
  /// the splits again without that check, kept where the straightened grid folds less
  /// still and folds nothing, or the exact one no more than before; then, where the grid
  /// kept still folds, one more round, at points of the input where a pair holds no
  /// input vertex that fits (docs/REMESH.md, step 3). Where no vertex could go under the
  /// last stage (the base over size whatever the splits) and defects are left, the same
  /// again within 10% of the size the simplification stopped at, kept where it leaves
  /// fewer defects beyond the input's own.
  bool splitFoldingFaces = true;
  /// Make each base face's grid level by level in its domain, keeping each level's
  /// triangles from folding where a step of a point in the domain mends them
  /// (grid_refinement.h); off: the uniform grid, as sampled until 2026-12-03. Over the
  /// 280 runs of docs/REMESH.md's four tables (commit e203db5 against 62e30e9) the
  /// clean-up ran on 105 instead of 129 and moved 45,293 points instead of 114,281, 22
  /// runs kept defects beyond the input's own instead of 24, and the runs took 534 s
  /// instead of 793; two fewer J = 5 runs met every target (the decimated knight over
  /// 150, whose base the uniform grid's folds had split, and odedstein's scorpion over
  /// 150).
  bool refineGrid = true;
  /// Take the input's folds out before simplifying it (unfold.h): each fold's corners
  /// moved a short way on the surface where that leaves fewer folds.
  bool unfoldInput = true;
};

struct Remeshing {
  TriMesh mesh;  ///< the remeshed surface: M^levels over `base`, positions on the input
  /// Rounds of splitting made: RemeshOptions::levels, or fewer under maxFaces.
  int levels = 0;
  /// The base mesh M^0, the first vertices of `mesh`: input vertices, but for those the
  /// unfolding or the clean-up moved (to another point of the input).
  TriMesh base;
  int featureEdges = 0;  ///< input edges taken as features
  /// Feature edges left out: lines on their own shorter than a base edge, dropped where
  /// the base would otherwise have more than 10% more faces than asked (features.h).
  int featureEdgesDropped = 0;
  int tips = 0;  ///< input vertices kept as tips of protrusions (features.h)
  /// What taking the input's folds out did (unfold.h; RemeshOptions::unfoldInput).
  remeshing::UnfoldReport unfold;
  /// Why the base has more faces than asked (empty when it has not).
  std::string baseSizeReason;
  /// Rounds of the simplification, and the last of its stages (simplify.h's kStages)
  /// that it needed.
  int simplificationRounds = 0, simplificationStage = 0;
  /// How the kept remesh's stages were relaxed: "vertex" or "mesh" (StageRelaxation);
  /// and under perVertexElseMeshWide, the defects beyond the input's own that the
  /// per-vertex remesh left (-1: not tried).
  std::string stages = "mesh";
  long long perVertexDefects = -1;
  /// What the smoothing of the parameterisation did (smoothing.h): moves kept and moves
  /// refused (a fold or too much distortion), over all its sweeps; 0, 0 without it.
  int smoothingMoves = 0, smoothingRefused = 0;
  /// Base edges flipped out of caps, and caps left (base_flips.h).
  int baseFlips = 0, baseFlipsRefused = 0;
  /// Base edges flipped towards the input (RemeshOptions::flipTowardsInput).
  int baseFlipsTowardsInput = 0;
  /// Base faces whose grid folded split, and splits refused (or undone, where the split
  /// base's grid folded no less) (RemeshOptions::splitFoldingFaces).
  int baseSplits = 0, baseSplitsRefused = 0;
  /// Of the splits made, those at a point of the input that is no input vertex
  /// (base_flips.h: BaseFlipOptions::splitAtPoints).
  int baseSplitsAtPoints = 0;
  /// The map the grid was sampled through (resample.h's GridMap): the straightened
  /// one, or where that folds grid triangles and the exact one folds none, the exact
  /// one; or the other where the first one's clean-up left defects and the other's
  /// fewer. The grid triangles each folded as sampled (flipped or of zero area, before
  /// the clean-up; -1: not sampled), and the defects (flipped, zero-area, crossing
  /// pairs) each left after the clean-up (-1: not cleaned up, as the first map's clean-up
  /// left none).
  std::string gridMap = "straightened";
  /// Steps the kept grid's refinement took in base faces' domains to keep its levels from
  /// folding (grid_refinement.h); the folds counted next are those it left.
  int gridRefinementMoves = 0;
  long long straightenedFolds = 0, exactFolds = -1;
  long long straightenedDefects = -1, exactDefects = -1;
  /// How much the clean-up ran: flipped and zero-area triangles it found, points it
  /// moved, base faces it relaxed as a whole. 0, 0, 0 when sampling folded nothing.
  int cleanupDefectsBefore = 0, cleanupMovedPoints = 0, cleanupRelaxedFaces = 0;
  /// Triangles of `mesh` left flipped (facing against the input triangle under each of
  /// their corners, where those were sampled) or
  /// of zero area after the clean-up pass; 0 is the goal (see remesh()).
  int flippedTriangles = 0, degenerateTriangles = 0;
  /// Pairs of triangles of `mesh` that cross without being neighbours
  /// (findSelfIntersections); 0 is the goal.
  long long selfIntersections = 0;
  /// Of those, the pairs where the input crosses itself: both triangles have a corner
  /// on an input face that crosses another input face or shares a corner with one.
  long long selfIntersectionsAtInputCrossings = 0;
  /// Of those, the pairs where two sheets of the input cross (faces farther apart than
  /// a fold's): no remesh on the input avoids them, and the clean-up leaves them alone.
  long long selfIntersectionsWhereSheetsCross = 0;
};

/// The levels to split a base of `baseFaces` with: the most, up to `maxLevels`, that
/// keep the output within `maxFaces` faces (0: no limit), but at least 2 (or
/// `maxLevels`, if fewer), so that a level of detail has levels to choose among: 5
/// over 300 faces within 2^19 (307,200), 4 over 1,000 (256,000).
int levelsWithin(long long baseFaces, int maxLevels, long long maxFaces);

/// Remeshes a valid mesh (validate(): manifold, oriented, no unreferenced vertex).
/// Throws Error when the mesh cannot be simplified to any base at all (fewer than
/// 4 faces, say) or when options are out of range. The result depends on the surface,
/// not on how its vertices and faces are numbered (inSpatialOrder(); but for vertices
/// at one position, taken in their order).
Remeshing remesh(const TriMesh& input, const RemeshOptions& options = {},
                 const Progress& progress = {});

}  // namespace osdmra
