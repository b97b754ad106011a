// Step 1 of remesh.h: simplification of the input to a base mesh, tracking every input
// vertex's place on it (MAPS, Lee et al. 1998). Vertices go in rounds of independent
// sets, least important first (small one-ring area and curvature; or, as an option,
// least error, measured, first: SimplifyOptions::orderByError); each removal is
// certified bijective (removal.h) and bounded in distortion (distortion.h), else
// refused; so is one that would make the mesh cross itself (noNewCrossings), leave
// one face around the tip of a protrusion of the input holding more than half of the
// tip's cone (the grid would sample the tip from that face's corner alone, and fold
// there), or leave a base edge standing for a boundary or feature line of the input
// that strays from it by over 0.3 of its length (the face beside it would cover a
// crescent, over which the grid folds). The bounds relax in stages only when nothing can go under
// the current ones, or, as an option, vertex by vertex for those passed over for more important
// ones.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <unordered_set>
#include <vector>

#include "osdmra/base/progress.h"
#include "osdmra/geometry/self_intersection.h"
#include "osdmra/geometry/surface_walk.h"
#include "osdmra/mesh/mesh.h"
#include "osdmra/remesh/features.h"
#include "osdmra/remesh/planar.h"

namespace osdmra::remeshing {

/// A point of the base mesh: a face and barycentric coordinates in its corner order.
struct Param {
  int face = -1;
  std::array<double, 3> bary{};
};

/// The limits a removal must meet in one stage of the simplification.
struct StageLimits {
  /// Largest anisotropy (distortion.h) of an input triangle between its corners'
  /// places, in the faces that hold them laid flat.
  double anisotropy;
  /// Smallest angle of a new face in the flattened ring, degrees.
  double flatAngle;
  /// Largest z^a exponent a (and smallest 1 / a): how curved a one-ring may be.
  double power;
  /// Whether a new face may go under flatAngle, down to the smallest angle of the
  /// faces the removal replaces (never skinnier than those): inputs made of slivers,
  /// as CAD exports are (a cylinder's side one strip of 1-degree triangles, caps fanned
  /// into their centres), have no removal whose new faces all meet any fixed bound.
  bool orAsSkinnyAsReplaced = false;
  /// Input triangles with an angle under this, in degrees, are exempt from the
  /// anisotropy bound (not from keeping their orientation): a sliver's anisotropy
  /// measures its own thinness, a ratio its image's tiny width changes by any amount,
  /// more than the map's distortion, which its well-shaped neighbours still bound; and
  /// a sample landing in it moves by less than its width.
  double sliverAngle = 0;
};

/// The stages, strictest first. Every stage checks every input triangle with a corner
/// among the points a removal moves, straddling faces or not, near or far apart
/// (distortion.h's chartImage); where no vertex can go under the last one the base
/// stays larger than asked and says why (a stage without the straddlers took armadillo
/// and the bunny from 159-164 faces to 150 at the price of folds that the clean-up left
/// as crossing pairs). The exponent never goes past 1.875: a one-ring whose angles sum
/// to under 2 pi / 1.875 (192 degrees) is the tip of a protrusion (an ear, a horn);
/// removing it folds the protrusion into the faces around (the bunny over 150 base faces
/// lost its ear tips so: Hausdorff 4% of the diagonal).
extern const std::vector<StageLimits> kStages;

/// One removal as it was made: the flattened ring and its retriangulation, enough to
/// map a point of a new face back to the old face it came from (removal.h).
struct RemovalRecord {
  int vertex = -1;                            ///< the removed vertex, at the origin
  std::vector<int> verts;                     ///< its ring (as Ring::verts)
  std::vector<int> oldFaces;                  ///< face k = (vertex, verts[k], verts[k+1])
  std::vector<Vec2> points;                   ///< verts[k] flattened
  std::vector<std::array<int, 3>> triangles;  ///< the new faces, ring positions
};

/// Every face the simplification made, and how: the history of the parameterisation.
/// Faces 0 .. F-1 are the input's, in order; face f > F-1 is triangle `triangle[f]`
/// of removal `removal[f]`.
struct History {
  std::vector<std::array<int, 3>> faces;  ///< corners (input vertex ids) of every face
  std::vector<int> removal, triangle;     ///< -1 for input faces
  std::vector<RemovalRecord> removals;
  std::vector<int> baseFace;  ///< base face -> its id here
};

/// The point of the input that the parameterisation maps to point `bary` of base face
/// `baseFace`: the removals undone one by one, newest first, each by its exact
/// piecewise-linear inverse. The result's triangle is an input face.
SurfacePoint traceToInput(const History& history, int baseFace, const std::array<double, 3>& bary);

struct Simplification {
  History history;            ///< how the parameterisation was made
  TriMesh base;               ///< the base mesh M^0, vertices renumbered 0..
  std::vector<int> baseOf;    ///< input vertex -> base vertex, or -1 if removed
  std::vector<Param> params;  ///< every input vertex's place on `base`
  /// Feature edges of the base, as keys of their input vertices (features.h).
  std::unordered_set<std::uint64_t> featureEdges;
  int rounds = 0;  ///< rounds of independent removals
  int stage = 0;   ///< the last stage of kStages used (by the mesh, or by one vertex)
  /// Why the base has more faces than asked, if it has: empty otherwise.
  std::string stopReason;
  /// Base vertices that are no input vertex, made by base splits where the pair of faces
  /// held no input vertex to make one (base_flips.h): the k-th is vertex
  /// baseOf.size() + k of history.faces, base vertex `base`, at input point `at` (the
  /// exact map's image of its place).
  struct Added {
    int base = -1;
    SurfacePoint at;
  };
  std::vector<Added> added;
};

/// Every base vertex's id in `s.history.faces`: its input vertex, or baseOf.size() + k
/// for the point s.added[k].
std::vector<int> historyIdsOfBase(const Simplification& s);

/// How simplify() goes about it, beyond its stages.
struct SimplifyOptions {
  /// Refuse a removal whose new faces would cross a live face of the mesh
  /// (RemeshOptions::baseWithoutNewCrossings).
  bool noNewCrossings = false;
  /// A vertex refused under its stage's limits in a round where a more important vertex
  /// is removed after it goes on under the next stage's limits, alone
  /// (RemeshOptions::stages, StageRelaxation); otherwise the stages move for the whole mesh, only
  /// when no vertex can be removed.
  bool stagesPerVertex = false;
  /// Try each removal's retriangulations (the ear clipping, and the fans from each
  /// corner of a ring without a feature line: a fan is the collapse of the removed vertex
  /// into that corner) in order of the error they make at the removed vertex's place,
  /// measured by the quadric of the input's planes it stands for (quadric.h: its own
  /// faces', and a share of those of the vertices removed into its ring before it);
  /// otherwise the ear clipping first, then the fans from the corners of lowest valence
  /// (RemeshOptions::retriangulateByError).
  bool retriangulateByError = false;
  /// Where over 0, a new face may have a smallest angle under its stage's flatAngle, down
  /// to kSkinnyFloor degrees, if every input point it holds lies within this fraction of
  /// its width (its shortest altitude) of its plane: a sliver along a direction in which
  /// the surface does not bend (a CAD model's flat sides and the axes of its cylinders)
  /// stays as close to the input as a fat face does, while one across a bend does not
  /// (RemeshOptions::skinnyWhereFlat).
  double skinnyWhereFlat = 0;
  /// Order each round's removals by the error they make, as a quadric simplifier orders
  /// its collapses, measured: each candidate's removal is planned, and its error is how
  /// much farther apart the input and the mesh come, as area-weighted sums of squared
  /// distances both ways (every input point the removal moves against its new place on
  /// the mesh, after minus before; points of the new faces against the old faces under
  /// them in the flattening). Each removal keeps the least such error of its certified
  /// retriangulations, and a round goes no further down its order than the removals it
  /// needs, so that the dearest do not go for want of cheap ones the round's independence
  /// keeps out. Ties (folds of the input, first) broken by the default priority;
  /// otherwise by one-ring area and curvature, as MAPS does (RemeshOptions::orderByError).
  /// Far slower than MAPS's order (the head's 16,098-face base from its 32,768 faces:
  /// about 30 s against 1 s in a probe, docs/LOD.md).
  bool orderByError = false;
  /// The input's crossing pairs (findSelfIntersections), where the caller has them
  /// already (remesh() finds them once for every simplification and clean-up); found
  /// here otherwise. Read under noNewCrossings only.
  const CrossingPairs* inputCrossings = nullptr;
};

/// The smallest angle, in degrees, of a new face that SimplifyOptions::skinnyWhereFlat
/// lets through.
constexpr double kSkinnyFloor = 1;

/// Simplifies a valid mesh to at most `targetFaces` faces, or as far as the stages
/// allow.
Simplification simplify(const TriMesh& input, const Features& features, int targetFaces,
                        const Progress& progress = {},
                        const std::vector<StageLimits>& stages = kStages,
                        const SimplifyOptions& options = {});

}  // namespace osdmra::remeshing
