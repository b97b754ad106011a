// Step 0 of remesh.h: a scan's folds taken out of the input before it is simplified.
// A fold (features.h: a triangle facing against its own corners' area-weighted normals)
// is a pleat of the surface, or a sliver turned over onto its neighbours, as scanners and
// decimations leave them. A grid sampled over a pleat cannot follow its layers: its
// triangles cross the layer turned back, or face against it, and the clean-up had to
// repair them afterwards (the camel head's remeshes at J = 5: 36 crossing pairs in a
// pleat 0.2% of the diagonal wide, 169 points moved). Each fold's corners go a short
// way, on the surface, towards their neighbours' centroid, where that leaves fewer folds
// around them and the surface where it was; remesh() measures its distances to the
// input as given.
#pragma once

#include "osdmra/mesh/mesh.h"

namespace osdmra::remeshing {

/// What unfoldInput() did.
struct UnfoldReport {
  int foldCorners = 0;      ///< vertices of folds found (Features::fold)
  int foldCornersLeft = 0;  ///< vertices of folds left
  int movedVertices = 0;
  double largestMove = 0;  ///< the farthest a vertex moved, relative to the diagonal
};

/// A vertex moves at most this fraction of the mean length of its edges.
constexpr double kUnfoldReach = 0.1;
/// The faces around a moved vertex, and those before the move, lie within this fraction
/// of their longest edge of the other (their centroids and edges' midpoints).
constexpr double kUnfoldDeviation = 0.1;

/// Moves each corner of a fold of `mesh` (Features::fold: tips of protrusions are left
/// alone, as are boundary vertices) to the point of the mesh as given nearest a point a
/// quarter, half or all the way to its neighbours' centroid, the first that leaves fewer
/// folds among the faces whose test the move changes, stays within kUnfoldReach and
/// keeps the faces around it within kUnfoldDeviation of where they were; in rounds,
/// until a round moves nothing (at most `maxRounds`). The connectivity is unchanged, and
/// a mesh without folds is left exactly as it is.
UnfoldReport unfoldInput(TriMesh& mesh, int maxRounds = 16);

}  // namespace osdmra::remeshing
