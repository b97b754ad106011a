#include "osdmra/remesh/simplify.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <tuple>

#include "osdmra/geometry/face_grid.h"
#include "osdmra/geometry/normals.h"
#include "osdmra/geometry/quadric.h"
#include "osdmra/geometry/self_intersection.h"
#include "osdmra/mesh/connectivity.h"
#include "osdmra/remesh/distortion.h"
#include "osdmra/remesh/removal.h"

namespace osdmra::remeshing {

const std::vector<StageLimits> kStages = {
    {2, 15, 1.5},   {3, 15, 1.5},   {4, 12, 1.5},   {6, 10, 1.5},         {8, 10, 1.5},
    {12, 8, 1.875}, {16, 6, 1.875}, {24, 5, 1.875}, {24, 5, 1.875, true}, {24, 5, 1.875, true, 15},
};

namespace {

// A removal worked out but not yet made: the new faces (ring positions) and where
// every point of the old faces goes in them.
struct Plan {
  Ring ring;
  const StageLimits* limits = nullptr;  // of the removed vertex's stage (stageOf)
  int featureAt = -1;
  Flattening flat;
  std::vector<std::array<int, 3>> triangles;
  struct Moved {
    int point, triangle;
    std::array<double, 3> bary;
  };
  std::vector<Moved> moved;
  double error = 0;  // measuredError, under orderByError_
  int vertex(int k) const {
    return ring.verts[k % (ring.boundary ? ring.numFaces() + 1 : ring.numFaces())];
  }
};

// Per vertex, a third of the area of its faces.
std::vector<double> vertexAreas(const TriMesh& m) {
  std::vector<double> area(m.V.rows(), 0.0);
  for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
    const Vec3 a = m.V.row(m.F(f, 0)), b = m.V.row(m.F(f, 1)), c = m.V.row(m.F(f, 2));
    const double third = (b - a).cross(c - a).norm() / 6;
    for (int k = 0; k < 3; ++k) area[m.F(f, k)] += third;
  }
  return area;
}

// The mesh being simplified, with every input vertex's place on it.
class Simplifier {
 public:
  Simplifier(const TriMesh& m, const Features& features, const std::vector<StageLimits>& stages,
             const SimplifyOptions& options)
      : V_(m.V),
        noNewCrossings_(options.noNewCrossings),
        features_(features.edges),
        corner_(features.corner),
        fold_(features.fold),
        stages_(stages),
        stagesPerVertex_(options.stagesPerVertex),
        skinnyWhereFlat_(options.skinnyWhereFlat),
        orderByError_(options.orderByError) {
    const int n = static_cast<int>(m.V.rows());
    if (noNewCrossings_) markInputCrossings(m, options.inputCrossings);
    faces_.reserve(2 * m.F.rows());
    vertFaces_.resize(n);
    inputFaces_.resize(n);
    for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
      addFace({m.F(f, 0), m.F(f, 1), m.F(f, 2)});
      for (int k = 0; k < 3; ++k) inputFaces_[m.F(f, k)].push_back(static_cast<int>(f));
    }
    inputF_ = m.F;
    aliveFaces_ = static_cast<int>(m.F.rows());
    removed_.assign(n, 0);
    param_.resize(n);
    movedStamp_.assign(n, -1);
    movedIndex_.assign(n, -1);
    checkedStamp_.assign(m.F.rows(), -1);
    aroundStamp_.assign(n, -1);
    aroundOf_.resize(n);
    refusedAt_.assign(n, -1);
    refusedStage_.assign(n, -1);
    ownStage_.assign(n, 0);
    changedAt_.assign(n, 0);
    markTips(m, features.tip);
    along_ = lineNeighbours(Connectivity(m.F, static_cast<int>(m.V.rows())), features.list);
    if (options.retriangulateByError || options.orderByError) quadric_ = vertexQuadrics(m);
    if (orderByError_) pointArea_ = vertexAreas(m);
    smallestAngle_.resize(m.F.rows());
    inputFlat_.resize(m.F.rows());
    for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
      const auto flat = layFlat(m.V.row(m.F(f, 0)).transpose(), m.V.row(m.F(f, 1)).transpose(),
                                m.V.row(m.F(f, 2)).transpose());
      smallestAngle_[f] = smallestAngle(flat[0], flat[1], flat[2]) * 180 / kPi;
      inputFlat_[f] = flat;
    }
  }

  void run(int target, const Progress& progress, Simplification& out);
  void result(Simplification& out);

 private:
  // Why plan() refused a vertex, the furthest check reached (the counts make the
  // warning when the base stays larger than asked).
  enum Refusal {
    kShape,
    kPinch,
    kDistortion,
    kTip,
    kCrossing,
    kTopology,
    kCorner,
    kFeatureSide,
    kCurved,
    kBulge,
    kRefusals
  };
  struct Candidate {
    double area, curvature;
    int v;
    double error = 0;  // measuredError of its plan, under orderByError_
  };
  std::vector<Candidate> candidates() const;
  int removeRound(int target, int round, const Progress& progress, int start);
  int addFace(const std::array<int, 3>& t);
  bool ring(int v, Ring& r) const;
  bool isFeature(int a, int b) const { return features_.count(edgeKey(a, b)) != 0; }
  bool removable(int v, const Ring& r) const;
  bool lineBulges(int v, const Ring& r, int end) const;
  bool hasEdge(int a, int b) const;
  bool plan(int v, const Ring& around, Plan& p);
  bool tryTriangulation(int v, Plan& p, double& worst);
  bool retriangulate(int v, Plan& p);
  double triangulationError(int v, const Plan& p) const;
  double measuredError(int v, const Plan& p) const;
  void measureCandidates(std::vector<Candidate>& cands);
  bool skinnyFacesAreFlat(const Plan& p);
  void passOnQuadric(int v, const Ring& ring);
  bool placePoints(int v, Plan& p);
  double distortion(const Plan& p);
  void markTips(const TriMesh& m, const std::vector<char>& tip);
  double largestTipShare(int tip, const Plan* p) const;
  bool unbalancesTips(const Plan& p) const;
  using Box = Eigen::AlignedBox3d;
  bool crossesMesh(const Plan& p) const;
  void gatherNear(const Ring& r) const;
  Box boxOf(const std::array<int, 3>& t) const;
  void indexFaces();
  void markInputCrossings(const TriMesh& m, const CrossingPairs* known);
  void commit(int v, const Plan& p);
  void markChanged(const Ring& ring);
  bool refusedAndUnchanged(int v) const;
  std::string whyKept();
  // The stage whose limits a removal of v meets: the mesh's, or v's own where v was
  // passed over for more important removals (stagesPerVertex).
  std::size_t stageOf(int v) const { return std::max(stage_, std::size_t{ownStage_[v]}); }
  void relaxPassedOver(const std::vector<int>& passedOver);

  const Points& V_;
  bool noNewCrossings_ = false;
  std::unique_ptr<FaceGrid> grid_;  // noNewCrossings_: the live faces, rebuilt each round
  // crossesMesh's candidates for the current plan() (plansMade_ counts the calls).
  mutable std::vector<std::pair<int, Box>> near_;
  mutable std::vector<int> nearIds_;
  mutable int nearOfPlan_ = -1;
  mutable bool nearRingAtCrossing_ = false;
  // noNewCrossings_: per input vertex, whether it is a corner of an input face that
  // crosses another; per face, whether it holds such a vertex (a corner or a point).
  std::vector<char> atInputCrossing_, faceAtCrossing_;
  int plansMade_ = 0;
  Faces inputF_;
  std::vector<std::array<int, 3>> faces_;
  std::vector<char> faceAlive_;
  std::vector<std::vector<int>> vertFaces_, facePoints_, inputFaces_;
  std::vector<Param> param_;
  std::unordered_set<std::uint64_t> features_;
  // Per input vertex, its neighbours along the input's boundary and along its feature
  // lines: the chain a base edge on a line stands for (lineBulges).
  LineNeighbours along_;
  std::vector<char> corner_, fold_, removed_;
  const std::vector<StageLimits>& stages_;
  std::size_t stage_ = 0;
  bool stagesPerVertex_ = false;
  double skinnyWhereFlat_ = 0;
  bool orderByError_ = false;
  std::vector<unsigned char> ownStage_;  // per vertex, under stagesPerVertex_
  std::size_t stageUsed_ = 0;            // the last stage a removal was made under
  int aliveFaces_ = 0, plans_ = 0;
  int refusal_ = kShape;
  std::vector<int> movedStamp_, movedIndex_;
  // SimplifyOptions::retriangulateByError: per vertex, the planes it stands for (empty
  // otherwise).
  std::vector<Quadric> quadric_;
  // SimplifyOptions::orderByError: per input vertex, a third of its faces' area, the
  // share of the surface its distance to the mesh stands for.
  std::vector<double> pointArea_;
  std::vector<double> smallestAngle_;  // per input face, degrees
  // tryTriangulation's and skinnyFacesAreFlat's scratch, kept between plans: per new
  // face, whether it is under its stage's angle, and its unit normal and bound.
  std::vector<char> skinny_;
  std::vector<double> skinnyBound_;
  std::vector<Vec3> skinnyNormal_;
  // Per input face, laid flat once: distortion() measures each against its chart image
  // in many plans, and the input never moves.
  std::vector<std::array<Vec2, 3>> inputFlat_;
  // Per input vertex at the tip of a protrusion (markTips): its cone's faces, each as
  // (next ring vertex, the one after, apex angle); empty elsewhere.
  struct Sector {
    int from, to;
    double angle;
  };
  std::vector<std::vector<Sector>> tipCone_;
  std::vector<int> checkedStamp_;  // per input face: the plan that last checked it
  mutable std::vector<std::array<int, 3>> ringCorners_;  // ring()'s, kept between calls
  // Per vertex: the plan that last listed the faces around it, and that list.
  std::vector<int> aroundStamp_;
  std::vector<std::vector<std::array<int, 3>>> aroundOf_;
  // Refusals remembered (refusedAndUnchanged): per vertex, the number of removals made
  // when it was last refused (-1: never) and the stage then; the number made when a
  // removal was last made within two rings of it.
  int removalsMade_ = 0;
  std::vector<int> refusedAt_, refusedStage_, changedAt_;
  std::vector<RemovalRecord> removals_;
  std::vector<int> removalOf_, triangleOf_;
};

