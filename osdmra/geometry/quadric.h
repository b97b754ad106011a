// Garland and Heckbert's quadric error metric (Surface simplification using quadric
// error metrics, 1997): a sum of weighted planes, whose value at a point is the sum of
// the weighted squared distances from the point to them. The remesher's simplification
// measures with it what a removal's retriangulation loses (simplify.h).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "osdmra/mesh/mesh.h"

namespace osdmra {

/// p^T A p + 2 b.p + c: the sum of w (n.p + d)^2 over the planes added.
struct Quadric {
  Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  double c = 0;

  /// Adds the plane through `at` with unit normal n, weighted by w.
  void addPlane(const Eigen::Vector3d& n, const Eigen::Vector3d& at, double w);
  /// Adds s times q's planes.
  void add(const Quadric& q, double s);
  double operator()(const Eigen::Vector3d& p) const { return p.dot(A * p) + 2 * b.dot(p) + c; }
};

/// Per vertex of a valid mesh, the planes of its faces, each weighted by a third of
/// the face's area (a zero-area face adds nothing).
std::vector<Quadric> vertexQuadrics(const TriMesh& mesh);

}  // namespace osdmra
