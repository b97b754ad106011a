#include "osdmra/geometry/surface_walk.h"

#include <Eigen/Geometry>
#include <algorithm>

#include "osdmra/geometry/normals.h"

namespace osdmra {

bool barycentricIn(const TriMesh& mesh, int t, const Eigen::Vector3d& x,
                   std::array<double, 3>& bary) {
  const Eigen::Vector3d a = mesh.V.row(mesh.F(t, 0)).transpose(),
                        e1 = mesh.V.row(mesh.F(t, 1)).transpose() - a,
                        e2 = mesh.V.row(mesh.F(t, 2)).transpose() - a, d = x - a;
  const double d11 = e1.dot(e1), d12 = e1.dot(e2), d22 = e2.dot(e2), det = d11 * d22 - d12 * d12;
  if (!(det > 0)) return false;
  const double u = (d22 * d.dot(e1) - d12 * d.dot(e2)) / det;
  const double w = (d11 * d.dot(e2) - d12 * d.dot(e1)) / det;
  bary = {1 - u - w, u, w};
  return true;
}

bool facesAlong(const TriMesh& mesh, const Connectivity& conn, const SurfacePoint& p,
                const Eigen::Vector3d& n) {
  if (p.triangle < 0 || n.dot(faceNormal(mesh, p.triangle)) > 0) return true;
  int zeros = 0, zero = -1, inside = -1;
  for (int k = 0; k < 3; ++k) {
    if (p.bary[k] > 0) {
      inside = k;
    } else {
      ++zeros;
      zero = k;
    }
  }
  if (zeros == 1) {  // on the edge opposite corner `zero`: the face across it too
    const int h = conn.twin(3 * p.triangle + (zero + 1) % 3);
    return h >= 0 && n.dot(faceNormal(mesh, h / 3)) > 0;
  }
  if (zeros == 2)  // at corner `inside`: every face around it
    for (int h : conn.fan(mesh.F(p.triangle, inside)))
      if (n.dot(faceNormal(mesh, h / 3)) > 0) return true;
  return false;
}

bool foldedAgainst(const TriMesh& mesh, const Connectivity& conn,
                   const std::array<Eigen::Vector3d, 3>& x, const std::array<SurfacePoint, 3>& at,
                   double tinyArea, bool& degenerate) {
  const Eigen::Vector3d n = (x[1] - x[0]).cross(x[2] - x[0]);
  degenerate = n.norm() <= tinyArea;
  if (degenerate) return true;
  for (const SurfacePoint& p : at)
    if (facesAlong(mesh, conn, p, n)) return false;
  return true;
}

SurfaceWalker::SurfaceWalker(const TriMesh& mesh, const std::vector<std::array<int, 2>>& stops)
    : mesh_(mesh), conn_(mesh.F, static_cast<int>(mesh.V.rows())), stop_(conn_.numEdges(), 0) {
  for (const auto& [a, b] : stops) {
    const int e = conn_.findEdge(a, b);
    if (e >= 0) stop_[e] = 1;
  }
}

Eigen::Vector3d SurfaceWalker::corner(int t, int k) const {
  return mesh_.V.row(mesh_.F(t, k)).transpose();
}

Eigen::Vector3d SurfaceWalker::position(const SurfacePoint& p) const {
  return p.bary[0] * corner(p.triangle, 0) + p.bary[1] * corner(p.triangle, 1) +
         p.bary[2] * corner(p.triangle, 2);
}

SurfacePoint SurfaceWalker::walk(SurfacePoint w, Eigen::Vector3d d) const {
  if (w.triangle < 0) return w;
  const double tiny = 1e-15 * (d.norm() + (corner(w.triangle, 1) - corner(w.triangle, 0)).norm());
  for (int step = 0; step < kMaxSteps; ++step) {
    const int t = w.triangle;
    const Eigen::Vector3d a = corner(t, 0), b = corner(t, 1), c = corner(t, 2);
    const Eigen::Vector3d n = (b - a).cross(c - a).normalized();
    d -= n * n.dot(d);
    std::array<double, 3> to;
    if (!(d.norm() > tiny) || !barycentricIn(mesh_, t, position(w) + d, to)) break;
    if (*std::min_element(to.begin(), to.end()) >= 0) {
      w.bary = to;
      break;
    }
    // It leaves through the edge opposite corner k, the first the segment crosses.
    double s = 2;
    int k = -1;
    for (int i = 0; i < 3; ++i)
      if (to[i] < 0 && w.bary[i] - to[i] > 0) {
        const double si = std::max(0.0, w.bary[i] / (w.bary[i] - to[i]));
        if (si < s) s = si, k = i;
      }
    if (k < 0) break;
    std::array<double, 3> exit;
    for (int i = 0; i < 3; ++i) exit[i] = w.bary[i] + s * (to[i] - w.bary[i]);
    exit[k] = 0;
    w.bary = clampedBarycentric(exit);
    const int ia = (k + 1) % 3, ib = (k + 2) % 3, h = 3 * t + ia;
    const int twin = conn_.twin(h);
    if (twin < 0 || stop_[conn_.edge(h)]) break;
    // The rest of the displacement, unfolded into the next face's plane.
    const int next = twin / 3, ea = mesh_.F(t, ia), eb = mesh_.F(t, ib);
    const Eigen::Vector3d rest = (1 - s) * d, e = (corner(t, ib) - corner(t, ia)).normalized();
    int o = 0;
    while (mesh_.F(next, o) == ea || mesh_.F(next, o) == eb) ++o;
    Eigen::Vector3d inward = corner(next, o) - corner(t, ia);
    inward = (inward - e * e.dot(inward)).normalized();
    d = e * e.dot(rest) + inward * (rest - e * e.dot(rest)).norm();
    std::array<double, 3> on{0, 0, 0};
    for (int i = 0; i < 3; ++i) {
      if (mesh_.F(next, i) == ea) on[i] = w.bary[ia];
      if (mesh_.F(next, i) == eb) on[i] = w.bary[ib];
    }
    w = {next, clampedBarycentric(on)};
  }
  return w;
}

}  // namespace osdmra