int Simplifier::addFace(const std::array<int, 3>& t) {
  const int f = static_cast<int>(faces_.size());
  faces_.push_back(t);
  faceAlive_.push_back(1);
  if (noNewCrossings_)
    faceAtCrossing_.push_back(std::any_of(t.begin(), t.end(), [&](int v) {
      return atInputCrossing_[static_cast<std::size_t>(v)] != 0;
    }));
  facePoints_.emplace_back();
  removalOf_.push_back(-1);
  triangleOf_.push_back(-1);
  for (int v : t) vertFaces_[v].push_back(f);
  return f;
}

bool Simplifier::ring(int v, Ring& r) const {
  const std::vector<int>& fs = vertFaces_[v];
  const int d = static_cast<int>(fs.size());
  if (d == 0) return false;
  std::vector<std::array<int, 3>>& corner = ringCorners_;  // next, prev, face
  corner.resize(d);
  for (int k = 0; k < d; ++k) {
    const auto& t = faces_[fs[k]];
    const int i = t[0] == v ? 0 : t[1] == v ? 1 : 2;
    corner[k] = {t[(i + 1) % 3], t[(i + 2) % 3], fs[k]};
  }
  int start = 0, starts = 0;
  for (int k = 0; k < d; ++k) {
    bool ends = false;
    for (int q = 0; q < d; ++q) ends = ends || corner[q][1] == corner[k][0];
    if (!ends) {
      start = k;
      ++starts;
    }
  }
  if (starts > 1) return false;
  r.boundary = starts == 1;
  r.verts.clear();
  r.faces.clear();
  int k = start;
  for (int step = 0; step < d; ++step) {
    r.verts.push_back(corner[k][0]);
    r.faces.push_back(corner[k][2]);
    int nextK = -1;
    for (int q = 0; q < d; ++q)
      if (corner[q][0] == corner[k][1]) nextK = q;
    if (step + 1 < d) {
      if (nextK < 0) return false;
      k = nextK;
    } else if (r.boundary) {
      r.verts.push_back(corner[k][1]);
    } else if (nextK != start) {
      return false;
    }
  }
  if (!r.boundary) r.verts.push_back(r.verts.front());  // verts[m] = verts[0]
  return true;
}

bool Simplifier::removable(int v, const Ring& r) const {
  const int m = r.numFaces();
  if (m < 2 || m > 24) return false;
  int nf = 0;
  for (int k = 0; k < m + (r.boundary ? 1 : 0); ++k) nf += isFeature(v, r.verts[k]);
  if (r.boundary) return nf == 0 && !corner_[v];
  return m >= 3 && !corner_[v] && (nf == 0 || nf == 2);
}

// Whether removing v, a vertex of a boundary or feature line (its ring's verts[0] and
// verts[end] its neighbours on it), would leave a base edge standing for a chain of the
// input's line that strays from the edge by over kMaxBulge of the edge's length. The
// base face beside such an edge holds the chain's bulge: a round hole's half circle under
// one edge left base faces whose surface is a crescent along the hole, over which a
// uniform grid folds however the parameterisation is smoothed (odedstein's aeroplane
// with 31 windows). 0.3 lets a round hole keep three base vertices where its own
// vertices let them be about evenly spaced (a third of a circle strays by 0.289 of its
// chord; otherwise it keeps four), but never half of it under one edge.
bool Simplifier::lineBulges(int v, const Ring& r, int end) const {
  constexpr double kMaxBulge = 0.3;
  const std::vector<std::vector<int>>& along = r.boundary ? along_.boundary : along_.feature;
  const Vec3 a = V_.row(r.verts[0]).transpose(), b = V_.row(r.verts[end]).transpose();
  const Vec3 ab = b - a;
  const double length2 = ab.squaredNorm();
  const auto strays = [&](int x) {
    const Vec3 ax = V_.row(x).transpose() - a;
    return ax.cross(ab).squaredNorm() > kMaxBulge * kMaxBulge * length2 * length2;
  };
  if (strays(v)) return true;
  // The removed vertices of the line on either side of v, up to the live vertices
  // that end the chain (the removed ones are no corners: two neighbours each).
  for (int first : along[v]) {
    int previous = v, at = first;
    for (std::size_t step = 0; removed_[at] && step < along.size(); ++step) {
      if (strays(at)) return true;
      if (along[at].size() != 2) break;
      const int next = along[at][0] == previous ? along[at][1] : along[at][0];
      previous = at;
      at = next;
    }
  }
  return false;
}

