#include "osdmra/remesh/base_flips.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "osdmra/geometry/normals.h"
#include "osdmra/geometry/self_intersection.h"
#include "osdmra/geometry/surface_walk.h"
#include "osdmra/remesh/distortion.h"
#include "osdmra/remesh/planar.h"
#include "osdmra/remesh/removal.h"

namespace osdmra::remeshing {
namespace {

using Box = Eigen::AlignedBox3d;

// Twice the signed area of (a, b, c) over the product of two of its sides' lengths: the
// sine of the angle at a, positive for a counter-clockwise triangle.
double sineAt(const Vec2& a, const Vec2& b, const Vec2& c) {
  const Vec2 u = b - a, v = c - a;
  const double n = u.norm() * v.norm();
  return n > 0 ? cross2(u, v) / n : 0;
}

// A pair of base faces about their shared edge (a, c): f1 = (a, c, b) and f2 = (c, a, d)
// in their corners' cyclic order, laid flat with a at the origin, c on the x axis, b
// above and d below (the hinge unfolded: each face keeps its shape).
struct Quad {
  int f1 = -1, f2 = -1;
  int a = -1, b = -1, c = -1, d = -1;
  Vec2 pa, pb, pc, pd;
  Vec2 flat(int v) const { return v == a ? pa : v == b ? pb : v == c ? pc : pd; }
};

class Flipper {
 public:
  Flipper(Simplification& s, const BaseFlipOptions& options) : s_(s), options_(options) {
    const int n = static_cast<int>(s.baseOf.size());
    inputOf_.assign(s.base.V.rows(), -1);
    for (int v = 0; v < n; ++v)
      if (s.baseOf[v] >= 0) inputOf_[s.baseOf[v]] = v;
    pointsOf_.resize(s.base.F.rows());
    for (int v = 0; v < n; ++v)
      if (s.baseOf[v] < 0) pointsOf_[s.params[v].face].push_back(v);
    facesOf_.resize(s.base.V.rows());
    for (Eigen::Index f = 0; f < s.base.F.rows(); ++f)
      for (int k = 0; k < 3; ++k) facesOf_[s.base.F(f, k)].push_back(static_cast<int>(f));
  }

  BaseFlipReport run() {
    BaseFlipReport report;
    for (int sweep = 0; sweep < options_.maxSweeps; ++sweep) {
      const int made = flipSweep(report);
      if (made == 0) break;
    }
    return report;
  }

 private:
  std::array<int, 3> face(int f) const {
    return {s_.base.F(f, 0), s_.base.F(f, 1), s_.base.F(f, 2)};
  }
  Vec3 position(int v) const { return s_.base.V.row(v).transpose(); }
  bool isFeature(int a, int b) const {
    return s_.featureEdges.count(edgeKey(inputOf_[a], inputOf_[b])) != 0;
  }

  int flipSweep(BaseFlipReport& report);
  bool quadAbout(int f1, int k, int f2, Quad& q) const;
  bool isCap(const Quad& q) const;
  bool convexAndFlat(const Quad& q) const;
  bool makesCrossing(const Quad& q) const;
  bool foldsLess(const Quad& q) const;
  int foldsOver(const Quad& q, const std::array<Vec2, 3>& face) const;
  bool onInput(const Quad& q, const std::vector<Vec2>& points, const Vec2& at, Vec3& position,
               Vec3& normal) const;
  bool movePoints(const Quad& q, std::vector<std::pair<int, Param>>& moved) const;
  void commit(const Quad& q, const std::vector<std::pair<int, Param>>& moved);

