// Placement: where a level of detail's vertices go.
//
// The paper puts them on the truncated surface at their parameter points (Surface).
// Fit moves them, with the mesh fixed, to the least-squares fit of the full-resolution
// surface: the level-of-detail mesh is a piecewise linear function over the base
// domain (each face a hierarchy triangle or half of one), its value at every level-J
// vertex's parameter point is a barycentric combination of its vertices (rows of
// lodInterpolation), and the fit minimises the sum over the level-J vertices of the
// squared distance between that value and the full-resolution surface there (the
// input's positions, or for Loop their limit points). Each level-J vertex stands for
// the same parametric area, so this is a discrete parametric L2 projection onto the
// level of detail's own piecewise linear space, which the truncated surface's samples
// only approximate. The normal equations are sparse (a vertex couples with the
// vertices of the faces around it) and are solved by conjugate gradients started
// from the truncated surface's positions: nothing dense, work linear in M^J per
// iteration.
//
// Closest goes on from the fit to the full-resolution surface itself. The parametric
// fit also pays for sliding along the surface (a level-J vertex's parameter point is not
// where the full surface is nearest the level of detail), which a geometric distance
// does not count. Closest matches the two surfaces both ways, each level-J point L_i X
// to its closest point on the full surface and each full vertex (and area samples, when
// matched to another surface: ClosestTarget) to its closest point on the level of
// detail, and takes Gauss-Newton steps of point-to-plane matching (the squared
// distances to the tangent planes at the matches, plus a small weight on sliding along
// the full surface, without which a flat region lets vertices slide freely), the mesh
// fixed, a few rounds. By construction no face of the level of detail turns over
// against the fit's (a vertex whose move would turn one stays), and a round that does
// not bring the surfaces closer ends the rounds. Matching one way only (the level-J
// points) left the full surface's far side uncovered: the head's Hausdorff error rose,
// and on a rough test surface the sampled distance did.
#pragma once

#include <string>
#include <vector>

#include "osdmra/geometry/distance.h"
#include "osdmra/mra/lod.h"
#include "osdmra/subdivision/hierarchy.h"

namespace osdmra {

enum class Placement {
  Surface,  ///< on the truncated surface (the paper; default)
  Fit,      ///< least-squares fit of the full-resolution surface (see above)
  Closest,  ///< Fit, then fitted to the full surface's closest points (see above)
  /// Closest, made once per level of the hierarchy on its uniform mesh M^j and looked
  /// up at extraction: each vertex of a level of detail takes the mean, over its faces,
  /// of its positions in their levels' fits, so an extraction costs what Surface's does.
  Levels,
};
const char* placementName(Placement p);
/// Parses "surface", "fit", "closest" or "levels"; throws Error otherwise.
Placement parsePlacement(const std::string& name);

/// Row v (a vertex of M^J): the weights, over the compact vertices of `lod`
/// (lod.vertices), of the level of detail's point at v's parameter point: barycentric
/// coordinates in the face that contains it (a vertex on an edge takes either face;
/// both give the same point). Each row sums to 1; a vertex of the mesh has weight 1
/// on itself.
SparseMatrix lodInterpolation(const Hierarchy& h, const LodMesh& lod);

struct FitOptions {
  /// Conjugate-gradient iterations at most. From the truncated surface's positions a
  /// few tens reach the fit to about 1e-6 relative residual on the meshes measured
  /// (docs/LOD.md); the residual left is reported, not an error.
  int iterations = 40;
  /// Relative residual of the normal equations at which to stop.
  double tolerance = 1e-7;
  /// Placement::Closest: rounds of matching and Gauss-Newton steps after the fit (each
  /// slides the vertices a little along the surface, the tangent weight holding them
  /// back). At 4,054 triangles, 1 / 3 / 5 rounds took the sampled RMS from the fit's
  /// 5.05e-4 to 3.85e-4 / 3.20e-4 / 2.95e-4 on spot's J = 5 remesh (about 0.3 s a round
  /// on 307,200 faces), and from 6.11e-4 to 4.63e-4 / 3.77e-4 / 3.62e-4 on the bundled
  /// head. On six scans remeshed by `lod --remesh` at 1/3/10% of their triangles
  /// (docs/LOD.md), 6 and 12 rounds lowered the RMS to the scan by 5-12% and 10-20%
  /// against 3 (the conjugate gradients had converged: 400 iterations changed nothing).
  int closestRounds = 8;
  /// Placement::Closest: weight of sliding along the full surface, against 1 across it.
  /// On spot at 4,054 triangles 0.001 / 0.01 / 0.1 gave 2.92e-4 / 3.20e-4 / 3.85e-4;
  /// 0.001 was worse than 0.01 on the head and the bunny (one-way matching).
  double tangentWeight = 0.01;
};

/// argmin_X ||L X - target||^2 (column by column), from `start`. L: n_J x n rows of
/// lodInterpolation, target: n_J x 3, start: n x 3. Throws Error on mismatched sizes.
Points fitPositions(const SparseMatrix& L, const Points& target, const Points& start,
                    const FitOptions& options = {});

/// `to`, except that the vertices of every pair of faces that crosses where it did not
/// cross at `from` (findSelfIntersections) move only half as far towards `to`, then a
/// quarter, ..., and at last stay at `from`, until no new pair crosses: that holds by
/// construction once every vertex is back. Fit and Closest move
/// vertices off the truncated surface to bring the faces closer to the full one, and
/// on thin parts that moved faces through each other (armadillo's level of detail at
/// 854 triangles: none crossing on the truncated surface, 3 pairs after the fit, 6
/// after Closest's rounds); both go through this (each round of Closest from the
/// last). Levels does not: it looks positions up without the truncated surface, which
/// is what makes it fast, and can cross (22 pairs there).
Points withoutNewCrossings(const Faces& F, const Points& from, const Points& to);

/// The surface Placement::Closest matches levels of detail to, with what every fit to
/// it reuses: its triangle hierarchy, which of its halfedges (3f + k, from corner k to
/// corner k + 1 of face f) lie on its boundary, and the points of it matched to the
/// level of detail. `mesh` must outlive it.
struct ClosestTarget {
  /// `samples` > 0 adds as many area-uniform points of `mesh` (samplePoints, seed 1) to
  /// its vertices. A surface other than the one the level of detail refines (the input
  /// a remeshing was made from) has its vertices where its maker put them, crowded in
  /// places (a CAD model's along its curves, a scan's where it was decimated least):
  /// matched at its vertices alone, the level of detail is pulled to the crowds and
  /// left loose between them, where the distance it is measured by samples as densely
  /// (docs/LOD.md: lod_scans RMS 1.037x matched at the vertices, 0.98x with samples).
  explicit ClosestTarget(const TriMesh& mesh, int samples = 0);
  const TriMesh& mesh;
  TriangleBvh bvh;
  std::vector<char> boundary;
  Points points;  ///< matched to the level of detail: the vertices, then the samples
};

/// Placement::Closest's rounds from `start` (the fit's positions) for the level of
/// detail with faces `faces` (indices of L's columns) towards `target`: see the file
/// comment. Throws Error on mismatched sizes.
Points fitToClosestPoints(const SparseMatrix& L, const Faces& faces, const ClosestTarget& target,
                          const Points& start, const FitOptions& options = {});

}  // namespace osdmra