bool Simplifier::hasEdge(int a, int b) const {
  for (int f : vertFaces_[a])
    for (int x : faces_[f])
      if (x == b) return true;
  return false;
}

// Flattens v's ring, retriangulates it and certifies the result (removal.h); then
// the points of the old faces are placed in the new ones and the distortion checked.
bool Simplifier::plan(int v, const Ring& around, Plan& p) {
  ++plansMade_;
  p.limits = &stages_[stageOf(v)];
  p.ring = around;  // into the plan's lists, kept from plan to plan
  Ring& r = p.ring;
  refusal_ = kCorner;
  if (!removable(v, r)) return false;
  refusal_ = kShape;
  const int m = r.numFaces();
  // Feature line through v: rotate so that verts[0] is one feature neighbour.
  p.featureAt = -1;
  if (!r.boundary) {
    std::vector<int> fi;
    for (int k = 0; k < m; ++k)
      if (isFeature(v, r.verts[k])) fi.push_back(k);
    if (fi.size() == 2) {
      std::rotate(r.verts.begin(), r.verts.begin() + fi[0], r.verts.begin() + m);
      std::rotate(r.faces.begin(), r.faces.begin() + fi[0], r.faces.end());
      r.verts[m] = r.verts[0];
      p.featureAt = fi[1] - fi[0];
      if (p.featureAt < 2 || m - p.featureAt < 2) {  // two faces per side
        refusal_ = kFeatureSide;
        return false;
      }
    }
  }
  std::vector<Vec3> points;
  for (int w : p.ring.verts) points.push_back(V_.row(w).transpose());
  refusal_ = kBulge;
  if (r.boundary ? lineBulges(v, r, m) : p.featureAt > 0 && lineBulges(v, r, p.featureAt))
    return false;
  refusal_ = kShape;
  p.flat = flattenRing(V_.row(v).transpose(), points, p.ring.boundary, p.featureAt);
  // A strongly curved one-ring (a cone tip, a saddle) flattens with much distortion:
  // keep such vertices while flatter ones remain. Folds of a scan go at any exponent.
  const double a = p.flat.exponent;
  if (!fold_[v] && (a > p.limits->power || a < 1 / p.limits->power)) {
    refusal_ = kCurved;
    return false;
  }
  return retriangulate(v, p);
}

// The ring's candidate retriangulations, tried in order, the first certified one kept:
// the ear clipping's, and for a ring without a feature line the fans from each corner.
// By shape (the default), the ear clipping first, then the fans from the corners of
// lowest valence (the first such corner on a tie); by error
// (SimplifyOptions::retriangulateByError), in order of the error each makes.
bool Simplifier::retriangulate(int v, Plan& p) {
  const int numPoints = static_cast<int>(p.flat.points.size());
  const int corners = p.ring.boundary ? numPoints : numPoints - 1;
  const std::vector<std::array<int, 3>> ear =
      triangulateRing(p.flat.points, p.ring.boundary, p.featureAt);
  // Candidate -1 is the ear clipping, k >= 0 the fan from corner k.
  const auto candidate = [&](int k) {
    return k < 0 ? ear : fanOfRing(k, numPoints, p.ring.boundary);
  };
  std::vector<int> order = {-1};
  if (p.featureAt < 0 && corners > 3)
    for (int k = 0; k < corners; ++k) order.push_back(k);
  if (quadric_.empty()) {
    std::stable_sort(order.begin() + 1, order.end(), [&](int x, int y) {
      return vertFaces_[p.vertex(x)].size() < vertFaces_[p.vertex(y)].size();
    });
  } else {
    std::vector<double> error(order.size());  // of candidate k at k + 1
    for (int k : order) {
      p.triangles = candidate(k);
      error[k + 1] = triangulationError(v, p);
    }
    std::stable_sort(order.begin(), order.end(),
                     [&](int x, int y) { return error[x + 1] < error[y + 1]; });
  }
  double worst = 0;
  if (orderByError_) {
    // Every certified candidate measured (measuredError), the least kept.
    int best = -2;
    double least = std::numeric_limits<double>::infinity();
    for (int k : order) {
      p.triangles = candidate(k);
      if (!tryTriangulation(v, p, worst)) continue;
      const double e = measuredError(v, p);
      if (e < least) least = e, best = k;
    }
    if (best > -2) {
      p.triangles = candidate(best);
      p.error = least;
      return tryTriangulation(v, p, worst);  // the same checks again: true
    }
  } else {
    for (int k : order) {
      p.triangles = candidate(k);
      if (tryTriangulation(v, p, worst)) return true;
    }
  }
  // A ring of three: removing v would close a tetrahedron's hole.
  if (p.featureAt < 0 && corners <= 3) refusal_ = kTopology;
  return false;
}

// The squared distance, in v's planes (its quadric), from v's place in the flattened
// ring to the retriangulated surface there: where the new faces cut across the surface
// v stood for, v's planes are far from them. v's place is the origin; a boundary
// vertex's may lie beyond the new faces (its ring's boundary is straightened), and is
// then taken in the nearest one.
double Simplifier::triangulationError(int v, const Plan& p) const {
  double bestMin = -std::numeric_limits<double>::infinity();
  std::array<double, 3> bary{};
  const std::array<int, 3>* at = nullptr;
  for (const auto& t : p.triangles) {
    const Vec2 a = p.flat.points[t[0]], b = p.flat.points[t[1]], c = p.flat.points[t[2]];
    const double area = cross2(b - a, c - a);
    if (!(std::abs(area) > 0)) continue;
    const std::array<double, 3> w = {cross2(b, c) / area, cross2(c, a) / area, cross2(a, b) / area};
    const double least = std::min({w[0], w[1], w[2]});
    if (least > bestMin) {
      bestMin = least;
      bary = w;
      at = &t;
    }
  }
  if (!at) return std::numeric_limits<double>::infinity();
  double sum = 0;
  for (double& w : bary) sum += (w = std::max(w, 0.0));
  Vec3 q = Vec3::Zero();
  for (int i = 0; i < 3; ++i) q += bary[i] / sum * V_.row(p.vertex((*at)[i])).transpose();
  return quadric_[v](q);
}

