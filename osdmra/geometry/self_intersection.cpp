#include "osdmra/geometry/self_intersection.h"

#include <Eigen/Geometry>
#include <algorithm>

#include "osdmra/base/detail/parallel.h"
#include "osdmra/geometry/distance.h"

namespace osdmra {

namespace {

using Vec3 = Eigen::Vector3d;

// Whether segment [p, q] meets triangle (a, b, c) (Moller and Trumbore's ray test
// cut to the segment). `eps` is relative: barycentric and segment parameters within
// it of the edge count as inside.
bool segmentMeetsTriangle(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b,
                          const Vec3& c) {
  constexpr double eps = 1e-12;
  const Vec3 d = q - p, e1 = b - a, e2 = c - a;
  const Vec3 h = d.cross(e2);
  const double det = e1.dot(h);
  // Parallel (or degenerate): a segment in the triangle's plane is a coplanar case,
  // not detected here.
  if (std::abs(det) <= eps * d.norm() * e1.norm() * e2.norm()) return false;
  const double inv = 1.0 / det;
  const Vec3 s = p - a;
  const double u = inv * s.dot(h);
  if (u < -eps || u > 1 + eps) return false;
  const Vec3 r = s.cross(e1);
  const double v = inv * d.dot(r);
  if (v < -eps || u + v > 1 + eps) return false;
  const double t = inv * e2.dot(r);
  return t >= -eps && t <= 1 + eps;
}

}  // namespace

bool trianglesMeet(const Points& V, const std::array<int, 3>& f, const std::array<int, 3>& g) {
  int shared = 0, sf = -1, sg = -1;  // common corners, and where they are in f and g
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (f[i] == g[j]) {
        ++shared;
        sf = i;
        sg = j;
      }
  if (shared >= 2) return false;
  auto at = [&](int v) -> Vec3 { return V.row(v).transpose(); };
  const Vec3 a = at(f[0]), b = at(f[1]), c = at(f[2]), x = at(g[0]), y = at(g[1]), z = at(g[2]);
  if (shared == 1)  // only the edges away from the common corner can cross the other
    return segmentMeetsTriangle(at(f[(sf + 1) % 3]), at(f[(sf + 2) % 3]), x, y, z) ||
           segmentMeetsTriangle(at(g[(sg + 1) % 3]), at(g[(sg + 2) % 3]), a, b, c);
  return segmentMeetsTriangle(a, b, x, y, z) || segmentMeetsTriangle(b, c, x, y, z) ||
         segmentMeetsTriangle(c, a, x, y, z) || segmentMeetsTriangle(x, y, a, b, c) ||
         segmentMeetsTriangle(y, z, a, b, c) || segmentMeetsTriangle(z, x, a, b, c);
}

SelfIntersections findSelfIntersections(const TriMesh& mesh, int maxListed) {
  const TriangleBvh bvh(mesh);
  const int nf = static_cast<int>(mesh.F.rows());
  auto corner = [&](int f, int k) -> Vec3 { return mesh.V.row(mesh.F(f, k)).transpose(); };
  auto meet = [&](int f, int g) {
    return trianglesMeet(mesh.V, {mesh.F(f, 0), mesh.F(f, 1), mesh.F(f, 2)},
                         {mesh.F(g, 0), mesh.F(g, 1), mesh.F(g, 2)});
  };
  const int chunks = numChunks(nf, 1 << 12);
  std::vector<std::vector<std::array<int, 2>>> found(chunks);
  std::vector<long long> counts(chunks, 0);
  forChunks(nf, chunks, [&](int chunk, int begin, int end) {
    std::vector<int> near;
    for (int f = begin; f < end; ++f) {
      const Vec3 a = corner(f, 0), b = corner(f, 1), c = corner(f, 2);
      near.clear();
      bvh.facesInBox(a.cwiseMin(b).cwiseMin(c), a.cwiseMax(b).cwiseMax(c), near);
      std::sort(near.begin(), near.end());
      for (int g : near) {
        if (g <= f || !meet(f, g)) continue;
        ++counts[chunk];
        if (static_cast<int>(found[chunk].size()) < maxListed) found[chunk].push_back({f, g});
      }
    }
  });
  SelfIntersections out;
  for (int c = 0; c < chunks; ++c) {
    out.count += counts[c];
    for (const auto& p : found[c])
      if (static_cast<int>(out.pairs.size()) < maxListed) out.pairs.push_back(p);
  }
  return out;
}

std::vector<std::array<int, 2>> selfIntersectionsWith(const TriMesh& mesh,
                                                      const std::vector<int>& faces) {
  if (faces.empty()) return {};
  TriMesh subset;
  subset.V = mesh.V;
  subset.F.resize(static_cast<Eigen::Index>(faces.size()), 3);
  std::vector<char> in(static_cast<std::size_t>(mesh.F.rows()), 0);
  for (std::size_t i = 0; i < faces.size(); ++i) {
    subset.F.row(static_cast<Eigen::Index>(i)) = mesh.F.row(faces[i]);
    in[faces[i]] = 1;
  }
  const TriangleBvh bvh(subset);
  const int nf = static_cast<int>(mesh.F.rows());
  const int chunks = numChunks(nf, 1 << 12);
  std::vector<std::vector<std::array<int, 2>>> found(chunks);
  forChunks(nf, chunks, [&](int chunk, int begin, int end) {
    std::vector<int> near;
    for (int f = begin; f < end; ++f) {
      const Vec3 a = mesh.V.row(mesh.F(f, 0)), b = mesh.V.row(mesh.F(f, 1)),
                 c = mesh.V.row(mesh.F(f, 2));
      near.clear();
      bvh.facesInBox(a.cwiseMin(b).cwiseMin(c), a.cwiseMax(b).cwiseMax(c), near);
      for (int i : near) {
        const int g = faces[i];
        // A pair of two faces of the subset is found from both: kept from the first.
        if (g == f || (in[f] && g < f)) continue;
        const int lo = std::min(f, g), hi = std::max(f, g);
        if (trianglesMeet(mesh.V, {mesh.F(lo, 0), mesh.F(lo, 1), mesh.F(lo, 2)},
                          {mesh.F(hi, 0), mesh.F(hi, 1), mesh.F(hi, 2)}))
          found[chunk].push_back({lo, hi});
      }
    }
  });
  std::vector<std::array<int, 2>> out;
  for (const auto& part : found) out.insert(out.end(), part.begin(), part.end());
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

}  // namespace osdmra
