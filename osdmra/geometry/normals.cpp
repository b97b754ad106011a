#include "osdmra/geometry/normals.h"

#include <Eigen/Geometry>
#include <cmath>

namespace osdmra {

Eigen::Vector3d faceNormal(const TriMesh& mesh, Eigen::Index f) {
  const Eigen::Vector3d a = mesh.V.row(mesh.F(f, 0)), b = mesh.V.row(mesh.F(f, 1)),
                        c = mesh.V.row(mesh.F(f, 2));
  return (b - a).cross(c - a);
}

double faceAngle(const TriMesh& mesh, Eigen::Index f, int i) {
  const Eigen::Vector3d o = mesh.V.row(mesh.F(f, i)).transpose();
  const Eigen::Vector3d u = mesh.V.row(mesh.F(f, (i + 1) % 3)).transpose() - o;
  const Eigen::Vector3d w = mesh.V.row(mesh.F(f, (i + 2) % 3)).transpose() - o;
  return std::atan2(u.cross(w).norm(), u.dot(w));
}

Points vertexNormalSums(const TriMesh& mesh) {
  Points sums = Points::Zero(mesh.V.rows(), 3);
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) {
    const Eigen::RowVector3d n = faceNormal(mesh, f).transpose();
    for (int k = 0; k < 3; ++k) sums.row(mesh.F(f, k)) += n;
  }
  return sums;
}

Points vertexNormals(const TriMesh& mesh) {
  Points N = vertexNormalSums(mesh);
  for (Eigen::Index i = 0; i < N.rows(); ++i) {
    const double length = N.row(i).norm();
    if (length > 0) N.row(i) /= length;
  }
  return N;
}

}  // namespace osdmra