// Whether every input point that a skinny new face of the plan (skinny_) holds lies within
// skinnyWhereFlat_ of its width from its plane (SimplifyOptions::skinnyWhereFlat). The
// face is the ring's corners in space, not the flattening, since the level of detail is
// that triangle.
bool Simplifier::skinnyFacesAreFlat(const Plan& p) {
  const std::vector<char>& skinny = skinny_;
  std::vector<double>& bound = skinnyBound_;
  std::vector<Vec3>& normal = skinnyNormal_;
  bound.resize(p.triangles.size());
  normal.resize(p.triangles.size());
  for (std::size_t q = 0; q < p.triangles.size(); ++q) {
    if (!skinny[q]) continue;
    const auto& t = p.triangles[q];
    const Vec3 a = V_.row(p.vertex(t[0])).transpose(), b = V_.row(p.vertex(t[1])).transpose(),
               c = V_.row(p.vertex(t[2])).transpose();
    const Vec3 n = (b - a).cross(c - a);
    const double twiceArea = n.norm();
    const double longest = std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()});
    if (!(twiceArea > 0) || !(longest > 0)) return false;
    normal[q] = n / twiceArea;
    bound[q] = skinnyWhereFlat_ * twiceArea / longest;  // a fraction of the width
  }
  for (const Plan::Moved& mv : p.moved) {
    if (!skinny[mv.triangle]) continue;
    const int corner = p.vertex(p.triangles[mv.triangle][0]);
    const double off = normal[mv.triangle].dot((V_.row(mv.point) - V_.row(corner)).transpose());
    if (std::abs(off) > bound[mv.triangle]) return false;
  }
  return true;
}

// A removed vertex's planes go to its ring, shared out evenly, so that the quadrics'
// sum stays the input's and later removals there answer for what this one smoothed.
void Simplifier::passOnQuadric(int v, const Ring& ring) {
  const int n = ring.boundary ? ring.numFaces() + 1 : ring.numFaces();
  for (int k = 0; k < n; ++k) quadric_[ring.verts[k]].add(quadric_[v], 1.0 / n);
}

// Whether the plan's triangulation is certified (removal.h), well shaped in the
// flattening, adds no edge that exists already, and places the old faces' points with
// bounded distortion (`worst`: the largest anisotropy).
bool Simplifier::tryTriangulation(int v, Plan& p, double& worst) {
  if (!isBijective(p.flat, p.triangles, p.ring.boundary)) return false;
  double minAngle = p.limits->flatAngle * kPi / 180;
  if (p.limits->orAsSkinnyAsReplaced)
    for (int k = 0; k < p.ring.numFaces(); ++k)
      minAngle =
          std::min(minAngle, smallestAngle(Vec2::Zero(), p.flat.points[k], p.flat.points[k + 1]));
  // Faces under minAngle but over kSkinnyFloor wait for the flatness test
  // (SimplifyOptions::skinnyWhereFlat), which needs the points placed; skinny_ is
  // cleared only once one is found, off the common path.
  bool anySkinny = false;
  for (std::size_t q = 0; q < p.triangles.size(); ++q) {
    const auto& t = p.triangles[q];
    const double angle =
        smallestAngle(p.flat.points[t[0]], p.flat.points[t[1]], p.flat.points[t[2]]);
    if (angle >= minAngle) continue;
    if (!(skinnyWhereFlat_ > 0) || angle < kSkinnyFloor * kPi / 180) return false;
    if (!anySkinny) skinny_.assign(p.triangles.size(), 0);
    skinny_[q] = 1;
    anySkinny = true;
  }
  // No new edge may exist already (that would pinch the surface: a changed topology).
  const int m = p.ring.numFaces();
  const int closing = p.ring.boundary ? -1 : m;
  for (const auto& t : p.triangles)
    for (int i = 0; i < 3; ++i) {
      const int ka = t[i], kb = t[(i + 1) % 3];
      const int lo = std::min(ka, kb), hi = std::max(ka, kb);
      const bool ringEdge =
          hi - lo == 1 || (lo == 0 && (hi == m - 1 || hi == closing) && !p.ring.boundary);
      const int x = p.vertex(ka), y = p.vertex(kb);
      if (x == y || (!ringEdge && hasEdge(x, y))) {
        refusal_ = std::max(refusal_, static_cast<int>(kPinch));
        return false;
      }
    }
  refusal_ = std::max(refusal_, static_cast<int>(kDistortion));
  if (!placePoints(v, p)) return false;
  if (anySkinny && !skinnyFacesAreFlat(p)) return false;
  worst = fold_[v] ? 1.0 : distortion(p);
  if (worst > p.limits->anisotropy) return false;
  refusal_ = std::max(refusal_, static_cast<int>(kTip));
  if (unbalancesTips(p)) return false;
  refusal_ = std::max(refusal_, static_cast<int>(kCrossing));
  return !crossesMesh(p);
}

// The cones of the tips of protrusions (features.h: kept as corners, and too curved for
// any stage's flattening).
void Simplifier::markTips(const TriMesh& m, const std::vector<char>& tip) {
  tipCone_.assign(static_cast<std::size_t>(m.V.rows()), {});
  for (int v = 0; v < m.V.rows(); ++v) {
    if (!tip[v]) continue;
    std::vector<Sector> cone;
    for (int f : inputFaces_[v]) {
      const int i = m.F(f, 0) == v ? 0 : m.F(f, 1) == v ? 1 : 2;
      cone.push_back({m.F(f, (i + 1) % 3), m.F(f, (i + 2) % 3), faceAngle(m, f, i)});
    }
    Ring r;
    if (ring(v, r)) tipCone_[v] = std::move(cone);
  }
}

// The largest share of tip's cone (its input faces' apex angles) that one face around
// the tip holds, now or (p) once the plan is made. A sector goes to the face holding
// both its far corners; a far corner that is a vertex of the mesh lies on an edge of
// the faces around the tip, and the sector goes to the face holding the other one; a
// sector between two faces is split between them.
double Simplifier::largestTipShare(int tip, const Plan* p) const {
  // Where an input vertex is: -1 a vertex of the mesh, else a face (a plan's new face
  // q as faces_.size() + q).
  const int fresh = static_cast<int>(faces_.size());
  auto holder = [&](int x) {
    if (p && movedStamp_[x] == plans_) return fresh + p->moved[movedIndex_[x]].triangle;
    return removed_[x] ? param_[x].face : -1;
  };
  auto hasTip = [&](int f) {
    if (f < fresh) return std::count(faces_[f].begin(), faces_[f].end(), tip) == 1;
    const auto& t = p->triangles[f - fresh];
    return p->vertex(t[0]) == tip || p->vertex(t[1]) == tip || p->vertex(t[2]) == tip;
  };
  std::vector<std::pair<int, double>> shares;
  auto add = [&](int f, double angle) {
    if (f < 0 || !hasTip(f)) return;
    for (auto& [g, a] : shares)
      if (g == f) {
        a += angle;
        return;
      }
    shares.emplace_back(f, angle);
  };
  double total = 0;
  for (const Sector& s : tipCone_[tip]) {
    total += s.angle;
    const int a = holder(s.from), b = holder(s.to);
    if (a == b || a < 0 || b < 0) {
      add(a < 0 ? b : a, s.angle);
    } else {
      add(a, 0.5 * s.angle);
      add(b, 0.5 * s.angle);
    }
  }
  double largest = 0;
  for (const auto& [f, a] : shares) largest = std::max(largest, a / total);
  return largest;
}

