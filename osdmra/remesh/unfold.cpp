#include "osdmra/remesh/unfold.h"

#include <algorithm>
#include <array>
#include <limits>
#include <vector>

#include "osdmra/geometry/distance.h"
#include "osdmra/geometry/normals.h"
#include "osdmra/mesh/connectivity.h"
#include "osdmra/remesh/features.h"
#include "osdmra/remesh/planar.h"

namespace osdmra::remeshing {

namespace {

int count(const std::vector<char>& marks) {
  return static_cast<int>(std::count(marks.begin(), marks.end(), 1));
}

// The folds among the faces whose test a move of v changes: those with a corner at v or
// at one of its neighbours (their corners' normals sum faces around v).
int foldsAround(const TriMesh& m, const Connectivity& c, int v) {
  auto normalSum = [&](int u) {
    Vec3 n = Vec3::Zero();
    for (int h : c.fan(u)) n += faceNormal(m, h / 3);
    return n;
  };
  std::vector<int> faces;
  for (int h : c.fan(v)) faces.push_back(h / 3);
  for (int u : c.ring(v))
    for (int h : c.fan(u)) faces.push_back(h / 3);
  std::sort(faces.begin(), faces.end());
  faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
  int folds = 0;
  for (int f : faces) {
    Vec3 corners = Vec3::Zero();
    for (int k = 0; k < 3; ++k) corners += normalSum(m.F(f, k));
    folds += facesAgainst(faceNormal(m, f), corners);
  }
  return folds;
}

using Triangle = std::array<Vec3, 3>;

// The faces around v, with v at `at`.
std::vector<Triangle> starOf(const TriMesh& m, const Connectivity& c, int v, const Vec3& at) {
  std::vector<Triangle> star;
  for (int h : c.fan(v)) {
    Triangle t;
    for (int k = 0; k < 3; ++k) t[k] = m.F(h / 3, k) == v ? at : Vec3(m.V.row(m.F(h / 3, k)));
    star.push_back(t);
  }
  return star;
}

// Whether the centroid and edge midpoints of every triangle of `from`, and `point` if
// given, lie within kUnfoldDeviation of the triangle's longest edge of `distanceTo`.
template <class DistanceTo>
bool within(const std::vector<Triangle>& from, DistanceTo&& distanceTo,
            const Vec3* point = nullptr) {
  for (const Triangle& t : from) {
    const double bound = kUnfoldDeviation * std::max({(t[1] - t[0]).norm(), (t[2] - t[1]).norm(),
                                                      (t[0] - t[2]).norm()});
    for (const Vec3& p : {Vec3((t[0] + t[1] + t[2]) / 3), Vec3((t[0] + t[1]) / 2),
                          Vec3((t[1] + t[2]) / 2), Vec3((t[2] + t[0]) / 2)})
      if (distanceTo(p) > bound) return false;
    if (point && distanceTo(*point) > bound) return false;
  }
  return true;
}

// Whether v's faces moved lie near the surface as given, and its faces as they were near
// them: a fold's corner slid far across a decimated mesh's large triangles, or pulled out
// of a pleat that is the shape's own, would cut through space, or leave part of the
// surface behind.
bool staysNear(const TriMesh& m, const Connectivity& c, int v, const Vec3& was,
               const TriangleBvh& given) {
  const std::vector<Triangle> now = starOf(m, c, v, m.V.row(v).transpose());
  auto toNow = [&](const Vec3& p) {
    double d = std::numeric_limits<double>::infinity();
    for (const Triangle& t : now)
      d = std::min(d, (closestPointOnTriangle(p, t[0], t[1], t[2]) - p).norm());
    return d;
  };
  return within(now, [&](const Vec3& p) { return given.closestPoint(p).distance; }) &&
         within(starOf(m, c, v, was), toNow, &was);
}

// One move of a fold's corner v (unfoldInput()); whether it was made.
bool unfoldCorner(TriMesh& m, const Connectivity& c, int v, const TriangleBvh& given) {
  const Vec3 was = m.V.row(v).transpose();
  Vec3 centroid = Vec3::Zero();
  double meanEdge = 0;
  for (int u : c.ring(v)) {
    centroid += m.V.row(u).transpose();
    meanEdge += (m.V.row(u).transpose() - was).norm();
  }
  centroid /= c.valence(v);
  meanEdge /= c.valence(v);
  const int before = foldsAround(m, c, v);
  for (double step : {0.25, 0.5, 1.0}) {
    const Vec3 to = given.closestPoint(was + step * (centroid - was)).point;
    if ((to - was).norm() > kUnfoldReach * meanEdge) continue;
    m.V.row(v) = to.transpose();
    if (foldsAround(m, c, v) < before && staysNear(m, c, v, was, given)) return true;
    m.V.row(v) = was.transpose();
  }
  return false;
}

}  // namespace

UnfoldReport unfoldInput(TriMesh& m, int maxRounds) {
  UnfoldReport r;
  // The moves keep the connectivity: one for every round.
  const Connectivity c(m.F, static_cast<int>(m.V.rows()));
  std::vector<char> fold = foldCorners(m, c);
  r.foldCorners = r.foldCornersLeft = count(fold);
  if (r.foldCorners == 0) return r;
  const TriangleBvh given(m);  // holds its own copy of the corners: the surface as given
  const Points was = m.V;
  for (int round = 0; round < maxRounds; ++round) {
    bool moved = false;
    for (int v = 0; v < static_cast<int>(m.V.rows()); ++v)
      if (fold[v] && !c.isBoundaryVertex(v) && c.isManifoldVertex(v) && c.valence(v) >= 3)
        moved = unfoldCorner(m, c, v, given) || moved;
    if (!moved) break;
    fold = foldCorners(m, c);
  }
  r.foldCornersLeft = count(fold);  // `fold` is of the mesh as the last round left it
  const double diagonal = boundingBoxDiagonal(was);
  for (Eigen::Index v = 0; v < m.V.rows(); ++v)
    if (m.V.row(v) != was.row(v)) {
      ++r.movedVertices;
      r.largestMove = std::max(r.largestMove, (m.V.row(v) - was.row(v)).norm() / diagonal);
    }
  return r;
}

}  // namespace osdmra::remeshing
