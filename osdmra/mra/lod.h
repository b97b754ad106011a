// Level of detail: an adaptive, crack-free mesh from the kept wavelet coefficients
// (paper section 4, math.md 5).
//
// A kept coefficient d^j_m sits on an edge of M^j (m is that edge's midpoint in
// M^{j+1}), so the mesh must be refined there: both level-j triangles on the edge
// are split 1-to-4 ("red"). Closure then makes the result a conforming mesh:
//   (i)   a red triangle's parent is red, so the triangle itself is in the mesh;
//   (ii)  the neighbours across a red triangle's edges are in the mesh at its level
//         (their parents are red), so adjacent triangles differ by at most one level
//         along an edge and every frontier edge is split exactly once;
//   (iii) a triangle with red neighbours across two or three edges is red too, so
//         every remaining frontier triangle has exactly one split edge.
// The frontier triangles are split 1-to-2 ("green") from the midpoint of their split
// edge to the opposite corner, which leaves no crack and no T-junction. The red set
// is the least one closed under these rules, so a larger keep mask never gives a
// smaller mesh.
//
// The closure and the output walk are linear in the number of hierarchy triangles
// they touch; beyond that there is one pass over the mask and one zeroed flag per
// face of M^0..M^{J-1} (both smaller than M^J). Connectivity is fetched only for
// levels that hold a split triangle, never for M^J.
#pragma once

#include <utility>
#include <vector>

#include "osdmra/mesh/mesh.h"
#include "osdmra/mra/truncation.h"
#include "osdmra/subdivision/hierarchy.h"

namespace osdmra {

/// An adaptive mesh cut from the hierarchy.
struct LodMesh {
  /// Triangles as vertex indices of M^J. Old vertices keep their index across levels,
  /// so a vertex of any level j is also vertex v of M^J, and positions of the level-J
  /// surface (or limit positions) can be read straight off these indices. Every
  /// triangle keeps the orientation of the base triangle it lies in.
  Faces faces;
  /// The distinct M^J vertex indices used by `faces`, ascending.
  std::vector<int> vertices;
  /// `faces` renumbered into 0..vertices.size()-1 (vertex k is M^J vertex vertices[k]),
  /// ready to pair with positions gathered through `vertices`.
  Faces compactFaces;
  /// Level of the hierarchy triangle each face comes from: the face itself, or the
  /// triangle that a green split halved.
  std::vector<int> faceLevel;
  /// Index in M^faceLevel of that hierarchy triangle (the two halves of a green split
  /// share it, and come one after the other: (a, m, o) then (m, b, o), m the midpoint
  /// of the split edge (a, b)).
  std::vector<int> faceOrigin;
  /// Faces that are whole hierarchy triangles (children of red splits, or unsplit
  /// base triangles).
  int redTriangles = 0;
  /// Faces that are halves of a green (1-to-2) split; red + green = faces.rows().
  int greenTriangles = 0;
};

/// The level-of-detail mesh for the coefficients kept in `keep` (keep[j][e] keeps the
/// coefficient of new vertex n_j + e of M^{j+1}). Every kept coefficient's vertex is a
/// vertex of the result. Nothing kept gives the base mesh; everything kept gives M^J
/// in canonical face order. Throws Error when the mask does not fit the hierarchy.
LodMesh extractLod(const Hierarchy& h, const KeepMask& keep);

/// The largest keep mask with the same mesh as `keep`: it adds every coefficient whose
/// edge's faces the closure of `keep` splits anyway. Their vertices are in the mesh
/// already, so keeping them costs no triangle and moves those vertices onto a closer
/// truncated surface.
KeepMask saturate(const Hierarchy& h, const KeepMask& keep);

/// extractLod(h, saturate(h, keep)), with `saturated` set to saturate(h, keep), from one
/// closure: the free coefficients split no face that the closure of `keep` leaves
/// whole, so both masks have the same closure and the same mesh.
LodMesh extractSaturated(const Hierarchy& h, const KeepMask& keep, KeepMask& saturated);

/// The triangle count of extractLod for every prefix of `order` at once: entry k is
/// the count when exactly the first k coefficients (level j, index e within level j's
/// new vertices) are kept, k = 0..order.size(). Costs about one full-resolution
/// extraction, after which a triangle budget is a binary search (counts never
/// decrease with k: the meshes of nested masks are nested).
std::vector<long long> lodTriangleCounts(const Hierarchy& h,
                                         const std::vector<std::pair<int, int>>& order);

}  // namespace osdmra