// Whether the plan leaves a face around a tip of the input holding more than half of
// the tip's cone, where none did: the grid then samples the tip from that face's corner
// alone, and its first triangle there, spanning more than half the turn around a
// narrow cone, faces against it (the cow's horn of docs/REMESH.md: seven of its ten
// faces in one base face's corner, the tip's three grid neighbours within 7 degrees
// of each other).
bool Simplifier::unbalancesTips(const Plan& p) const {
  for (std::size_t k = 0; k + (p.ring.boundary ? 0 : 1) < p.ring.verts.size(); ++k) {
    const int t = p.ring.verts[k];
    if (tipCone_[t].empty()) continue;
    const double after = largestTipShare(t, &p);
    if (after > 0.5 && after > largestTipShare(t, nullptr)) return true;
  }
  return false;
}

// With noNewCrossings_: whether a new face of the plan would meet a live face g of the
// mesh (other than the ring's, which it replaces) where it should not
// (trianglesMeet), no face of the ring met g already, and the ring and g do not both
// hold a point where the input crosses itself (markInputCrossings). Refusing such
// removals keeps the mesh from crossing itself where the input does not, by
// construction: a coarse base over a thin part otherwise can (the lion's over 105
// faces: 3 pairs), and the J-fold split and a level of detail near the base inherit it.
bool Simplifier::crossesMesh(const Plan& p) const {
  if (!grid_) return false;
  if (nearOfPlan_ != plansMade_) gatherNear(p.ring);
  for (const auto& q : p.triangles) {
    const std::array<int, 3> t = {p.vertex(q[0]), p.vertex(q[1]), p.vertex(q[2])};
    const Box box = boxOf(t);
    for (const auto& [g, gBox] : near_) {
      if (!box.intersects(gBox) || !trianglesMeet(V_, t, faces_[g])) continue;
      const bool inherited = (nearRingAtCrossing_ && faceAtCrossing_[g]) ||
                             std::any_of(p.ring.faces.begin(), p.ring.faces.end(), [&](int f) {
                               return trianglesMeet(V_, faces_[f], faces_[g]);
                             });
      if (!inherited) return true;
    }
  }
  return false;
}

// The live faces other than the ring's whose boxes meet the ring's, once for all the
// triangulations plan() tries: every new face lies in the box of the ring's corners.
void Simplifier::gatherNear(const Ring& r) const {
  nearOfPlan_ = plansMade_;
  nearRingAtCrossing_ =
      std::any_of(r.faces.begin(), r.faces.end(), [&](int f) { return faceAtCrossing_[f] != 0; });
  Box ringBox;
  for (int w : r.verts) ringBox.extend(V_.row(w).transpose());
  grid_->near(ringBox.min(), ringBox.max(), nearIds_);
  near_.clear();
  for (int g : nearIds_) {
    if (!faceAlive_[g] || std::find(r.faces.begin(), r.faces.end(), g) != r.faces.end()) continue;
    const Box gBox = boxOf(faces_[g]);
    if (gBox.intersects(ringBox)) near_.emplace_back(g, gBox);
  }
}

// A face's bounding box, grown by a relative margin beyond trianglesMeet's tolerance
// so that the box test never rejects a pair the exact test would count.
Simplifier::Box Simplifier::boxOf(const std::array<int, 3>& t) const {
  Box b;
  for (int x : t) b.extend(V_.row(x).transpose());
  const double margin =
      1e-9 * (b.diagonal().norm() + b.max().cwiseAbs().maxCoeff() + b.min().cwiseAbs().maxCoeff());
  return Box(b.min().array() - margin, b.max().array() + margin);
}

// Where the input crosses itself, the base may too: a removal whose faces hold a point
// of an input face that crosses another may cross faces that hold one (the cow, the
// ogre: refused, such removals left their bases a third larger than without the check,
// and the knots where two sheets cross are the input's either way).
void Simplifier::markInputCrossings(const TriMesh& m, const CrossingPairs* known) {
  atInputCrossing_.assign(static_cast<std::size_t>(m.V.rows()), 0);
  CrossingPairs found;
  for (const auto& pair : crossingPairs(m, known, found))
    for (int f : pair)
      for (int k = 0; k < 3; ++k) atInputCrossing_[static_cast<std::size_t>(m.F(f, k))] = 1;
}

// The live faces in a grid of cells the size of their mean edge (a face meets a few
// cells, a cell holds a few faces), made again each round as the faces grow.
void Simplifier::indexFaces() {
  double length = 0;
  int edges = 0;
  for (std::size_t f = 0; f < faces_.size(); ++f)
    if (faceAlive_[f])
      for (int k = 0; k < 3; ++k, ++edges)
        length += (V_.row(faces_[f][k]) - V_.row(faces_[f][(k + 1) % 3])).norm();
  grid_ = std::make_unique<FaceGrid>(V_, edges > 0 && length > 0 ? length / edges : 1.0);
  for (std::size_t f = 0; f < faces_.size(); ++f)
    if (faceAlive_[f]) grid_->insert(static_cast<int>(f), faces_[f]);
  grid_->freeze();
}

// Every parameterised point of the old faces, and v itself (the origin), at its place
// in the new faces. By the certificate each lies in one of them; a point that does not
// (rounding gone wrong) refuses the removal rather than be snapped.
bool Simplifier::placePoints(int v, Plan& p) {
  ++plans_;
  p.moved.clear();
  auto place = [&](int point, const Vec2& at) {
    std::array<double, 3> bary;
    const int q = locateInTriangles(at, p.flat.points, p.triangles, bary);
    if (q < 0) return false;
    movedStamp_[point] = plans_;
    movedIndex_[point] = static_cast<int>(p.moved.size());
    p.moved.push_back({point, q, bary});
    return true;
  };
  if (!place(v, Vec2::Zero())) return false;
  for (int k = 0; k < p.ring.numFaces(); ++k) {
    const int f = p.ring.faces[k];
    auto flatOf = [&](int x) -> Vec2 {
      if (x == v) return Vec2::Zero();
      return x == p.ring.verts[k] ? p.flat.points[k] : p.flat.points[k + 1];
    };
    for (int point : facePoints_[f]) {
      Vec2 at = Vec2::Zero();
      for (int i = 0; i < 3; ++i) at += param_[point].bary[i] * flatOf(faces_[f][i]);
      if (!place(point, at)) return false;
    }
  }
  return true;
}

