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

// A split of the longest edge (a, c) of a base face whose grid folds: an input vertex
// held by the pair about it (or by the face alone, on the boundary) made a base vertex
// again, the faces fanned about it. Corners by local id: 0 the new vertex, 1 a, 2 b,
// 3 c, 4 d (as in Quad; no d on the boundary).
struct Split {
  bool boundary = false;   // (a, c) on the boundary: one face split in two
  bool onEdge = false;     // the vertex on (a, c) itself: a boundary or feature line's
  int vertex = -1;         // the input vertex, or -1 for a point of the input (added)
  bool added = false;      // a point of the input that is no input vertex
  Vec2 at = Vec2::Zero();  // its place in the flat pair
  Vec3 position = Vec3::Zero();
  SurfacePoint where;  // where it lies on the input, if added
  std::vector<std::array<int, 3>> fan() const {
    if (boundary) return {{1, 0, 2}, {0, 3, 2}};
    return {{0, 1, 4}, {0, 4, 3}, {0, 3, 2}, {0, 2, 1}};
  }
};

template <typename T>
std::array<T, 3> corners(const std::array<int, 3>& local, const std::array<T, 5>& of) {
  return {of[local[0]], of[local[1]], of[local[2]]};
}

class Flipper {
 public:
  Flipper(Simplification& s, const BaseFlipOptions& options)
      : s_(s), options_(options), inputOf_(historyIdsOfBase(s)) {
    indexFaces();
  }

  // Sweeps of flips out of caps, or (towardsInput) towards the input.
  BaseFlipReport run(bool towardsInput) {
    BaseFlipReport report;
    for (int sweep = 0; sweep < options_.maxSweeps; ++sweep) {
      const int made = flipSweep(report, towardsInput);
      if (made == 0) break;
    }
    return report;
  }