  Simplification& s_;
  const BaseFlipOptions& options_;
  std::vector<int> inputOf_;                 // base vertex -> input vertex
  std::vector<std::vector<int>> pointsOf_;   // base face -> the input points it holds
  std::vector<std::vector<int>> facesOf_;    // base vertex -> its faces
  std::unordered_set<std::uint64_t> edges_;  // every base edge, as a key
};

// One pass over the base's interior edges; a face flipped in it waits for the next.
int Flipper::flipSweep(BaseFlipReport& report) {
  const int nf = static_cast<int>(s_.base.F.rows());
  std::unordered_map<std::uint64_t, std::vector<int>> facesOfEdge;
  edges_.clear();
  for (int f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) {
      const std::uint64_t key = edgeKey(s_.base.F(f, k), s_.base.F(f, (k + 1) % 3));
      facesOfEdge[key].push_back(f);
      edges_.insert(key);
    }
  std::vector<char> touched(nf, 0);
  int made = 0;
  for (int f1 = 0; f1 < nf; ++f1)
    for (int k = 0; k < 3 && !touched[f1]; ++k) {
      const auto& pair = facesOfEdge[edgeKey(s_.base.F(f1, k), s_.base.F(f1, (k + 1) % 3))];
      if (pair.size() != 2) continue;
      const int f2 = pair[0] == f1 ? pair[1] : pair[0];
      Quad q;
      if (touched[f2] || !quadAbout(f1, k, f2, q) || !isCap(q)) continue;
      std::vector<std::pair<int, Param>> moved;
      if (isFeature(q.a, q.c) || edges_.count(edgeKey(q.b, q.d)) || facesOf_[q.a].size() < 4 ||
          facesOf_[q.c].size() < 4 || !convexAndFlat(q) || makesCrossing(q) ||
          (options_.levels > 0 && options_.input && !foldsLess(q)) || !movePoints(q, moved)) {
        ++report.refused;
        continue;
      }
      commit(q, moved);
      touched[f1] = touched[f2] = 1;
      ++made;
      ++report.flips;
    }
  return made;
}

// The pair about edge k of f1 (corners k, k + 1), laid flat; false where f2 does not
// hold that edge the other way round (a non-manifold or misoriented pair).
bool Flipper::quadAbout(int f1, int k, int f2, Quad& q) const {
  const auto t1 = face(f1), t2 = face(f2);
  q.f1 = f1;
  q.f2 = f2;
  q.a = t1[k];
  q.c = t1[(k + 1) % 3];
  q.b = t1[(k + 2) % 3];
  int j = 0;
  while (j < 3 && !(t2[j] == q.c && t2[(j + 1) % 3] == q.a)) ++j;
  if (j == 3) return false;
  q.d = t2[(j + 2) % 3];
  if (q.b == q.d) return false;
  const auto up = layFlat(position(q.a), position(q.c), position(q.b));
  const auto down = layFlat(position(q.a), position(q.c), position(q.d));
  q.pa = up[0];
  q.pc = up[1];
  q.pb = up[2];
  q.pd = Vec2(down[2].x(), -down[2].y());
  return true;
}

// Whether the pair holds an angle over the cap bound that the flip makes smaller.
bool Flipper::isCap(const Quad& q) const {
  const double before =
      std::max(largestAngle(q.pa, q.pc, q.pb), largestAngle(q.pc, q.pa, q.pd)) * 180 / kPi;
  if (before <= options_.capAngle) return false;
  return std::max(largestAngle(q.pa, q.pd, q.pb), largestAngle(q.pc, q.pb, q.pd)) * 180 / kPi <
         before;
}

// The flipped faces (a, d, b) and (c, b, d) counter-clockwise with a margin at every
// corner: the quad is strictly convex, so the two triangulations tile it alike and the
// map between them is a bijection; and each about as in space as in the quad.
bool Flipper::convexAndFlat(const Quad& q) const {
  constexpr double kMargin = 1e-6;
  const std::array<std::array<Vec2, 3>, 2> faces = {{{q.pa, q.pd, q.pb}, {q.pc, q.pb, q.pd}}};
  for (const auto& t : faces)
    for (int i = 0; i < 3; ++i)
      if (!(sineAt(t[i], t[(i + 1) % 3], t[(i + 2) % 3]) > kMargin)) return false;
  const std::array<std::array<Vec3, 3>, 2> inSpace = {
      {{position(q.a), position(q.d), position(q.b)},
       {position(q.c), position(q.b), position(q.d)}}};
  for (int t = 0; t < 2; ++t)
    if (!(anisotropy(inSpace[t], faces[t]) <= options_.stretch)) return false;
  return true;
}

// Whether a flipped face would meet a base face in space that neither old face met (the
// base never crosses itself where the simplification kept it from doing so).
bool Flipper::makesCrossing(const Quad& q) const {
  const Points& V = s_.base.V;
  const std::array<std::array<int, 3>, 2> made = {{{q.a, q.d, q.b}, {q.c, q.b, q.d}}};
  const std::array<int, 3> old1 = face(q.f1), old2 = face(q.f2);
  Box box;
  for (int v : {q.a, q.b, q.c, q.d}) box.extend(position(v));
  for (Eigen::Index g = 0; g < s_.base.F.rows(); ++g) {
    if (g == q.f1 || g == q.f2) continue;
    const std::array<int, 3> t = face(static_cast<int>(g));
    Box gb;
    for (int v : t) gb.extend(position(v));
    if (!gb.intersects(box)) continue;
    if (!trianglesMeet(V, made[0], t) && !trianglesMeet(V, made[1], t)) continue;
    if (!trianglesMeet(V, old1, t) && !trianglesMeet(V, old2, t)) return true;
  }
  return false;
}

// The input point the exact map puts at flat point `at` of the pair (before the flip;
// `points` its corners a, c, b, d laid flat), and the normal of the input face there.
bool Flipper::onInput(const Quad& q, const std::vector<Vec2>& points, const Vec2& at,
                      Vec3& position, Vec3& normal) const {
  static const std::vector<std::array<int, 3>> kOldPair = {{0, 1, 2}, {1, 0, 3}};
  std::array<double, 3> bary;
  const int t = locateInTriangles(at, points, kOldPair, bary);
  if (t < 0) return false;
  const int f = t == 0 ? q.f1 : q.f2;
  const std::array<int, 3> corners =
      t == 0 ? std::array<int, 3>{q.a, q.c, q.b} : std::array<int, 3>{q.c, q.a, q.d};
  std::array<double, 3> row{};
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k)
      if (s_.base.F(f, i) == corners[k]) row[i] = bary[k];
  const SurfacePoint p = traceToInput(s_.history, f, row);
  const TriMesh& in = *options_.input;
  position.setZero();
  for (int i = 0; i < 3; ++i) position += p.bary[i] * in.V.row(in.F(p.triangle, i)).transpose();
  normal = faceNormal(in, p.triangle);
  return true;
}

// The grid triangles of `face` (flat corners) that face against the input under each of
// their corners, or have no area.
int Flipper::foldsOver(const Quad& q, const std::array<Vec2, 3>& face) const {
  const int n = 1 << options_.levels;
  const std::vector<Vec2> oldPair = {q.pa, q.pc, q.pb, q.pd};  // as onInput locates in
  std::vector<Vec3> position((n + 1) * (n + 2) / 2), normal(position.size());
  auto index = [&](int i, int j) { return j * (n + 1) - j * (j - 1) / 2 + i; };
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i + j <= n; ++i) {
      const Vec2 at =
          face[0] + (double(i) / n) * (face[1] - face[0]) + (double(j) / n) * (face[2] - face[0]);
      if (!onInput(q, oldPair, at, position[index(i, j)], normal[index(i, j)])) return 1 << 30;
    }
  int folds = 0;
  auto check = [&](int u, int v, int w) {
    const Vec3 m = (position[v] - position[u]).cross(position[w] - position[u]);
    if (!(m.squaredNorm() > 0) ||
        (m.dot(normal[u]) < 0 && m.dot(normal[v]) < 0 && m.dot(normal[w]) < 0))
      ++folds;
  };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i + j < n; ++i) {
      check(index(i, j), index(i + 1, j), index(i, j + 1));
      if (i + j + 1 < n) check(index(i + 1, j), index(i + 1, j + 1), index(i, j + 1));
    }
  return folds;
}