// The largest anisotropy of the input triangles with a corner among the moved points,
// each mapped onto the faces that hold its corners, laid flat (chartImage; infinite once
// over the stage's bound, or for a triangle with no chart: none is left unchecked).
double Simplifier::distortion(const Plan& p) {
  auto newFace = [&](int q) -> std::array<int, 3> {
    const auto& t = p.triangles[q];
    return {p.vertex(t[0]), p.vertex(t[1]), p.vertex(t[2])};
  };
  auto place = [&](int x) -> Placed {
    if (movedStamp_[x] == plans_) {
      const Plan::Moved& mv = p.moved[movedIndex_[x]];
      return {false, -1, newFace(mv.triangle), mv.bary};
    }
    if (!removed_[x]) return {true, x, {}, {}};
    return {false, -1, faces_[param_[x].face], param_[x].bary};
  };
  // The faces around vertex w once the plan is made: the new ones and the others. Listed
  // once per plan and vertex (the charts of neighbouring triangles ask for the same).
  const FacesAround facesAround = [&](int w, std::vector<std::array<int, 3>>& out) {
    std::vector<std::array<int, 3>>& around = aroundOf_[w];
    if (aroundStamp_[w] != plans_) {
      aroundStamp_[w] = plans_;
      around.clear();
      for (int f : vertFaces_[w])
        if (std::find(p.ring.faces.begin(), p.ring.faces.end(), f) == p.ring.faces.end())
          around.push_back(faces_[f]);
      for (std::size_t q = 0; q < p.triangles.size(); ++q) {
        const std::array<int, 3> f = newFace(static_cast<int>(q));
        if (std::count(f.begin(), f.end(), w) == 1) around.push_back(f);
      }
    }
    out.insert(out.end(), around.begin(), around.end());
  };
  double worst = 1;
  for (const Plan::Moved& mv : p.moved)
    for (int t : inputFaces_[mv.point]) {
      if (checkedStamp_[t] == plans_) continue;  // met through another moved corner
      checkedStamp_[t] = plans_;
      const std::array<Placed, 3> at = {place(inputF_(t, 0)), place(inputF_(t, 1)),
                                        place(inputF_(t, 2))};
      std::array<Vec2, 3> image;
      if (!chartImage(V_, at, facesAround, image)) return std::numeric_limits<double>::infinity();
      const double a = anisotropyFromFlat(inputFlat_[t], image);
      if (smallestAngle_[t] < p.limits->sliverAngle && a < std::numeric_limits<double>::infinity())
        continue;
      if (!(a <= p.limits->anisotropy)) return std::numeric_limits<double>::infinity();
      worst = std::max(worst, a);
    }
  return worst;
}

void Simplifier::commit(int v, const Plan& p) {
  for (int f : p.ring.faces) {
    faceAlive_[f] = 0;
    for (int x : faces_[f]) {
      auto& list = vertFaces_[x];
      list.erase(std::find(list.begin(), list.end(), f));
    }
  }
  std::vector<int> newFaces;
  const int record = static_cast<int>(removals_.size());
  removals_.push_back({v, p.ring.verts, p.ring.faces, p.flat.points, p.triangles});
  for (std::size_t q = 0; q < p.triangles.size(); ++q) {
    const auto& t = p.triangles[q];
    newFaces.push_back(addFace({p.vertex(t[0]), p.vertex(t[1]), p.vertex(t[2])}));
    if (grid_) grid_->insert(newFaces.back(), faces_[newFaces.back()]);
    removalOf_.back() = record;
    triangleOf_.back() = static_cast<int>(q);
  }
  for (const Plan::Moved& mv : p.moved) {
    param_[mv.point] = {newFaces[mv.triangle], mv.bary};
    facePoints_[newFaces[mv.triangle]].push_back(mv.point);
    if (noNewCrossings_ && atInputCrossing_[mv.point]) faceAtCrossing_[newFaces[mv.triangle]] = 1;
  }
  for (int f : p.ring.faces) std::vector<int>().swap(facePoints_[f]);
  removed_[v] = 1;
  if (!quadric_.empty()) passOnQuadric(v, p.ring);
  if (p.featureAt >= 0) {
    features_.erase(edgeKey(v, p.ring.verts[0]));
    features_.erase(edgeKey(v, p.ring.verts[p.featureAt]));
    features_.insert(edgeKey(p.ring.verts[0], p.ring.verts[p.featureAt]));
  }
  aliveFaces_ += static_cast<int>(p.triangles.size()) - p.ring.numFaces();
}

// Removable vertices with their importance: one-ring area, and curvature (the angle
// defect, for cone tips, plus the bending across the spokes, angle between
// neighbouring faces times length, over the one-ring's extent, for ridges such as the
// rim of a thin flap, which have no defect but bend sharply).
std::vector<Simplifier::Candidate> Simplifier::candidates() const {
  std::vector<Candidate> cands;
  Ring r;  // its lists and the normals' kept from vertex to vertex
  std::vector<Vec3> normals;
  for (int v = 0; v < V_.rows(); ++v) {
    if (removed_[v] || !ring(v, r) || !removable(v, r)) continue;
    double area = 0, angles = 0, bending = 0, extent = 0;
    const Vec3 pv = V_.row(v);
    const int m = r.numFaces();
    normals.resize(m);
    for (int k = 0; k < m; ++k) {
      const Vec3 a = V_.row(r.verts[k]) - pv.transpose(),
                 b = V_.row(r.verts[k + 1]) - pv.transpose();
      area += 0.5 * a.cross(b).norm();
      angles += angleBetween(a, b);
      normals[k] = a.cross(b).normalized();
    }
    for (int k = 0; k < m; ++k) {
      const double len = (V_.row(r.verts[k]) - pv.transpose()).norm();
      extent = std::max(extent, len);
      if (k > 0 || !r.boundary) {
        const Vec3& n0 = normals[(k + m - 1) % m];
        bending += angleBetween(n0, normals[k]) * len;
      }
    }
    const double curv =
        std::abs((r.boundary ? kPi : 2 * kPi) - angles) + bending / std::max(extent, 1e-300);
    cands.push_back({area, fold_[v] ? 0.0 : curv, v});
  }
  return cands;
}

// SimplifyOptions::orderByError: how much farther apart the input and the mesh are once
// the plan is made, as sums of squared distances weighted by area. One way, every point
// the plan moves (its input vertex against its place on the mesh: the map's distance,
// after minus before); the other, four points of each new face against the place on the
// old faces that the flattening puts under them (the surface's own move). The first
// alone missed new faces that hold no input point but cut across a bend: the head's
// whole-budget base at 16,098 faces came 1.24e-4 of the diagonal from its input (RMS)
// with it, 7.3e-5 with both (docs/LOD.md).
double Simplifier::measuredError(int v, const Plan& p) const {
  auto at = [&](const std::array<int, 3>& f, const std::array<double, 3>& b) -> Vec3 {
    return b[0] * V_.row(f[0]).transpose() + b[1] * V_.row(f[1]).transpose() +
           b[2] * V_.row(f[2]).transpose();
  };
  double change = 0;
  for (const Plan::Moved& mv : p.moved) {
    const Vec3 x = V_.row(mv.point).transpose();
    const auto& t = p.triangles[mv.triangle];
    const Vec3 after = at({p.vertex(t[0]), p.vertex(t[1]), p.vertex(t[2])}, mv.bary);
    change += pointArea_[mv.point] * (x - after).squaredNorm();
    if (mv.point == v) continue;  // on the mesh until now
    const Vec3 before = at(faces_[param_[mv.point].face], param_[mv.point].bary);
    change -= pointArea_[mv.point] * (x - before).squaredNorm();
  }
  static constexpr double kSamples[4][3] = {{1.0 / 3, 1.0 / 3, 1.0 / 3},
                                            {2.0 / 3, 1.0 / 6, 1.0 / 6},
                                            {1.0 / 6, 2.0 / 3, 1.0 / 6},
                                            {1.0 / 6, 1.0 / 6, 2.0 / 3}};
  const int m = p.ring.numFaces();
  for (const auto& t : p.triangles) {
    const std::array<int, 3> corners = {p.vertex(t[0]), p.vertex(t[1]), p.vertex(t[2])};
    const Vec3 c0 = V_.row(corners[0]), c1 = V_.row(corners[1]), c2 = V_.row(corners[2]);
    const double quarter = (c1 - c0).cross(c2 - c0).norm() / 8;
    for (const auto& w : kSamples) {
      const Vec2 flat =
          w[0] * p.flat.points[t[0]] + w[1] * p.flat.points[t[1]] + w[2] * p.flat.points[t[2]];
      // The old face (origin, points[k], points[k + 1]) the sample is least outside of: a
      // boundary ring's new faces may reach past its fan.
      int best = 0;
      std::array<double, 3> fan{-1e300, 0, 0};
      for (int k = 0; k < m; ++k) {
        const auto b = barycentric(flat, Vec2::Zero(), p.flat.points[k], p.flat.points[k + 1]);
        if (minOf(b) > minOf(fan)) fan = b, best = k;
      }
      const Vec3 onOld = at({v, p.vertex(best), p.vertex(best + 1)}, fan);
      change += quarter * (at(corners, {w[0], w[1], w[2]}) - onOld).squaredNorm();
    }
  }
  return change;
}

