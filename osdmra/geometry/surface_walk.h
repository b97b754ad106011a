// Points of a triangle mesh and straight walks between them along its surface. The
// remesher moves grid points this way (remesh.h, clean-up): a walk stays on the
// surface and crosses creases and concave parts without jumping to another sheet,
// as a projection onto the nearest point would.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <vector>

#include "osdmra/mesh/connectivity.h"
#include "osdmra/mesh/mesh.h"

namespace osdmra {

/// A point of a triangle mesh: a face and barycentric coordinates over its corners
/// (face -1: none).
struct SurfacePoint {
  int triangle = -1;
  std::array<double, 3> bary{};
};

/// Barycentric coordinates clamped into the triangle (negative ones to 0, the rest
/// rescaled to sum 1; the centroid if none is positive). Inline: the exact map's
/// tracing calls it at every removal it undoes for every grid point.
inline std::array<double, 3> clampedBarycentric(std::array<double, 3> b) {
  double sum = 0;
  for (double& x : b) sum += x = std::max(x, 0.0);
  if (sum <= 0) return {1.0 / 3, 1.0 / 3, 1.0 / 3};
  for (double& x : b) x /= sum;
  return b;
}

/// Barycentric coordinates, in face t of `mesh`, of the projection of x onto the
/// face's plane; false if the face has no area.
bool barycentricIn(const TriMesh& mesh, int t, const Eigen::Vector3d& x,
                   std::array<double, 3>& bary);

/// Whether direction n faces along `mesh` at point p: n points to the side of p's face
/// (positive dot product with its normal) or, where p lies on an edge or at a vertex,
/// of a face that shares that edge or vertex. A triangle whose normal faces along the
/// mesh under none of its corners is turned over against it, unambiguously even where
/// the mesh is thin (the remesher counts flipped triangles so). On a sharp edge a point
/// belongs to both sides: a triangle flat on one side whose corners all lie on the edge
/// would be counted flipped if they were sampled in the other side's faces (a
/// cylinder's cap, at the corner of a base face with two edges on its rim).
/// True if p has no face.
bool facesAlong(const TriMesh& mesh, const Connectivity& conn, const SurfacePoint& p,
                const Eigen::Vector3d& n);

/// The area (norm of the edges' cross product) at or under which a triangle counts as of
/// none, for a mesh of bounding-box diagonal `diagonal`.
inline double tinyAreaFor(double diagonal) {
  return 1e-14 * diagonal * diagonal;
}

/// Whether the triangle with corners `x`, sampled at `at` on `mesh`, is folded against it:
/// of no area (at most `tinyArea`: then `degenerate` is set) or facing along the mesh
/// (facesAlong) under none of its corners.
bool foldedAgainst(const TriMesh& mesh, const Connectivity& conn,
                   const std::array<Eigen::Vector3d, 3>& x, const std::array<SurfacePoint, 3>& at,
                   double tinyArea, bool& degenerate);

/// Walks on a triangle mesh (which must outlive the walker). A walk from point p
/// along displacement d goes straight: d is taken in the plane of the face it is in,
/// and where it leaves the face its remainder is unfolded into the next face (same
/// length, same angle to the shared edge), so that on a developable strip it follows
/// the geodesic. It stops early at the mesh's boundary, at a `stop` edge, or after
/// crossing kMaxSteps faces.
class SurfaceWalker {
 public:
  /// `stops`: edges (pairs of vertex indices) a walk does not cross, such as feature
  /// lines; pairs that are not edges of the mesh are ignored.
  SurfaceWalker(const TriMesh& mesh, const std::vector<std::array<int, 2>>& stops = {});

  /// Where a walk from `from` along `d` ends (on the edge where it stopped, if it did).
  SurfacePoint walk(SurfacePoint from, Eigen::Vector3d d) const;
  /// The position of a point.
  Eigen::Vector3d position(const SurfacePoint& p) const;
  /// The mesh's connectivity, built for the walks (for callers that need it too).
  const Connectivity& connectivity() const { return conn_; }

  static constexpr int kMaxSteps = 256;

 private:
  Eigen::Vector3d corner(int t, int k) const;
  const TriMesh& mesh_;
  Connectivity conn_;
  std::vector<char> stop_;  // per edge of conn_
};

}  // namespace osdmra