// Whether the grid over the flipped pair folds less than over the pair as it is.
bool Flipper::foldsLess(const Quad& q) const {
  const int before = foldsOver(q, {q.pa, q.pc, q.pb}) + foldsOver(q, {q.pc, q.pa, q.pd});
  if (before == 0) return false;
  const int after = foldsOver(q, {q.pa, q.pd, q.pb}) + foldsOver(q, {q.pc, q.pb, q.pd});
  return after < before;
}

// Every point of the pair at its place in the flipped faces: its flat position from
// its barycentric coordinates in its old face, then located in the new ones.
bool Flipper::movePoints(const Quad& q, std::vector<std::pair<int, Param>>& moved) const {
  const std::vector<Vec2> points = {q.pa, q.pd, q.pb, q.pc};
  const std::vector<std::array<int, 3>> triangles = {{0, 1, 2}, {3, 2, 1}};
  for (int f : {q.f1, q.f2})
    for (int point : pointsOf_[f]) {
      const Param& p = s_.params[point];
      Vec2 at = Vec2::Zero();
      for (int i = 0; i < 3; ++i) at += p.bary[i] * q.flat(s_.base.F(f, i));
      std::array<double, 3> bary;
      const int t = locateInTriangles(at, points, triangles, bary);
      if (t < 0) return false;
      moved.push_back({point, {t == 0 ? q.f1 : q.f2, bary}});
    }
  return true;
}