// After a removal: every vertex within two rings of the removed one (one of its ring)
// may plan differently now.
void Simplifier::markChanged(const Ring& ring) {
  ++removalsMade_;
  for (int w : ring.verts)
    for (int f : vertFaces_[w])
      for (int x : faces_[f]) changedAt_[x] = removalsMade_;
}

// Whether v was refused under the current stage and no removal within two rings of it
// was made since: planned again, it would be refused again (its ring, its faces'
// points, the edges a retriangulation could repeat and the faces holding the corners of
// the input triangles it moves lie within a ring of its ring; a refusal for a crossing
// is not remembered). Where most vertices left are refused round after round, the plans
// were most of the simplification (beetle-alt: 162,862 plans for 19,000 removals over
// 155 rounds).
bool Simplifier::refusedAndUnchanged(int v) const {
  return refusedAt_[v] >= 0 && refusedStage_[v] == static_cast<int>(stageOf(v)) &&
         changedAt_[v] <= refusedAt_[v];
}

// SimplifyOptions::orderByError: each candidate's error, its removal planned
// (measuredError); infinite where it is refused, a fold of the input's 0 (those go first).
void Simplifier::measureCandidates(std::vector<Candidate>& cands) {
  Ring r;
  Plan p;
  for (Candidate& c : cands) {
    if (fold_[c.v]) continue;
    const bool planned = !refusedAndUnchanged(c.v) && ring(c.v, r) && plan(c.v, r, p);
    c.error = planned ? p.error : std::numeric_limits<double>::infinity();
  }
}

// One round: an independent set of removals, by priority. Returns how many were made.
int Simplifier::removeRound(int target, int round, const Progress& progress, int start) {
  std::vector<Candidate> cands = candidates();
  if (noNewCrossings_) indexFaces();
  if (orderByError_) measureCandidates(cands);
  double maxArea = 0, maxCurv = 0;
  for (const Candidate& c : cands) {
    maxArea = std::max(maxArea, c.area);
    maxCurv = std::max(maxCurv, c.curvature);
  }
  // Weight of the area term: 0.3 met the error targets on the scans of docs/REMESH.md;
  // 0.5 (MAPS's choice) left the bunny's ears undersampled.
  constexpr double kAreaWeight = 0.3;
  auto priority = [&](const Candidate& c) {
    return kAreaWeight * c.area / std::max(maxArea, 1e-300) +
           (1 - kAreaWeight) * c.curvature / std::max(maxCurv, 1e-300);
  };
  // Each priority computed once, not at every comparison of the sort: the error first
  // under orderByError_ (0 otherwise), then area and curvature.
  std::vector<std::tuple<double, double, int>> order;
  order.reserve(cands.size());
  for (const Candidate& c : cands) order.emplace_back(c.error, priority(c), c.v);
  std::sort(order.begin(), order.end());
  std::vector<int> stamp(V_.rows(), -1);
  int removedNow = 0;
  // Refused under the limits of their stage (not for topology, features or tips), and
  // those of them after which a more important removal was made.
  std::vector<int> refusedNow, passedOver;
  Ring r;  // the ring and the plan keep their lists from candidate to candidate
  Plan p;
  // Under orderByError_ a round goes no further down its order than the removals it needs
  // (two faces each): where it went on until it had them, the neighbours that the
  // cheapest removals keep out of the round left it the dearest ones, and the head's
  // base at 16,098 faces came 1.72e-4 of the diagonal from its input (RMS), against
  // 1.24e-4 so (docs/LOD.md). Those passed over wait for the next round, measured again.
  const std::size_t depth =
      orderByError_ ? std::max<std::size_t>(1, static_cast<std::size_t>(aliveFaces_ - target) / 2)
                    : order.size();
  std::size_t walked = 0;
  for (const auto& entry : order) {
    const int v = std::get<2>(entry);
    if (aliveFaces_ <= target || walked++ >= depth) break;
    if (stamp[v] == round) continue;
    if (refusedAndUnchanged(v)) continue;
    const bool disc = ring(v, r);
    if (!disc || !plan(v, r, p)) {
      // A crossing depends on faces near in space, not in the mesh: planned again.
      if (!disc || refusal_ != kCrossing) {
        refusedAt_[v] = removalsMade_;
        refusedStage_[v] = static_cast<int>(stageOf(v));
      }
      if (disc && (refusal_ == kShape || refusal_ == kDistortion || refusal_ == kCurved))
        refusedNow.push_back(v);
      continue;
    }
    commit(v, p);
    stageUsed_ = std::max(stageUsed_, stageOf(v));
    passedOver.insert(passedOver.end(), refusedNow.begin(), refusedNow.end());
    refusedNow.clear();
    markChanged(p.ring);
    ++removedNow;
    for (int w : p.ring.verts) stamp[w] = round;
    if (progress && removedNow % 1024 == 0)
      progress("simplify", double(start - aliveFaces_) / std::max(1, start - target));
  }
  if (stagesPerVertex_) relaxPassedOver(passedOver);
  return removedNow;
}

// Each vertex that its stage's limits kept while a more important one went goes on
// under the next stage's: the order of removal follows importance, not which removals
// the strictest limits allow. Mesh-wide, a refused vertex waits until no vertex at all
// can go, and the target is reached by removing the important ones instead (the camel
// head's 1% base kept its mouth and ear and lost its skull's curvature).
void Simplifier::relaxPassedOver(const std::vector<int>& passedOver) {
  for (int v : passedOver)
    ownStage_[v] = static_cast<unsigned char>(std::min(stages_.size() - 1, stageOf(v) + 1));
}

void Simplifier::run(int target, const Progress& progress, Simplification& out) {
  const int start = aliveFaces_;
  int round = 0;
  while (aliveFaces_ > target) {
    // Under orderByError_, a round removes at most half of what is left to remove, so
    // that the last rounds, not only the last one, go greedily by error.
    const int excess = aliveFaces_ - target;
    const int roundTarget = orderByError_ && excess > 4 ? aliveFaces_ - excess / 2 : target;
    const int removedNow = removeRound(roundTarget, round++, progress, start);
    if (progress) progress("simplify", double(start - aliveFaces_) / std::max(1, start - target));
    if (removedNow > 0) continue;
    if (stage_ + 1 >= stages_.size()) break;
    ++stage_;  // nothing can go under these limits: relax them
  }
  out.rounds = round;
  out.stage = static_cast<int>(std::max(stage_, stageUsed_));
  if (aliveFaces_ > target) out.stopReason = whyKept();
  if (progress) progress("simplify", 1.0);
}

