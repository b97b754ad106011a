// Self-intersection of a triangle mesh: pairs of triangles that cross each other
// without being neighbours. A remeshed surface must have none (remesh.h), and a
// user handing osdmra a mesh may want to know.
#pragma once

#include <array>
#include <vector>

#include "osdmra/mesh/mesh.h"

namespace osdmra {

/// Pairs of faces (f, g), f < g, that cross (SelfIntersections::count's rule).
using CrossingPairs = std::vector<std::array<int, 2>>;

struct SelfIntersections {
  /// Pairs of faces (f < g) that meet where they should not: faces with no common
  /// vertex that touch or cross, and faces with one common vertex whose opposite edge
  /// passes through the other (a fold at that vertex). Faces sharing an edge are not
  /// tested (a fold across an edge turns a face over: see Remeshing::flippedTriangles).
  long long count = 0;
  /// The first pairs in (f, g) order (at most `maxListed`).
  CrossingPairs pairs;
};

/// Whether triangles f and g (rows of vertex indices into V) meet where they should
/// not, by the rule of SelfIntersections::count (false when they share an edge).
bool trianglesMeet(const Points& V, const std::array<int, 3>& f, const std::array<int, 3>& g);

/// Tests every pair of faces whose bounding boxes overlap (a bounding volume
/// hierarchy traversed against itself finds them), on all cores. Exact up to
/// rounding: segment-triangle tests with a relative tolerance of 1e-12, so two faces
/// that merely touch at a point may or may not count. Coplanar overlaps of disjoint faces are not
/// detected. Throws Error for a mesh without faces.
SelfIntersections findSelfIntersections(const TriMesh& mesh, int maxListed = 16);

/// Every pair of SelfIntersections::count, sorted (findSelfIntersections without a
/// limit on the pairs listed).
CrossingPairs crossingPairs(const TriMesh& mesh);

/// `given` where a caller has a mesh's crossing pairs already, else crossingPairs(mesh),
/// kept in `found`: the input's pairs are found once and passed down (remesh.h).
const CrossingPairs& crossingPairs(const TriMesh& mesh, const CrossingPairs* given,
                                   CrossingPairs& found);

/// Every pair {f, g} (f < g) of SelfIntersections::count with f or g among `faces`
/// (indices of rows of mesh.F), sorted: what a recount would change after the corners
/// of `faces` moved, at the cost of a bounding volume hierarchy over `faces` alone.
CrossingPairs selfIntersectionsWith(const TriMesh& mesh, const std::vector<int>& faces);

}  // namespace osdmra
