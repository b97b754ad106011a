#include "osdmra/geometry/quadric.h"

#include <Eigen/Geometry>

namespace osdmra {

void Quadric::addPlane(const Eigen::Vector3d& n, const Eigen::Vector3d& at, double w) {
  const double d = -n.dot(at);
  A += w * n * n.transpose();
  b += w * d * n;
  c += w * d * d;
}

void Quadric::add(const Quadric& q, double s) {
  A += s * q.A;
  b += s * q.b;
  c += s * q.c;
}

std::vector<Quadric> vertexQuadrics(const TriMesh& mesh) {
  std::vector<Quadric> q(static_cast<std::size_t>(mesh.V.rows()));
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) {
    const Eigen::Vector3d a = mesh.V.row(mesh.F(f, 0)), b = mesh.V.row(mesh.F(f, 1)),
                          c = mesh.V.row(mesh.F(f, 2));
    const Eigen::Vector3d n = (b - a).cross(c - a);
    const double area = 0.5 * n.norm();
    if (!(area > 0)) continue;
    for (int k = 0; k < 3; ++k) q[mesh.F(f, k)].addPlane(n.normalized(), a, area / 3);
  }
  return q;
}

}  // namespace osdmra