// Why every vertex left is kept, counted by reason: the warning a user gets when the
// base stays larger than asked, so that they know what to change (the feature angle,
// the input's tips, its slivers).
std::string Simplifier::whyKept() {
  std::array<int, kRefusals> count{};
  int left = 0;
  for (int v = 0; v < V_.rows(); ++v) {
    if (removed_[v]) continue;
    ++left;
    Ring r;
    Plan p;
    if (!ring(v, r)) {
      ++count[kTopology];
    } else if (plan(v, r, p)) {
      ++count[kShape];  // unreachable once the stages are spent; counted, not hidden
    } else {
      ++count[refusal_];
    }
  }
  static const char* const kWhy[kRefusals] = {
      "no retriangulation of their one-ring has every angle above the last stage's bound",
      "every retriangulation would join two vertices already joined (a pinch)",
      "removing them would distort the parameterisation beyond the last stage's bounds",
      "removing them would leave one base face holding more than half the cone of a tip of "
      "the input (a vertex whose faces' angles sum to under 192 degrees)",
      "their removal would make the base cross itself",
      "their removal would change the topology (a one-ring of three faces, or not a disc)",
      "they are corners or ends of feature lines, corners of boundaries, tips of the input "
      "(faces' angles summing to under 192 degrees), or have over 24 faces",
      "a feature line through them would keep one face on a side",
      "their one-ring is too curved to flatten (a tip under 192 degrees, or a saddle)",
      "the boundary or feature line their removal would put under one base edge strays from "
      "that edge by over 0.3 of its length"};
  std::string why = "no vertex can be removed: of the " + std::to_string(left) + " left,";
  bool first = true;
  for (int k = 0; k < kRefusals; ++k)
    if (count[k] > 0) {
      why += std::string(first ? " " : "; ") + std::to_string(count[k]) + " because " + kWhy[k];
      first = false;
    }
  return why;
}

void Simplifier::result(Simplification& out) {
  const int n = static_cast<int>(V_.rows());
  out.baseOf.assign(n, -1);
  std::vector<int> faceIndex(faces_.size(), -1);
  int nf = 0, nv = 0;
  for (std::size_t f = 0; f < faces_.size(); ++f)
    if (faceAlive_[f]) faceIndex[f] = nf++;
  for (int v = 0; v < n; ++v)
    if (!removed_[v]) out.baseOf[v] = nv++;
  out.base.V.resize(nv, 3);
  out.base.F.resize(nf, 3);
  for (int v = 0; v < n; ++v)
    if (out.baseOf[v] >= 0) out.base.V.row(out.baseOf[v]) = V_.row(v);
  for (std::size_t f = 0; f < faces_.size(); ++f)
    if (faceAlive_[f])
      for (int i = 0; i < 3; ++i) out.base.F(faceIndex[f], i) = out.baseOf[faces_[f][i]];
  out.params.assign(n, Param());
  for (int v = 0; v < n; ++v) {
    if (removed_[v]) {
      out.params[v] = {faceIndex[param_[v].face], param_[v].bary};
    } else {
      const int f = vertFaces_[v].front();
      Param p{faceIndex[f], {0, 0, 0}};
      for (int i = 0; i < 3; ++i) p.bary[i] = faces_[f][i] == v ? 1.0 : 0.0;
      out.params[v] = p;
    }
  }
  out.featureEdges = features_;
  History& h = out.history;
  h.faces = faces_;
  h.removal = std::move(removalOf_);
  h.triangle = std::move(triangleOf_);
  h.removals = std::move(removals_);
  h.baseFace.assign(nf, -1);
  for (std::size_t f = 0; f < faces_.size(); ++f)
    if (faceAlive_[f]) h.baseFace[faceIndex[f]] = static_cast<int>(f);
}

}  // namespace

std::vector<int> historyIdsOfBase(const Simplification& s) {
  const int inputs = static_cast<int>(s.baseOf.size());
  std::vector<int> id(s.base.V.rows(), -1);
  for (int v = 0; v < inputs; ++v)
    if (s.baseOf[v] >= 0) id[s.baseOf[v]] = v;
  for (std::size_t k = 0; k < s.added.size(); ++k)
    id[s.added[k].base] = inputs + static_cast<int>(k);
  return id;
}

namespace {
// A barycentric coordinate above this is inside a fan triangle beyond rounding.
constexpr double kClearOfTheSides = 1e-9;
}  // namespace

SurfacePoint traceToInput(const History& h, int baseFace, const std::array<double, 3>& bary) {
  int f = h.baseFace[baseFace];
  std::array<double, 3> b = bary;
  while (h.removal[f] >= 0) {
    const RemovalRecord& r = h.removals[h.removal[f]];
    const std::array<int, 3>& t = r.triangles[h.triangle[f]];
    const Vec2 at = b[0] * r.points[t[0]] + b[1] * r.points[t[1]] + b[2] * r.points[t[2]];
    // The fan triangle (origin, points[k], points[k+1]) that holds it: old face k. The
    // fan's triangles do not overlap, so one that holds it clear of its sides is the
    // one (every other has a coordinate below zero): first the one whose wedge about
    // the origin holds its direction, then, near a side, the one it is least outside of.
    const int m = static_cast<int>(r.oldFaces.size());
    int best = 0;
    std::array<double, 3> fan{-1e300, 0, 0};
    for (int k = 0; k < m; ++k)
      if (cross2(r.points[k], at) >= 0 && cross2(at, r.points[k + 1]) > 0) {
        fan = barycentric(at, Vec2::Zero(), r.points[k], r.points[k + 1]);
        best = k;
        break;
      }
    if (!(minOf(fan) > kClearOfTheSides)) {
      fan = {-1e300, 0, 0};
      for (int k = 0; k < m; ++k) {
        const auto c = barycentric(at, Vec2::Zero(), r.points[k], r.points[k + 1]);
        if (minOf(c) > minOf(fan)) fan = c, best = k;
        if (minOf(fan) > kClearOfTheSides) break;
      }
    }
    const std::array<double, 3> on = clampedBarycentric(fan);
    const int corners[3] = {r.vertex, r.verts[best], r.verts[best + 1]};
    f = r.oldFaces[best];
    for (int i = 0; i < 3; ++i) {
      b[i] = 0;
      for (int c = 0; c < 3; ++c)
        if (h.faces[f][i] == corners[c]) b[i] = on[c];
    }
  }
  return {f, b};
}

Simplification simplify(const TriMesh& input, const Features& features, int targetFaces,
                        const Progress& progress, const std::vector<StageLimits>& stages,
                        const SimplifyOptions& options) {
  Simplifier s(input, features, stages, options);
  Simplification out;
  s.run(targetFaces, progress, out);
  s.result(out);
  return out;
}

}  // namespace osdmra::remeshing
