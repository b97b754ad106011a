// Zero-area faces of an input mesh, mended without changing its surface.
//
// CAD exports (STL, and OBJ made from it) triangulate each planar polygon from one of
// its corners, and a polygon with several points along one side then has triangles
// whose three corners lie on one line ("caps"); meshes welded from coincident points
// have triangles with two corners at one place ("needles"). Such a face has no normal:
// it makes no feature edge (a cube's edges are lost), and the remesher's flattening
// of a one-ring through it is degenerate (the sampled grid folds). Both kinds are
// mended exactly, the surface as a set of points unchanged:
//  - a cap (a, b, m) with m on the segment ab: the edge ab is flipped to m d, where
//    d is the far corner of the face across ab, which that splits in two at m; a cap
//    on the boundary (no face across ab) is dropped, its edges am and mb becoming the
//    boundary, when m is interior; a zero-area face alone (no neighbour) is dropped;
//  - a needle: its shortest edge is collapsed (its ends coincide), when the link
//    condition holds and no face around turns over.
// Each change keeps the mesh a manifold of the same genus, boundary loops and
// components (tests/mesh/test_zero_area.cpp).
#pragma once

#include "osdmra/mesh/mesh.h"

namespace osdmra {

/// What removeZeroAreaFaces() did.
struct ZeroAreaRepair {
  int flipped = 0;    ///< caps mended by flipping their long edge
  int dropped = 0;    ///< caps on the boundary dropped
  int collapsed = 0;  ///< needles mended by collapsing their short edge
  int left = 0;       ///< zero-area faces none of these could mend
};

/// A face is of zero area when its height over its longest edge is at most
/// kZeroAreaHeight times that edge (collinear corners, as rounding leaves them).
constexpr double kZeroAreaHeight = 1e-10;

/// True when face f of `mesh` is of zero area (kZeroAreaHeight).
bool isZeroAreaFace(const TriMesh& mesh, int f);

/// Mends the zero-area faces of a valid mesh (validate()) as described above: the caps'
/// flips first, each cap after its neighbour's (a fan's caps along a line in one pass),
/// then rounds until none is left or a round changes nothing. Vertices a collapse leaves
/// unused are removed. Nothing changes when the mesh is not valid.
ZeroAreaRepair removeZeroAreaFaces(TriMesh& mesh);

}  // namespace osdmra