  BaseFlipReport split(const std::vector<int>& folds) {
    BaseFlipReport report;
    if (options_.maxSplits > 0 && options_.input) splitFolds(folds, report);
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

  int flipSweep(BaseFlipReport& report, bool towardsInput);
  bool nearerInput(const Quad& q) const;
  double sharpestFold(const Quad& q, const std::array<std::array<int, 3>, 2>& pair) const;
  bool quadAbout(int f1, int k, int f2, Quad& q) const;
  bool isCap(const Quad& q) const;
  bool convexAndFlat(const Quad& q) const;
  bool makesCrossing(const Quad& q, const Points& V,
                     const std::vector<std::array<int, 3>>& made) const;
  void splitFolds(const std::vector<int>& folds, BaseFlipReport& report);
  bool singleAbout(int f, int k, Quad& q) const;
  bool splitPoint(const Quad& q, Split& split) const;
  bool fanFits(const Quad& q, const Split& split, const Vec2& at, const Vec3& inSpace,
               double& widestSoFar) const;
  bool splitFoldsLess(const Quad& q, const Split& split) const;
  std::vector<int> slotsOf(const Quad& q) const;
  bool moveSplitPoints(const Quad& q, const Split& split,
                       std::vector<std::pair<int, Param>>& moved) const;
  bool splitMakesCrossing(const Quad& q, const Split& split) const;
  void commitSplit(const Quad& q, const Split& split,
                   const std::vector<std::pair<int, Param>>& moved);
  void indexFaces();
  bool foldsLess(const Quad& q) const;
  int foldsOver(const Quad& q, const std::array<Vec2, 3>& face) const;
  bool onInput(const Quad& q, const std::vector<Vec2>& points, const Vec2& at, Vec3& position,
               Vec3& normal, SurfacePoint* where = nullptr) const;
  bool movePoints(const Quad& q, std::vector<std::pair<int, Param>>& moved) const;
  Vec2 flatPlace(const Quad& q, int f, int point) const;
  bool relocate(const Quad& q, const std::vector<Vec2>& points,
                const std::vector<std::array<int, 3>>& triangles, const std::vector<int>& slots,
                int skip, std::vector<std::pair<int, Param>>& moved) const;
  void commit(const Quad& q, const std::vector<std::pair<int, Param>>& moved);

  Simplification& s_;
  const BaseFlipOptions& options_;
  std::vector<int> inputOf_;  // base vertex -> its id in the history (historyIdsOfBase)
  std::vector<std::vector<int>> pointsOf_;   // base face -> the input points it holds
  std::vector<std::vector<int>> facesOf_;    // base vertex -> its faces
  std::unordered_set<std::uint64_t> edges_;  // every base edge, as a key
};

// One pass over the base's interior edges; a face flipped in it waits for the next.
int Flipper::flipSweep(BaseFlipReport& report, bool towardsInput) {
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
      if (touched[f2] || !quadAbout(f1, k, f2, q) || !(towardsInput || isCap(q))) continue;
      std::vector<std::pair<int, Param>> moved;
      // Towards the input every edge is a candidate: the local test before the crossing
      // check, which looks at every base face (the same flips: the bunny at 6,945 57 -> 51 s).
      if (isFeature(q.a, q.c) || edges_.count(edgeKey(q.b, q.d)) || facesOf_[q.a].size() < 4 ||
          facesOf_[q.c].size() < 4 || !convexAndFlat(q) || (towardsInput && !nearerInput(q)) ||
          makesCrossing(q, s_.base.V, {{q.a, q.d, q.b}, {q.c, q.b, q.d}}) ||
          (!towardsInput && options_.levels > 0 && options_.input && !foldsLess(q)) ||
          !movePoints(q, moved)) {
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
  singleAbout(f1, k, q);
  const auto t2 = face(f2);
  q.f2 = f2;
  int j = 0;
  while (j < 3 && !(t2[j] == q.c && t2[(j + 1) % 3] == q.a)) ++j;
  if (j == 3) return false;
  q.d = t2[(j + 2) % 3];
  if (q.b == q.d) return false;
  const auto down = layFlat(position(q.a), position(q.c), position(q.d));
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
bool Flipper::makesCrossing(const Quad& q, const Points& V,
                            const std::vector<std::array<int, 3>>& made) const {
  const std::array<int, 3> old1 = face(q.f1), old2 = q.f2 >= 0 ? face(q.f2) : old1;
  Box box;
  for (const auto& t : made)
    for (int v : t) box.extend(V.row(v).transpose());
  for (Eigen::Index g = 0; g < s_.base.F.rows(); ++g) {
    if (g == q.f1 || g == q.f2) continue;
    const std::array<int, 3> t = face(static_cast<int>(g));
    Box gb;
    for (int v : t) gb.extend(position(v));
    if (!gb.intersects(box)) continue;
    if (std::none_of(made.begin(), made.end(),
                     [&](const std::array<int, 3>& m) { return trianglesMeet(V, m, t); }))
      continue;
    if (!trianglesMeet(V, old1, t) && !trianglesMeet(V, old2, t)) return true;
  }
  return false;
}

// The input point the exact map puts at flat point `at` of the pair (before the flip;
// `points` its corners a, c, b, d laid flat), and the normal of the input face there.
bool Flipper::onInput(const Quad& q, const std::vector<Vec2>& points, const Vec2& at,
                      Vec3& position, Vec3& normal, SurfacePoint* where) const {
  static const std::vector<std::array<int, 3>> kOldPair = {{0, 1, 2}, {1, 0, 3}};
  static const std::vector<std::array<int, 3>> kOldFace = {{0, 1, 2}};
  std::array<double, 3> bary;
  const int t = locateInTriangles(at, points, q.f2 >= 0 ? kOldPair : kOldFace, bary);
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
  if (where) *where = p;
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

// Whether the input points the pair holds lie nearer the planes of the flipped faces
// than of the faces as they are (each point against the face its flat place falls in):
// the triangulation of the four corners that fits the input better, as a data-dependent
// triangulation chooses (Dyn, Levin and Rippa 1990). Each flip lowers the sum over the
// base, so the sweeps end.
bool Flipper::nearerInput(const Quad& q) const {
  if (!options_.input) return false;
  const TriMesh& in = *options_.input;
  auto plane = [&](int u, int v, int w) {
    const Vec3 n = (position(v) - position(u)).cross(position(w) - position(u));
    return std::make_pair(n.normalized(), position(u));
  };
  const std::array<std::pair<Vec3, Vec3>, 4> planes = {plane(q.a, q.c, q.b), plane(q.c, q.a, q.d),
                                                       plane(q.a, q.d, q.b), plane(q.c, q.b, q.d)};
  for (const auto& [n, o] : planes)
    if (!n.allFinite()) return false;
  const std::vector<Vec2> flipped = {q.pa, q.pd, q.pb, q.pc};
  const std::vector<std::array<int, 3>> faces = {{0, 1, 2}, {3, 2, 1}};
  double before = 0, after = 0;
  for (int t = 0; t < 2; ++t) {
    const int f = t == 0 ? q.f1 : q.f2;
    for (int point : pointsOf_[f]) {
      const Vec3 x = in.V.row(point).transpose();
      const auto& [n, o] = planes[t];
      const double d0 = n.dot(x - o);
      before += d0 * d0;
      std::array<double, 3> bary;
      const int g = locateInTriangles(flatPlace(q, f, point), flipped, faces, bary);
      if (g < 0) return false;
      const auto& [m, p] = planes[2 + g];
      const double d1 = m.dot(x - p);
      after += d1 * d1;
    }
  }
  if (!(after < before * (1 - 1e-9))) return false;
  // No new fold past a right angle, between the new faces or with a face beside them:
  // on a coarse base of a CAD model such a flip left crossing pairs (fandisk at 129).
  const double old = sharpestFold(q, {{{q.a, q.c, q.b}, {q.c, q.a, q.d}}});
  const double made = sharpestFold(q, {{{q.a, q.d, q.b}, {q.c, q.b, q.d}}});
  return made > 0 || made >= old;
}

// The least cosine between the normal of either face of `pair` (taking the place of the
// quad's) and of the other, or of a base face sharing an edge with it.
double Flipper::sharpestFold(const Quad& q, const std::array<std::array<int, 3>, 2>& pair) const {
  auto normal = [&](const std::array<int, 3>& t) {
    return (position(t[1]) - position(t[0])).cross(position(t[2]) - position(t[0])).normalized();
  };
  const Vec3 n0 = normal(pair[0]), n1 = normal(pair[1]);
  double least = n0.dot(n1);
  for (int t = 0; t < 2; ++t) {
    const Vec3 n = t == 0 ? n0 : n1;
    for (int i = 0; i < 3; ++i) {
      const int u = pair[t][i], v = pair[t][(i + 1) % 3];
      for (int g : facesOf_[u]) {
        if (g == q.f1 || g == q.f2) continue;
        const auto other = face(g);
        if (std::find(other.begin(), other.end(), v) == other.end()) continue;
        least = std::min(least, n.dot(normal(other)));
      }
    }
  }
  return least;
}

// Every point of the pair at its place in the flipped faces: its flat position from
// its barycentric coordinates in its old face, then located in the new ones.
bool Flipper::movePoints(const Quad& q, std::vector<std::pair<int, Param>>& moved) const {
  return relocate(q, {q.pa, q.pd, q.pb, q.pc}, {{0, 1, 2}, {3, 2, 1}}, {q.f1, q.f2}, -1, moved);
}

// Point `point` of base face f (one of the pair) where the pair is laid flat.
Vec2 Flipper::flatPlace(const Quad& q, int f, int point) const {
  const Param& p = s_.params[point];
  Vec2 at = Vec2::Zero();
  for (int i = 0; i < 3; ++i) at += p.bary[i] * q.flat(s_.base.F(f, i));
  return at;
}

// Every point of the old faces but `skip`, at its flat place located in the new
// `triangles` (corners among `points`), the i-th of which is base face slots[i].
bool Flipper::relocate(const Quad& q, const std::vector<Vec2>& points,
                       const std::vector<std::array<int, 3>>& triangles,
                       const std::vector<int>& slots, int skip,
                       std::vector<std::pair<int, Param>>& moved) const {
  for (int f : {q.f1, q.f2}) {
    if (f < 0) continue;
    for (int point : pointsOf_[f]) {
      if (point == skip) continue;
      std::array<double, 3> bary;
      const int t = locateInTriangles(flatPlace(q, f, point), points, triangles, bary);
      if (t < 0) return false;
      moved.push_back({point, {slots[t], bary}});
    }
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
  // no longer has it (a point of the input made a base vertex by a split has none).
  const int inputs = static_cast<int>(s_.baseOf.size());
  for (int v : {q.a, q.b, q.c, q.d}) {
    if (inputOf_[v] >= inputs) continue;
    Param& p = s_.params[inputOf_[v]];
    if (p.face != q.f1 && p.face != q.f2) continue;
    p.face = facesOf_[v].front();
    for (int i = 0; i < 3; ++i) p.bary[i] = s_.base.F(p.face, i) == v ? 1.0 : 0.0;
  }
}

// Base faces whose grid folds, the longest edge of each split, most folds first, each a
// step of the parameterisation that traceToInput undoes. A finer base where sampling
// folds: a base face's grid folds less the smaller the face is against the input's
// creases.
void Flipper::splitFolds(const std::vector<int>& folds, BaseFlipReport& report) {
  std::unordered_map<std::uint64_t, std::vector<int>> facesOfEdge;
  const int nf = static_cast<int>(s_.base.F.rows());
  for (int f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k)
      facesOfEdge[edgeKey(s_.base.F(f, k), s_.base.F(f, (k + 1) % 3))].push_back(f);
  // The quad about f's longest edge (or f alone, that edge on the boundary).
  auto quadOf = [&](int f, Quad& q) {
    const auto t = face(f);
    int k = 0;
    for (int i = 1; i < 3; ++i)
      if ((position(t[(i + 1) % 3]) - position(t[i])).norm() >
          (position(t[(k + 1) % 3]) - position(t[k])).norm())
        k = i;
    const auto& pair = facesOfEdge[edgeKey(t[k], t[(k + 1) % 3])];
    if (pair.size() == 1) return singleAbout(f, k, q);
    return pair.size() == 2 && quadAbout(f, k, pair[0] == f ? pair[1] : pair[0], q);
  };
  std::vector<std::pair<int, int>> folding;  // (folds, face)
  for (int f = 0; f < nf && f < static_cast<int>(folds.size()); ++f)
    if (folds[f] > 0) folding.push_back({folds[f], f});
  std::sort(folding.rbegin(), folding.rend());
  std::vector<char> touched(nf, 0);
  for (const auto& [count, f1] : folding) {
    if (report.splits >= options_.maxSplits) break;
    Quad q;
    if (touched[f1] || !quadOf(f1, q) || (q.f2 >= 0 && touched[q.f2])) continue;
    Split split;
    split.boundary = q.f2 < 0;
    split.onEdge = split.boundary || isFeature(q.a, q.c);
    std::vector<std::pair<int, Param>> moved;
    const bool placed = splitPoint(q, split);
    const bool foldsMore = placed && options_.splitFoldCheck && !splitFoldsLess(q, split);
    if (!placed || foldsMore || !moveSplitPoints(q, split, moved) || splitMakesCrossing(q, split)) {
      ++report.splitsRefused;
      report.splitsFoldingMore += foldsMore;
      continue;
    }
    commitSplit(q, split, moved);
    touched[f1] = 1;
    if (q.f2 >= 0) touched[q.f2] = 1;
    ++report.splits;
  }
}

// Face f alone about its edge k, as quadAbout lays a pair (no d: b mirrored, never used).
bool Flipper::singleAbout(int f, int k, Quad& q) const {
  const auto t = face(f);
  q.f1 = f;
  q.f2 = q.d = -1;
  q.a = t[k];
  q.c = t[(k + 1) % 3];
  q.b = t[(k + 2) % 3];
  const auto up = layFlat(position(q.a), position(q.c), position(q.b));
  q.pa = up[0];
  q.pc = up[1];
  q.pb = up[2];
  q.pd = Vec2(up[2].x(), -up[2].y());
  return true;
}

// The input vertex held by the pair whose re-insertion leaves the new faces' widest
// angle in space smallest, and under 120 degrees or the pair's widest: strictly inside
// the flat pair's kernel (on the edge itself where that is a boundary or feature line,
// which it then keeps), each new face about as in space as in the pair (the points keep
// their flat places). Where the pair holds none (a decimated input's faces hold few, and
// a face along a hole's rim few more) and the options allow, a point of the input that
// is no vertex of it, under the same bounds: the base needs no input vertex there, only
// a point of the input at a place in the pair, which traceToInput maps as any other.
bool Flipper::splitPoint(const Quad& q, Split& split) const {
  const TriMesh& in = *options_.input;
  double best = std::max(largestAngle(q.pa, q.pc, q.pb), 120 * kPi / 180);
  if (q.f2 >= 0) best = std::max(best, largestAngle(q.pc, q.pa, q.pd));
  for (int f : {q.f1, q.f2}) {
    if (f < 0) continue;
    for (int point : pointsOf_[f]) {
      const Vec2 at = flatPlace(q, f, point);
      double offEdge = 0;
      for (int i = 0; i < 3; ++i) {
        const int corner = s_.base.F(f, i);
        if (corner != q.a && corner != q.c) offEdge = s_.params[point].bary[i];
      }
      if (split.onEdge != (std::abs(offEdge) < 1e-12)) continue;
      const Vec3 position = in.V.row(point).transpose();
      if (fanFits(q, split, at, position, best))
        split.vertex = point, split.at = at, split.position = position;
    }
  }
  if (split.vertex >= 0 || split.onEdge || !options_.splitAtPoints) return split.vertex >= 0;
  // The points of a lattice over each face of the pair laid flat (the shared edge's
  // inner ones too), each where the exact map puts it on the input: the one whose fan
  // fits best. The middle of the shared edge alone seldom fits where the grid folds:
  // the map is distorted there (the decimated knight over 150 at J = 4: stretches of 2.2
  // to 9.3 for a bound of 2, or a widest angle of 154 degrees).
  constexpr int kLattice = 8;  // 4: more points moved on the corpus; 16: the same
  const std::array<std::array<Vec2, 3>, 2> pair = {{{q.pa, q.pc, q.pb}, {q.pc, q.pa, q.pd}}};
  for (const auto& face : pair) {
    const int fromJ = &face == &pair[0] ? 0 : 1;  // the shared edge (j = 0) once
    for (int i = 1; i < kLattice; ++i)
      for (int j = fromJ; i + j < kLattice; ++j) {
        const Vec2 at = face[0] + (double(i) / kLattice) * (face[1] - face[0]) +
                        (double(j) / kLattice) * (face[2] - face[0]);
        Vec3 position, normal;
        SurfacePoint where;
        if (onInput(q, {q.pa, q.pc, q.pb, q.pd}, at, position, normal, &where) &&
            fanFits(q, split, at, position, best))
          split.added = true, split.at = at, split.position = position, split.where = where;
      }
  }
  return split.added;
}

// Whether the fan about a new vertex at flat place `at`, at `inSpace` in space, has
// every face turning the same way in the pair, each within options.splitStretch of its
// flat shape, and a widest angle in space under `widestSoFar`, which it then lowers.
bool Flipper::fanFits(const Quad& q, const Split& split, const Vec2& at, const Vec3& inSpace,
                      double& widestSoFar) const {
  constexpr double kMargin = 1e-3;
  const std::array<Vec2, 5> flat = {at, q.pa, q.pb, q.pc, q.pd};
  const std::array<Vec3, 5> space = {inSpace, position(q.a), position(q.b), position(q.c),
                                     q.f2 >= 0 ? position(q.d) : Vec3::Zero()};
  double widest = 0;
  for (const auto& local : split.fan()) {
    const auto t = corners(local, flat);
    for (int i = 0; i < 3; ++i)
      if (!(sineAt(t[i], t[(i + 1) % 3], t[(i + 2) % 3]) > kMargin)) return false;
    if (!(anisotropy(corners(local, space), t) <= options_.splitStretch)) return false;
    const auto laid = layFlat(space[local[0]], space[local[1]], space[local[2]]);
    widest = std::max(widest, largestAngle(laid[0], laid[1], laid[2]));
  }
  if (!(widest < widestSoFar)) return false;
  widestSoFar = widest;
  return true;
}

// Whether the grid over the new faces folds no more than over the old.
bool Flipper::splitFoldsLess(const Quad& q, const Split& split) const {
  int before = foldsOver(q, {q.pa, q.pc, q.pb});
  if (q.f2 >= 0) before += foldsOver(q, {q.pc, q.pa, q.pd});
  const std::array<Vec2, 5> flat = {split.at, q.pa, q.pb, q.pc, q.pd};
  int after = 0;
  for (const auto& local : split.fan())
    if ((after += foldsOver(q, corners(local, flat))) > before) return false;
  return true;
}

// The slots of the new faces: the old ones', then new ones at the end of the base.
std::vector<int> Flipper::slotsOf(const Quad& q) const {
  const int nf = static_cast<int>(s_.base.F.rows());
  if (q.f2 < 0) return {q.f1, nf};
  return {q.f1, q.f2, nf, nf + 1};
}

// Every other point of the old faces at its place in the new ones.
bool Flipper::moveSplitPoints(const Quad& q, const Split& split,
                              std::vector<std::pair<int, Param>>& moved) const {
  return relocate(q, {split.at, q.pa, q.pb, q.pc, q.pd}, split.fan(), slotsOf(q), split.vertex,
                  moved);
}

// Whether a new face would meet a base face in space that the old ones did not meet.
bool Flipper::splitMakesCrossing(const Quad& q, const Split& split) const {
  const int nv = static_cast<int>(s_.base.V.rows());
  Points V(nv + 1, 3);
  V.topRows(nv) = s_.base.V;
  V.row(nv) = split.position;
  const std::array<int, 5> id = {nv, q.a, q.b, q.c, q.d};
  std::vector<std::array<int, 3>> made;
  for (const auto& local : split.fan()) made.push_back(corners(local, id));
  return makesCrossing(q, V, made);
}

// The split made: the input vertex a base vertex again, the old faces' slots and new ones
// the fan about it; the history records it as a removal whose "removed" vertex a stays
// (its fan about a the old faces, as a flip's), the new vertex at the last ring position.
void Flipper::commitSplit(const Quad& q, const Split& split,
                          const std::vector<std::pair<int, Param>>& moved) {
  History& h = s_.history;
  const int record = static_cast<int>(h.removals.size());
  const int inputs = static_cast<int>(s_.baseOf.size());
  const int v = split.added ? inputs + static_cast<int>(s_.added.size()) : split.vertex;
  RemovalRecord r;
  r.vertex = inputOf_[q.a];
  std::array<int, 5> ring;  // local id -> ring position
  if (split.boundary) {
    r.verts = {inputOf_[q.c], inputOf_[q.b], inputOf_[q.a], v};
    r.oldFaces = {h.baseFace[q.f1]};
    r.points = {q.pc, q.pb, Vec2::Zero(), split.at};
    ring = {3, 2, 1, 0, -1};
  } else {
    r.verts = {inputOf_[q.d], inputOf_[q.c], inputOf_[q.b], inputOf_[q.a], v};
    r.oldFaces = {h.baseFace[q.f2], h.baseFace[q.f1]};
    r.points = {q.pd, q.pc, q.pb, Vec2::Zero(), split.at};
    ring = {4, 3, 2, 1, 0};
  }
  const auto fan = split.fan();
  for (const auto& local : fan) r.triangles.push_back(corners(local, ring));
  h.removals.push_back(std::move(r));
  const auto slot = slotsOf(q);
  const int nv = static_cast<int>(s_.base.V.rows());
  s_.base.V.conservativeResize(nv + 1, 3);
  s_.base.V.row(nv) = split.position;
  s_.base.F.conservativeResize(slot.back() + 1, 3);
  h.baseFace.resize(s_.base.F.rows());
  if (split.added)
    s_.added.push_back({nv, split.where});
  else
    s_.baseOf[v] = nv;
  inputOf_.push_back(v);
  if (split.onEdge && !split.boundary) {
    s_.featureEdges.erase(edgeKey(inputOf_[q.a], inputOf_[q.c]));
    s_.featureEdges.insert(edgeKey(inputOf_[q.a], v));
    s_.featureEdges.insert(edgeKey(v, inputOf_[q.c]));
  }
  const std::array<int, 5> id = {nv, q.a, q.b, q.c, q.d};
  for (std::size_t t = 0; t < fan.size(); ++t) {
    const auto made = corners(fan[t], id);
    h.faces.push_back({inputOf_[made[0]], inputOf_[made[1]], inputOf_[made[2]]});
    h.removal.push_back(record);
    h.triangle.push_back(static_cast<int>(t));
    h.baseFace[slot[t]] = static_cast<int>(h.faces.size()) - 1;
    for (int i = 0; i < 3; ++i) s_.base.F(slot[t], i) = made[i];
  }
  for (const auto& [point, param] : moved) s_.params[point] = param;
  indexFaces();
  for (int u : {nv, q.a, q.b, q.c, q.d}) {
    if (u < 0 || inputOf_[u] >= inputs) continue;  // an added point has no Param
    Param& p = s_.params[inputOf_[u]];
    if (u != nv && std::find(slot.begin(), slot.end(), p.face) == slot.end()) continue;
    p.face = facesOf_[u].front();
    for (int i = 0; i < 3; ++i) p.bary[i] = s_.base.F(p.face, i) == u ? 1.0 : 0.0;
  }
}

// The base faces of every base vertex and the points of every base face, afresh.
void Flipper::indexFaces() {
  const int n = static_cast<int>(s_.baseOf.size());
  pointsOf_.assign(s_.base.F.rows(), {});
  for (int v = 0; v < n; ++v)
    if (s_.baseOf[v] < 0) pointsOf_[s_.params[v].face].push_back(v);
  facesOf_.assign(s_.base.V.rows(), {});
  for (Eigen::Index f = 0; f < s_.base.F.rows(); ++f)
    for (int k = 0; k < 3; ++k) facesOf_[s_.base.F(f, k)].push_back(static_cast<int>(f));
}

}  // namespace

BaseFlipReport flipCaps(Simplification& s, const BaseFlipOptions& options) {
  return Flipper(s, options).run(false);
}

BaseFlipReport flipTowardsInput(Simplification& s, const BaseFlipOptions& options) {
  return Flipper(s, options).run(true);
}

BaseFlipReport splitFoldingFaces(Simplification& s, const std::vector<int>& folds,
                                 const BaseFlipOptions& options) {
  return Flipper(s, options).split(folds);
}

}  // namespace osdmra::remeshing
