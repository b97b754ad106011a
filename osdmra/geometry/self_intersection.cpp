#include "osdmra/geometry/self_intersection.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <atomic>
#include <limits>

#include "osdmra/base/detail/parallel.h"
#include "osdmra/geometry/distance.h"

namespace osdmra {

namespace {

using Vec3 = Eigen::Vector3d;

// A triangle for the segment tests: its corners and its plane's (unnormalised) normal.
struct Triangle {
  Vec3 a, b, c, n;
  Triangle(const Vec3& p, const Vec3& q, const Vec3& r)
      : a(p), b(q), c(r), n((q - p).cross(r - p)) {}
};

// Whether segment [p, q] meets triangle t (Moller and Trumbore's ray test cut to the
// segment). `eps` is relative: barycentric and segment parameters within it of the
// edge count as inside.
bool segmentMeetsTriangle(const Vec3& p, const Vec3& q, const Triangle& t) {
  // Both ends on one side of the plane, farther from it than a millionth of the
  // segment's reach across it (1e-9 of its length), give a segment parameter outside
  // [-eps, 1 + eps] by far more than rounding: the ray test below would reject it, and
  // most pairs of a mesh's nearby faces end here, at two dot products.
  const double dp = t.n.dot(p - t.a), dq = t.n.dot(q - t.a);
  if (dp * dq > 0 && std::min(dp * dp, dq * dq) > 1e-18 * t.n.squaredNorm() * (q - p).squaredNorm())
    return false;
  constexpr double eps = 1e-12;
  const Vec3 d = q - p, e1 = t.b - t.a, e2 = t.c - t.a;
  const Vec3 h = d.cross(e2);
  const double det = e1.dot(h);
  // Parallel (or degenerate): a segment in the triangle's plane is a coplanar case,
  // not detected here.
  if (std::abs(det) <= eps * d.norm() * e1.norm() * e2.norm()) return false;
  const double inv = 1.0 / det;
  const Vec3 s = p - t.a;
  const double u = inv * s.dot(h);
  if (u < -eps || u > 1 + eps) return false;
  const Vec3 r = s.cross(e1);
  const double v = inv * d.dot(r);
  if (v < -eps || u + v > 1 + eps) return false;
  const double param = inv * e2.dot(r);
  return param >= -eps && param <= 1 + eps;
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
  const Triangle tf(a, b, c), tg(x, y, z);
  if (shared == 1)  // only the edges away from the common corner can cross the other
    return segmentMeetsTriangle(at(f[(sf + 1) % 3]), at(f[(sf + 2) % 3]), tg) ||
           segmentMeetsTriangle(at(g[(sg + 1) % 3]), at(g[(sg + 2) % 3]), tf);
  return segmentMeetsTriangle(a, b, tg) || segmentMeetsTriangle(b, c, tg) ||
         segmentMeetsTriangle(c, a, tg) || segmentMeetsTriangle(x, y, tf) ||
         segmentMeetsTriangle(y, z, tf) || segmentMeetsTriangle(z, x, tf);
}

namespace {

bool facesMeet(const TriMesh& mesh, int f, int g) {
  return trianglesMeet(mesh.V, {mesh.F(f, 0), mesh.F(f, 1), mesh.F(f, 2)},
                       {mesh.F(g, 0), mesh.F(g, 1), mesh.F(g, 2)});
}

// For every face f of `mesh`, on all cores in `chunks` even chunks: visit(chunk, f, g)
// for each face g = faceOf(i) of `bvh`'s triangles i whose box meets f's, in
// increasing i.
template <class FaceOf, class Visit>
void forFacesWithMeetingBoxes(const TriMesh& mesh, const TriangleBvh& bvh, int chunks,
                              FaceOf faceOf, Visit visit) {
  forChunks(static_cast<int>(mesh.F.rows()), chunks, [&](int chunk, int begin, int end) {
    std::vector<int> near;
    for (int f = begin; f < end; ++f) {
      const Vec3 a = mesh.V.row(mesh.F(f, 0)), b = mesh.V.row(mesh.F(f, 1)),
                 c = mesh.V.row(mesh.F(f, 2));
      near.clear();
      bvh.facesInBox(a.cwiseMin(b).cwiseMin(c), a.cwiseMax(b).cwiseMax(c), near);
      std::sort(near.begin(), near.end());
      for (int i : near) visit(chunk, f, faceOf(i));
    }
  });
}

}  // namespace

SelfIntersections findSelfIntersections(const TriMesh& mesh, int maxListed) {
  const TriangleBvh bvh(mesh);
  const int chunks = numChunks(mesh.F.rows(), 1 << 12);
  // Threads take the hierarchy's pairs of subtrees in turn (their work varies by
  // orders of magnitude); what each finds is kept to the smallest maxListed pairs, and
  // sorted at the end, so the result does not depend on who took what.
  const std::vector<std::array<int, 2>> tasks = bvh.selfPairTasks(chunks > 1 ? 64 * chunks : 1);
  std::atomic<int> nextTask{0};
  std::vector<std::vector<std::array<int, 2>>> found(chunks);
  std::vector<long long> counts(chunks, 0);
  const std::size_t kept = static_cast<std::size_t>(std::max(maxListed, 0));
  forChunks(chunks, chunks, [&](int chunk, int, int) {
    std::vector<std::array<int, 2>>& mine = found[chunk];
    for (int t = nextTask++; t < static_cast<int>(tasks.size()); t = nextTask++) {
      bvh.forBoxesMeeting(tasks[t], [&](int f, int g) {
        if (!facesMeet(mesh, f, g)) return;
        ++counts[chunk];
        if (kept == 0) return;
        mine.push_back({f, g});
        if (mine.size() >= 2 * kept + 1024) {
          std::nth_element(mine.begin(), mine.begin() + static_cast<std::ptrdiff_t>(kept),
                           mine.end());
          mine.resize(kept);
        }
      });
    }
  });
  SelfIntersections out;
  for (int c = 0; c < chunks; ++c) {
    out.count += counts[c];
    out.pairs.insert(out.pairs.end(), found[c].begin(), found[c].end());
  }
  std::sort(out.pairs.begin(), out.pairs.end());
  if (out.pairs.size() > kept) out.pairs.resize(kept);
  return out;
}

CrossingPairs crossingPairs(const TriMesh& mesh) {
  return findSelfIntersections(mesh, std::numeric_limits<int>::max()).pairs;
}

const CrossingPairs& crossingPairs(const TriMesh& mesh, const CrossingPairs* given,
                                   CrossingPairs& found) {
  if (given) return *given;
  found = crossingPairs(mesh);
  return found;
}

CrossingPairs selfIntersectionsWith(const TriMesh& mesh, const std::vector<int>& faces) {
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
  const int chunks = numChunks(mesh.F.rows(), 1 << 12);
  std::vector<std::vector<std::array<int, 2>>> found(chunks);
  forFacesWithMeetingBoxes(
      mesh, bvh, chunks, [&](int i) { return faces[i]; },
      [&](int chunk, int f, int g) {
        // A pair of two faces of the subset is found from both: kept from the first.
        if (g == f || (in[f] && g < f)) return;
        const int lo = std::min(f, g), hi = std::max(f, g);
        if (facesMeet(mesh, lo, hi)) found[chunk].push_back({lo, hi});
      });
  std::vector<std::array<int, 2>> out;
  for (const auto& part : found) out.insert(out.end(), part.begin(), part.end());
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace osdmra
