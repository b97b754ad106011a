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
#pragma once

#include <string>

#include "osdmra/mra/lod.h"
#include "osdmra/subdivision/hierarchy.h"

namespace osdmra {

enum class Placement {
  Surface,  ///< on the truncated surface (the paper; default)
  Fit,      ///< least-squares fit of the full-resolution surface (see above)
};
const char* placementName(Placement p);
/// Parses "surface" or "fit"; throws Error otherwise.
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
};

/// argmin_X ||L X - target||^2 (column by column), from `start`. L: n_J x n rows of
/// lodInterpolation, target: n_J x 3, start: n x 3. Throws Error on mismatched sizes.
Points fitPositions(const SparseMatrix& L, const Points& target, const Points& start,
                    const FitOptions& options = {});

}  // namespace osdmra