// The flip made: f1 becomes (a, d, b) and f2 (c, b, d); the history records it as a
// removal whose "removed" vertex a stays, so traceToInput undoes it as any other: its
// fan about a is the old pair (a, d, c) and (a, c, b), and a is also ring position 3.
void Flipper::commit(const Quad& q, const std::vector<std::pair<int, Param>>& moved) {
  History& h = s_.history;
  const int record = static_cast<int>(h.removals.size());
  RemovalRecord r;
  r.vertex = inputOf_[q.a];
  r.verts = {inputOf_[q.d], inputOf_[q.c], inputOf_[q.b], inputOf_[q.a]};
  r.oldFaces = {h.baseFace[q.f2], h.baseFace[q.f1]};
  r.points = {q.pd, q.pc, q.pb, Vec2::Zero()};
  r.triangles = {{3, 0, 2}, {1, 2, 0}};
  h.removals.push_back(std::move(r));
  const std::array<std::array<int, 3>, 2> made = {{{q.a, q.d, q.b}, {q.c, q.b, q.d}}};
  const std::array<int, 2> slot = {q.f1, q.f2};
  for (int t = 0; t < 2; ++t) {
    h.faces.push_back({inputOf_[made[t][0]], inputOf_[made[t][1]], inputOf_[made[t][2]]});
    h.removal.push_back(record);
    h.triangle.push_back(t);
    h.baseFace[slot[t]] = static_cast<int>(h.faces.size()) - 1;
    for (int i = 0; i < 3; ++i) s_.base.F(slot[t], i) = made[t][i];
  }
  auto drop = [&](int v, int f) {
    auto& list = facesOf_[v];
    list.erase(std::find(list.begin(), list.end(), f));
  };
  drop(q.a, q.f2);
  drop(q.c, q.f1);
  facesOf_[q.d].push_back(q.f1);
  facesOf_[q.b].push_back(q.f2);
  edges_.erase(edgeKey(q.a, q.c));
  edges_.insert(edgeKey(q.b, q.d));
  pointsOf_[q.f1].clear();
  pointsOf_[q.f2].clear();
  for (const auto& [point, param] : moved) {
    s_.params[point] = param;
    pointsOf_[param.face].push_back(point);
  }
  // A kept vertex's place is a corner of one of its faces: re-pointed where that face
  // no longer has it.
  for (int v : {q.a, q.b, q.c, q.d}) {
    Param& p = s_.params[inputOf_[v]];
    if (p.face != q.f1 && p.face != q.f2) continue;
    p.face = facesOf_[v].front();
    for (int i = 0; i < 3; ++i) p.bary[i] = s_.base.F(p.face, i) == v ? 1.0 : 0.0;
  }
}

}  // namespace

BaseFlipReport flipCaps(Simplification& s, const BaseFlipOptions& options) {
  return Flipper(s, options).run();
}

}  // namespace osdmra::remeshing
