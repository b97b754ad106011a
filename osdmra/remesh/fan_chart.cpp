#include "osdmra/remesh/fan_chart.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "osdmra/geometry/normals.h"

namespace osdmra::remeshing {

namespace {

// Base vertex v's faces counter-clockwise (its fan's halfedges, each leaving v), from
// face f where v is interior and from the boundary where it is not, with the angle about
// v where each face starts, counted from f's first edge out of v.
struct Fan {
  bool closed = true;
  std::vector<int> halfedges;
  std::vector<double> start;
  double total = 0;  // the angles' sum
  double own = 0;    // f's angle at v
};

bool fanFrom(const TriMesh& base, const Connectivity& conn, int v, int f, Fan& fan) {
  const IndexSpan around = conn.fan(v);
  const int m = around.size();
  int first = 0;
  while (first < m && around[first] / 3 != f) ++first;
  if (first == m) return false;
  fan.closed = !conn.isBoundaryVertex(v);
  const int origin = fan.closed ? first : 0;
  fan.halfedges.clear();
  fan.start.clear();
  double angle = 0, startOfF = 0;
  for (int n = 0; n < m; ++n) {
    const int h = around[(origin + n) % m];
    const int g = h / 3, i = h % 3;
    const double a = faceAngle(base, g, i);
    if (g == f) startOfF = angle, fan.own = a;
    fan.halfedges.push_back(h);
    fan.start.push_back(angle);
    angle += a;
  }
  fan.total = angle;
  for (double& s : fan.start) s -= startOfF;
  return true;
}

// Where point p of the base lies about the fan's vertex v: its angle from f's first edge
// out of v and its distance from v, in the face of the fan that holds it, laid flat with
// v at the origin and its first edge along the x axis.
bool polarAbout(const TriMesh& base, const Fan& fan, int v, const BasePoint& p, double& angle,
                double& radius) {
  const Vec3 pv = base.V.row(v).transpose();
  const int m = static_cast<int>(fan.halfedges.size());
  for (int n = 0; n < m; ++n) {
    const int g = fan.halfedges[n] / 3, i = fan.halfedges[n] % 3;
    const int next = base.F(g, (i + 1) % 3), last = base.F(g, (i + 2) % 3);
    // A neighbour of v lies on the first edge of a face of the fan, or on the last edge
    // of the last face of an open fan.
    const bool onFirst = p.vertex == next, onLast = p.vertex == last && !fan.closed && n + 1 == m;
    if (p.vertex >= 0 ? !(onFirst || onLast) : p.param.face != g) continue;
    const std::array<Vec2, 3> flat =
        layFlat(pv, base.V.row(next).transpose(), base.V.row(last).transpose());
    Vec2 q = onFirst ? flat[1] : flat[2];
    if (p.vertex < 0)
      q = p.param.bary[i] * flat[0] + p.param.bary[(i + 1) % 3] * flat[1] +
          p.param.bary[(i + 2) % 3] * flat[2];
    angle = fan.start[n] + std::atan2(q.y(), q.x());
    radius = q.norm();
    return true;
  }
  return false;
}

// The corners' angles (all but the fan's vertex, `atVertex`) unwrapped onto the arc of
// the turn they span, that arc taken the way round nearest f's sector [0, fan.own].
void ontoArc(const Fan& fan, const std::array<char, 3>& atVertex, std::array<double, 3>& angle) {
  if (!fan.closed) return;  // an open fan has no way round: its angles are unique
  const double total = fan.total;
  // Into [0, total) first: a corner on the last face's far edge is on f's first edge.
  auto wrap = [&](double a) {
    a = std::fmod(a, total);
    return a < 0 ? a + total : a >= total ? a - total : a;
  };
  for (double& a : angle) a = wrap(a);
  int first = -1;
  const int kv =
      static_cast<int>(std::find(atVertex.begin(), atVertex.end(), 1) - atVertex.begin());
  if (kv < 3) {
    // A corner at v: the triangle is counter-clockwise, so it spans the turn from the
    // corner after v to the one before.
    first = (kv + 1) % 3;
  } else {
    // Else the arc starts at the corner after the widest gap between them.
    double widest = -1;
    for (int k = 0; k < 3; ++k) {
      double gap = total;
      for (int j = 0; j < 3; ++j) {
        const double ahead = wrap(angle[k] - angle[j]);
        if (j != k && ahead > 0) gap = std::min(gap, ahead);
      }
      if (gap > widest) widest = gap, first = k;
    }
  }
  const double lo = angle[first];
  double hi = lo;
  for (int k = 0; k < 3; ++k) {
    if (atVertex[k]) continue;
    angle[k] = lo + wrap(angle[k] - lo);
    hi = std::max(hi, angle[k]);
  }
  // A whole turn back or not, whichever leaves the arc nearer f's sector.
  auto distance = [&](double shift) {
    return std::max({0.0, lo + shift - fan.own, -(hi + shift)});
  };
  if (distance(-total) < distance(0))
    for (double& a : angle) a -= total;
}

}  // namespace

bool layAboutCorner(const TriMesh& base, const Connectivity& baseConn, int f, int iv,
                    const Laid& own, const std::array<BasePoint, 3>& corners,
                    std::array<Vec2, 3>& image) {
  thread_local Fan fan;
  const int v = base.F(f, iv);
  if (!fanFrom(base, baseConn, v, f, fan)) return false;
  std::array<double, 3> angle{}, radius{};
  std::array<char, 3> atVertex{};
  for (int k = 0; k < 3; ++k) {
    atVertex[k] = corners[k].vertex == v;
    if (!atVertex[k] && !polarAbout(base, fan, v, corners[k], angle[k], radius[k])) return false;
  }
  ontoArc(fan, atVertex, angle);
  // In f's chart: v where `own` has it, f's first edge out of v along `e`.
  const Vec2 at = own.pos[iv];
  const Vec2 e = (own.pos[(iv + 1) % 3] - at).normalized(), n(-e.y(), e.x());
  for (int k = 0; k < 3; ++k)
    image[k] =
        atVertex[k] ? at : Vec2(at + radius[k] * (std::cos(angle[k]) * e + std::sin(angle[k]) * n));
  return true;
}

}  // namespace osdmra::remeshing
