// One vertex removal of the simplification (step 1 of remesh.h), as plain geometry:
// the one-ring laid flat, its retriangulation, and the certificate that the map from
// the old faces to the new ones is a bijection (MAPS, Lee et al. 1998, section 3.2).
//
// The old faces around the removed vertex v are the fan (origin, p_k, p_k+1) of the
// flattened ring; the new faces triangulate the same polygon. When every fan triangle
// and every new triangle is positively oriented the polygon is star-shaped about the
// origin (the fan's angles sum to 2 pi, or pi per side of a boundary or feature line),
// both triangulations tile it exactly once, and a point's barycentric place in an old
// face goes to exactly one place in the new ones: the parameterisation stays a
// bijection. A removal without that certificate is refused, not repaired.
#pragma once

#include <array>
#include <vector>

#include "osdmra/remesh/planar.h"

namespace osdmra::remeshing {

/// A vertex's one-ring: verts[k] counter-clockwise, face k = (v, verts[k], verts[k+1]).
/// A closed ring repeats verts[0] as verts[m] (m faces); a boundary ring has m + 1
/// distinct vertices.
struct Ring {
  std::vector<int> verts, faces;
  bool boundary = false;
  int numFaces() const { return static_cast<int>(faces.size()); }
};

/// The ring laid flat by the z^a map (MAPS eq. 1): angles at v scaled to sum to 2 pi
/// around an interior vertex, pi on a boundary and on each side of a feature line
/// (verts[0] and verts[featureAt] are its feature neighbours); radii |p_k - v|^a.
struct Flattening {
  std::vector<Vec2> points;    ///< ring vertex k at points[k]; v at the origin
  std::vector<double> angles;  ///< the flat angle at the origin of fan triangle k
  double exponent = 1;         ///< a: 2 pi (or pi) over the sum of the 3D angles
};

/// Flattens a ring around `center` from its vertices' positions (m + 1 of them, as in
/// Ring). featureAt = -1 when no feature line runs through v.
Flattening flattenRing(const Vec3& center, const std::vector<Vec3>& ring, bool boundary,
                       int featureAt);

/// The triangulation of the polygon of a ring without a feature line (`numPoints` =
/// m + 1 flat points as in Flattening; closed: corners 0..m-1, on a boundary: 0..m)
/// that fans out from ring position `from`. Whether its triangles are positive is
/// isBijective's to say: a fan is valid exactly when the polygon is star-shaped from
/// that corner. Where the ear clipping's triangulation is refused, a fan may pass.
std::vector<std::array<int, 3>> fanOfRing(int from, int numPoints, bool boundary);

/// Triangulates the flat polygon (two polygons sharing the edge between the feature
/// neighbours when featureAt >= 0) by clipping, each time, the ear whose smallest
/// angle is largest. Triples of ring positions, counter-clockwise; empty when the
/// polygon has no valid ear (it is then not simple).
std::vector<std::array<int, 3>> triangulateRing(const std::vector<Vec2>& points, bool boundary,
                                                int featureAt);

/// The bijectivity certificate: every fan triangle and every new triangle is
/// positively oriented with a relative margin (a sine of at least `margin`).
bool isBijective(const Flattening& flat, const std::vector<std::array<int, 3>>& triangles,
                 bool boundary, double margin = 1e-9);

/// The new triangle holding the flat point p, with p's barycentric coordinates in it
/// (clamped to the triangle); -1 when p lies outside all of them beyond rounding.
int locateInTriangles(const Vec2& p, const std::vector<Vec2>& points,
                      const std::vector<std::array<int, 3>>& triangles,
                      std::array<double, 3>& bary);

}  // namespace osdmra::remeshing
