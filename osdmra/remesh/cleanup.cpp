#include "osdmra/remesh/cleanup.h"

#include <Eigen/Geometry>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>
#include <vector>

#include "osdmra/geometry/distance.h"
#include "osdmra/geometry/normals.h"
#include "osdmra/geometry/self_intersection.h"
#include "osdmra/mesh/connectivity.h"
#include "osdmra/remesh/planar.h"
#include "osdmra/remesh/untangle.h"

namespace osdmra::remeshing {

namespace {

// A point of the input: triangle and barycentric coordinates (triangle -1: none).
using Where = SurfacePoint;

// Output triangle `t` (corners, sampled at `where`) faces against the input triangles
// under each of its corners, or has an area of at most `tinyArea`.
bool folded(const TriMesh& m, const std::vector<Where>& where, const std::array<int, 3>& t,
            const TriMesh& input, const Connectivity& inputConn, double tinyArea,
            bool& degenerate) {
  return foldedAgainst(input, inputConn, {m.V.row(t[0]), m.V.row(t[1]), m.V.row(t[2])},
                       {where[t[0]], where[t[1]], where[t[2]]}, tinyArea, degenerate);
}

// The disks of the clean-up's second stage solve for at most this many times the grid's
// points in all. Over a small grid a disk of 16 rings is the whole surface: with
// thousands of defects (a 3,072-face torus displaced until it crosses itself 11,532
// times, over 20 base faces at J = 4) each disk was a solve over the whole surface,
// defect after defect. Over the scans of docs/REMESH.md the disks stay below it.
constexpr long long kDiskBudget = 64;

// The disks of at most this many rings whose flattening is untangled where Tutte's
// folds, in at most this many rounds (embedInPlane()). A larger disk that folds in the
// plane is mostly one whose boundary overlaps itself there, and untangling it is in
// vain: on the decimated knight over 300 faces at J = 5, thousands of them went through
// every round for the same remesh in the end (2.0 s without untangling, 3.9 s up to 3
// rings, 5.7 s up to 4, 130 s up to 16); the bunny over 150 at J = 5 came out clean
// with any of these.
constexpr int kUntangledRings = 3;
constexpr int kUntangleInPlaneRounds = 32;

// And those untanglings place at most this many points per grid point in all. On inputs
// that cross themselves most disks fold and stay folded: unbounded, they took the
// remeshes of alecjacobson's beetle and suzanne over 150 faces at J = 5 from 8.3 and
// 5.7 s to 18.5 and 14.9 s, for the same remeshes as with this bound (16.7 and 8.3 s,
// and 7.9 and 4.2 s once deepestPoint() solved its triples by Cramer's rule).
constexpr long long kPlaneUntangleBudget = 1;

// And the untangling moves at most this many points per grid point in all: over the
// scans of docs/REMESH.md and their decimated and noisy copies it moved at most 0.25
// per grid point; on an input that crosses itself thousands of times its rounds went on
// over tens of thousands of faces for minutes.
constexpr long long kUntangleBudget = 1;

// No repair may make an edge longer than this many times the mean edge of the grid over
// the base faces around either end, as sampled. The repairs' own tests (orientation
// against the input under each corner, crossings nearby) do not see a point lifted onto
// another part of the surface: alecjacobson's beetle-alt over 134 faces at J = 5 came out
// with edges 200 times its grid's mean edge and 8.9% of the diagonal from its input. Over
// the shared scans' remeshes (150 and 600 faces at J = 5) edges reach at most 10 times
// that mean (the decimated knight's, where a coarse input's tips are sampled).
constexpr double kLongestRepairedEdge = 16;

// The faces around each vertex: faces[start[v]], ..., faces[start[v + 1] - 1], in face
// order (a cheap incidence list; Connectivity also orders them, at more cost).
struct FacesAround {
  std::vector<int> start, faces;
};
FacesAround facesAround(const Faces& F, Eigen::Index numVertices) {
  FacesAround out{std::vector<int>(numVertices + 1, 0), std::vector<int>(3 * F.rows())};
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) ++out.start[F(f, k) + 1];
  for (Eigen::Index v = 0; v < numVertices; ++v) out.start[v + 1] += out.start[v];
  std::vector<int> fill(out.start.begin(), out.start.end() - 1);
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) out.faces[fill[F(f, k)]++] = static_cast<int>(f);
  return out;
}

template <class T>
void sortUnique(std::vector<T>& v) {
  std::sort(v.begin(), v.end());
  v.erase(std::unique(v.begin(), v.end()), v.end());
}

// A tangent plane: an origin and two unit axes orthogonal to the normal.
struct Plane {
  Vec3 origin, e1, e2;
  Plane(const Vec3& o, const Vec3& normal)
      : origin(o), e1(normal.unitOrthogonal()), e2(normal.cross(e1)) {}
  Vec2 flat(const Vec3& x) const { return Vec2((x - origin).dot(e1), (x - origin).dot(e2)); }
};

// kLongestRepairedEdge times the mean edge of the grid over each base face (base face b
// holds grid faces b * perBase .. (b + 1) * perBase - 1), per grid point the largest of
// its base faces'.
std::vector<double> edgeReach(const TriMesh& grid, Eigen::Index perBase) {
  const Eigen::Index numBase = grid.F.rows() / perBase;
  std::vector<double> reach(grid.V.rows(), 0.0);
  for (Eigen::Index b = 0; b < numBase; ++b) {
    double sum = 0;
    for (Eigen::Index f = b * perBase; f < (b + 1) * perBase; ++f)
      for (int k = 0; k < 3; ++k)
        sum += (grid.V.row(grid.F(f, k)) - grid.V.row(grid.F(f, (k + 1) % 3))).norm();
    const double r = kLongestRepairedEdge * sum / double(3 * perBase);
    for (Eigen::Index f = b * perBase; f < (b + 1) * perBase; ++f)
      for (int k = 0; k < 3; ++k) reach[grid.F(f, k)] = std::max(reach[grid.F(f, k)], r);
  }
  return reach;
}

// The clean-up of one remeshing, stage by stage (see cleanup.h). The remeshed surface
// m and the samples' places on the input change together; everything else is fixed.
class Cleaner {
 public:
  Cleaner(Remeshing& out, const TriMesh& input, const std::vector<char>& free,
          const std::vector<long long>& line, std::vector<Where>& where,
          const SurfaceWalker& walker, const CrossingPairs* inputCrossings);

  void run(const Progress& progress, const std::function<void()>& lastResort);

 private:
  // Reports the clean-up's progress. The repairs can run for seconds on inputs that
  // cross themselves: they report as they go (and a caller may abandon them so, by
  // throwing from the callback: remesh() does with a grid map it no longer needs).
  void report(double fraction) const {
    if (progress_) progress_("clean-up", fraction);
  }
  Progress progress_;

  // What counts as a defect, and how good a vertex's triangles are.
  Vec3 reference(int v) const;
  bool badCorners(int i, int j, int k, bool& degenerate) const;
  bool bad(Eigen::Index f, bool& degenerate) const;
  bool bad(Eigen::Index f) const;
  bool faceCrosses(Eigen::Index f) const;
  bool defective(Eigen::Index f) const { return bad(f) || faceCrosses(f); }
  int crossings(int v) const;
  std::pair<int, double> quality(int v) const;
  void updateCrossings();
  bool foldedTogether(int a, int b) const;
  // What an input face's crossing is (atInputCrossing): 1 a fold, 2 two sheets.
  enum InputCrossing : char { kNone, kFold, kSheets };
  bool atInputCrossing(Eigen::Index f, InputCrossing kind);
  // A pair at the input's crossings, reported as its own.
  bool inputsOwn(const std::array<int, 2>& pair) {
    return atInputCrossing(pair[0], kFold) && atInputCrossing(pair[1], kFold);
  }
  // A pair where two sheets of the input cross, which the repairs leave alone.
  bool sheetsCross(const std::array<int, 2>& pair) {
    return atInputCrossing(pair[0], kSheets) && atInputCrossing(pair[1], kSheets);
  }
  long long reportCrossings();
  long long countDefects();
  double farthest(const std::vector<char>& relaxFace) const;
  void countBad();

  // Moving points on the input.
  void touch(int v) {
    if (!isTouched_[v]) isTouched_[v] = 1, touched_.push_back(v);
  }
  void setPoint(int v, const Vec3& x, const Where& w);
  std::vector<int> patchAround(const Plane& plane, const std::vector<int>& seeds, double radius);
  bool lift(const Plane& plane, const std::vector<int>& seeds, double radius,
            const std::vector<Vec2>& points, const std::vector<int>& movers, std::vector<Vec3>& to,
            std::vector<Where>& found);
  bool moveIfGood(const std::vector<int>& movers, const std::vector<Vec3>& to,
                  const std::vector<Where>& found);

  // The stages.
  void projectNearBadTriangles();
  // What a disk of resampleDisk() came to: its points moved; not, but a larger disk
  // may do; not, and a larger one will not either.
  enum class Disk { moved, tryLarger, stop };
  Disk resampleDisk(int center, int k);
  bool embedInPlane(const std::vector<int>& inner, const std::vector<int>& order,
                    const Plane& plane, Eigen::MatrixX2d& uv, int k);
  bool placeInKernel(int v);
  int triangleOf(int a, int b) const;
  bool alongBoundary(const Where& at, int direction, double distance, Where& to, Vec3& x) const;
  bool slide(int v);
  void repair(double from, double to);
  std::vector<int> relax(const std::vector<char>& relaxFace);
  void relaxWhatIsLeft(const std::function<void()>& lastResort);

  Remeshing& out_;
  TriMesh& m_;
  const TriMesh& input_;
  const std::vector<char>& free_;
  const std::vector<long long>& line_;
  std::vector<Where>& where_;
  const SurfaceWalker& walker_;
  const TriangleBvh bvh_;
  const double diag_, tinyArea_;
  const Points sampled_;
  const VertexRings rings_, inputRings_;
  const Points vertexNormals_;
  const FacesAround inputAround_, outputAround_;
  const int numBase_;
  const Eigen::Index perBase_;
  // Per grid point, kLongestRepairedEdge times the longest mean sampled edge of the base
  // faces around it: how long a repair may make an edge of it (quality()).
  const std::vector<double> reach_;
  // Scratch marks: input triangles and vertices visited by lift number `lifts_`, and a
  // disk's rings and local numbering in resampleDisk.
  std::vector<int> triangleStamp_, vertexStamp_;
  int lifts_ = 0;
  std::vector<int> dist_, local_;
  // Grid points the disks of resampleDisk may still solve for, and moves the untangling
  // may still try, over the whole clean-up.
  long long diskBudget_ = 0, untangleBudget_ = 0, planeBudget_ = 0;
  bool diskOverBudget_ = false;  // a disk was refused for the budget since last cleared
  // Faces still to repair, and the faces of the last count of defects.
  std::vector<Eigen::Index> left_, flagged_;
  // The crossing pairs (f < g, sorted) as of the points touched_ since they were counted.
  CrossingPairs crossings_;
  bool crossingsKnown_ = false;
  // Input faces that cross another face of the input, and the faces around their
  // corners: InputCrossing (atInputCrossing); found once, when the output first has
  // crossing pairs; from the input's crossing pairs, given (cleanUp's inputCrossings) or
  // found then.
  std::vector<char> inputCrossing_;
  const CrossingPairs* givenInputCrossings_;
  std::vector<int> touched_;
  std::vector<char> isTouched_;
  // Per output vertex, the faces within two rings of it (crossings), once asked for.
  mutable std::vector<std::vector<int>> facesNear_;
};

Cleaner::Cleaner(Remeshing& out, const TriMesh& input, const std::vector<char>& free,
                 const std::vector<long long>& line, std::vector<Where>& where,
                 const SurfaceWalker& walker, const CrossingPairs* inputCrossings)
    : out_(out),
      m_(out.mesh),
      input_(input),
      free_(free),
      line_(line),
      where_(where),
      walker_(walker),
      bvh_(input),
      diag_(boundingBoxDiagonal(input.V)),
      tinyArea_(tinyAreaFor(diag_)),
      sampled_(out.mesh.V),
      rings_(out.mesh.F, static_cast<int>(out.mesh.V.rows())),
      inputRings_(input.F, static_cast<int>(input.V.rows())),
      vertexNormals_(vertexNormalSums(input)),
      inputAround_(facesAround(input.F, input.V.rows())),
      outputAround_(facesAround(out.mesh.F, out.mesh.V.rows())),
      numBase_(static_cast<int>(out.base.V.rows())),
      perBase_(out.mesh.F.rows() / out.base.F.rows()),
      reach_(edgeReach(out.mesh, perBase_)),
      triangleStamp_(input.F.rows(), -1),
      vertexStamp_(input.V.rows(), -1),
      dist_(out.mesh.V.rows(), -1),
      local_(out.mesh.V.rows(), -1),
      diskBudget_(kDiskBudget * static_cast<long long>(out.mesh.V.rows())),
      untangleBudget_(kUntangleBudget * static_cast<long long>(out.mesh.V.rows())),
      planeBudget_(kPlaneUntangleBudget * static_cast<long long>(out.mesh.V.rows())),
      givenInputCrossings_(inputCrossings),
      isTouched_(out.mesh.V.rows(), 0),
      facesNear_(out.mesh.V.rows()) {}

// The smoother reference of the repairs: the input's area-weighted vertex normals
// interpolated where v was sampled.
Vec3 Cleaner::reference(int v) const {
  const Where& w = where_[v];
  Vec3 n = Vec3::Zero();
  if (w.triangle >= 0)
    for (int k = 0; k < 3; ++k)
      n += std::max(w.bary[k], 0.0) * vertexNormals_.row(input_.F(w.triangle, k)).transpose();
  return n;
}

// A grid triangle is flipped when it faces against the input triangles under each of its
// corners (where they were sampled): unambiguous even on thin parts, where the nearest
// input point may lie on the other side, and on a coarse input, where interpolated
// vertex normals can point away from the very face a sample lies in.
bool Cleaner::badCorners(int i, int j, int k, bool& degenerate) const {
  return folded(m_, where_, {i, j, k}, input_, walker_.connectivity(), tinyArea_, degenerate);
}

bool Cleaner::bad(Eigen::Index f, bool& degenerate) const {
  return badCorners(m_.F(f, 0), m_.F(f, 1), m_.F(f, 2), degenerate);
}

bool Cleaner::bad(Eigen::Index f) const {
  bool degenerate = false;
  return bad(f, degenerate);
}

// Whether face f crosses a face around one of its corners' neighbours.
bool Cleaner::faceCrosses(Eigen::Index f) const {
  const std::vector<int>&start = outputAround_.start, &at = outputAround_.faces;
  for (int k = 0; k < 3; ++k)
    for (int w : rings_.ring(m_.F(f, k)))
      for (int q = start[w]; q < start[w + 1]; ++q)
        if (at[q] != f && trianglesMeet(m_.V, {m_.F(f, 0), m_.F(f, 1), m_.F(f, 2)},
                                        {m_.F(at[q], 0), m_.F(at[q], 1), m_.F(at[q], 2)}))
          return true;
  return false;
}

// The crossings of v's faces with the faces within two rings of v (what a move of v
// could come to cross).
int Cleaner::crossings(int v) const {
  const std::vector<int>&start = outputAround_.start, &at = outputAround_.faces;
  // The faces within two rings depend on the connectivity alone, which the clean-up
  // keeps: gathered once per vertex (the untangling asks again at every trial move).
  std::vector<int>& around = facesNear_[v];
  if (around.empty()) {
    for (int q = start[v]; q < start[v + 1]; ++q)
      for (int k = 0; k < 3; ++k)
        for (int w : rings_.ring(m_.F(at[q], k)))
          for (int r = start[w]; r < start[w + 1]; ++r) around.push_back(at[r]);
    sortUnique(around);
  }
  // Faces whose boxes lie apart by more than a billionth of their sizes do not meet
  // (trianglesMeet's tolerances reach a trillionth): most pairs end at the boxes.
  auto boxOf = [&](int f) {
    Eigen::AlignedBox3d box;
    for (int k = 0; k < 3; ++k) box.extend(m_.V.row(m_.F(f, k)).transpose());
    return box;
  };
  auto apart = [](const Eigen::AlignedBox3d& a, const Eigen::AlignedBox3d& b) {
    const double margin = 1e-9 * (a.sizes().maxCoeff() + b.sizes().maxCoeff());
    return ((a.min().array() - margin) > b.max().array()).any() ||
           ((b.min().array() - margin) > a.max().array()).any();
  };
  std::vector<Eigen::AlignedBox3d> boxes(around.size());
  for (std::size_t i = 0; i < around.size(); ++i) boxes[i] = boxOf(around[i]);
  int count = 0;
  for (int q = start[v]; q < start[v + 1]; ++q) {
    const int f = at[q];
    const Eigen::AlignedBox3d box = boxOf(f);
    for (std::size_t i = 0; i < around.size(); ++i) {
      const int g = around[i];
      count += g != f && !apart(box, boxes[i]) &&
               trianglesMeet(m_.V, {m_.F(f, 0), m_.F(f, 1), m_.F(f, 2)},
                             {m_.F(g, 0), m_.F(g, 1), m_.F(g, 2)});
    }
  }
  return count;
}

// How good the triangles around v are: fewer bad ones (turned over, of zero area, or
// crossing a triangle nearby) and edges longer than their ends' reach first, then the
// worst one's signed sine against the reference. A zero-area triangle counts twice: a
// move that trades two flipped triangles for one (a point lifted onto the input's edge
// in line with two others) leaves a defect that no later move sees a side of (the bunny
// over 300 faces at J = 5, after 10 smoothing sweeps: one such triangle left, and the
// exact map run for it).
std::pair<int, double> Cleaner::quality(int v) const {
  const IndexSpan ring = rings_.ring(v);
  const int last = rings_.isBoundaryVertex(v) ? ring.size() - 1 : ring.size();
  double worst = std::numeric_limits<double>::infinity();
  int numBad = crossings(v);
  for (int a : ring) numBad += (m_.V.row(v) - m_.V.row(a)).norm() > std::max(reach_[v], reach_[a]);
  for (int j = 0; j < last; ++j) {
    const int a = ring[j], b = ring[(j + 1) % ring.size()];
    bool degenerate = false;
    numBad += badCorners(v, a, b, degenerate) ? (degenerate ? 2 : 1) : 0;
    const Vec3 x = m_.V.row(v), p = m_.V.row(a), q = m_.V.row(b);
    const Vec3 r = reference(v) + reference(a) + reference(b);
    const double scale = (p - x).norm() * (q - x).norm() * r.norm();
    worst = std::min(worst, scale > 0 ? (p - x).cross(q - x).dot(r) / scale : 0.0);
  }
  return std::make_pair(-numBad, worst);
}

// The crossing pairs over the whole surface, near each other or not (a sheet through
// another part of the surface is not a defect that the repairs' local tests see). The
// first count tests every pair; later ones keep the pairs of faces that did not move
// since and test only the faces around the points moved.
void Cleaner::updateCrossings() {
  if (!crossingsKnown_) {
    crossings_ = crossingPairs(m_);
    crossingsKnown_ = true;
  } else {
    std::vector<char> moved(static_cast<std::size_t>(m_.F.rows()), 0);
    std::vector<int> faces;
    for (int v : touched_)
      for (int q = outputAround_.start[v]; q < outputAround_.start[v + 1]; ++q)
        if (!moved[outputAround_.faces[q]]) {
          moved[outputAround_.faces[q]] = 1;
          faces.push_back(outputAround_.faces[q]);
        }
    CrossingPairs kept;
    for (const auto& pair : crossings_)
      if (!moved[pair[0]] && !moved[pair[1]]) kept.push_back(pair);
    const CrossingPairs fresh = selfIntersectionsWith(m_, faces);
    crossings_.clear();
    std::merge(kept.begin(), kept.end(), fresh.begin(), fresh.end(),
               std::back_inserter(crossings_));
  }
  for (int v : touched_) isTouched_[v] = 0;
  touched_.clear();
}

// Whether input faces a and b are a few faces apart: a corner of b is a corner of a face
// around a corner of a. Crossing so, they are a fold of a scan (a vertex dragged over its
// neighbour), which sampling over it removes; farther apart, two sheets cross.
bool Cleaner::foldedTogether(int a, int b) const {
  const auto& start = inputAround_.start;
  const auto& at = inputAround_.faces;
  for (int k = 0; k < 3; ++k)
    for (int q = start[input_.F(a, k)]; q < start[input_.F(a, k) + 1]; ++q)
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
          if (input_.F(at[q], i) == input_.F(b, j)) return true;
  return false;
}

// Whether output face f stands where the input crosses itself, as `kind` at least: one
// of its corners was sampled on an input face that crosses another, or shares a corner
// with one. A pair of such faces crossing is the input's own crossing, sampled, and is
// reported apart. Where two sheets cross (faces not folded together), no placement of
// points on the input undoes it (a teapot's spout through its body), so the repairs
// leave it alone instead of spending their budgets on it; a fold they still try, as
// sampling over it can lie flat (a crumple of a scan as fine as the grid cannot).
bool Cleaner::atInputCrossing(Eigen::Index f, InputCrossing kind) {
  if (inputCrossing_.empty()) {
    inputCrossing_.assign(static_cast<std::size_t>(input_.F.rows()), kNone);
    const auto& start = inputAround_.start;
    const auto& at = inputAround_.faces;
    CrossingPairs found;
    for (const auto& pair : crossingPairs(input_, givenInputCrossings_, found)) {
      const char mark = foldedTogether(pair[0], pair[1]) ? kFold : kSheets;
      for (int g : pair)
        for (int k = 0; k < 3; ++k)
          for (int q = start[input_.F(g, k)]; q < start[input_.F(g, k) + 1]; ++q)
            inputCrossing_[at[q]] = std::max(inputCrossing_[at[q]], mark);
    }
  }
  for (int k = 0; k < 3; ++k) {
    const int t = where_[m_.F(f, k)].triangle;
    if (t >= 0 && inputCrossing_[t] >= kind) return true;
  }
  return false;
}

// Sets the crossing counts reported from crossings_; returns the pairs the repairs
// work on (not where two sheets of the input cross).
long long Cleaner::reportCrossings() {
  long long own = 0, sheets = 0;
  for (const auto& pair : crossings_) {
    own += inputsOwn(pair);
    sheets += sheetsCross(pair);
  }
  out_.selfIntersections = static_cast<long long>(crossings_.size());
  out_.selfIntersectionsAtInputCrossings = own;
  out_.selfIntersectionsWhereSheetsCross = sheets;
  return out_.selfIntersections - sheets;
}

// What is left over the whole surface: the bad faces and the faces of crossing pairs
// that are not the input's own, kept in flagged_; their number. Sets the counts of
// crossing pairs reported.
long long Cleaner::countDefects() {
  updateCrossings();
  long long count = reportCrossings();
  flagged_.clear();
  for (const auto& pair : crossings_)
    if (!sheetsCross(pair)) flagged_.insert(flagged_.end(), pair.begin(), pair.end());
  for (Eigen::Index f = 0; f < m_.F.rows(); ++f)
    if (bad(f)) {
      flagged_.push_back(f);
      ++count;
    }
  return count;
}

// How far the relaxed faces stray from the input: the largest distance of one of their
// centroids to it.
double Cleaner::farthest(const std::vector<char>& relaxFace) const {
  double d = 0;
  for (Eigen::Index f = 0; f < m_.F.rows(); ++f)
    if (relaxFace[f / perBase_]) {
      const Vec3 c =
          (m_.V.row(m_.F(f, 0)) + m_.V.row(m_.F(f, 1)) + m_.V.row(m_.F(f, 2))).transpose();
      d = std::max(d, bvh_.closestPoint(c / 3).distance);
    }
  return d;
}

void Cleaner::countBad() {
  out_.flippedTriangles = out_.degenerateTriangles = 0;
  for (Eigen::Index f = 0; f < m_.F.rows(); ++f) {
    bool degenerate = false;
    if (bad(f, degenerate)) ++(degenerate ? out_.degenerateTriangles : out_.flippedTriangles);
  }
}

void Cleaner::setPoint(int v, const Vec3& x, const Where& w) {
  touch(v);
  m_.V.row(v) = x.transpose();
  where_[v] = w;
}

// The input triangles reachable from where `seeds` were sampled, within `radius` of the
// plane's origin.
std::vector<int> Cleaner::patchAround(const Plane& plane, const std::vector<int>& seeds,
                                      double radius) {
  ++lifts_;
  std::vector<int> patch, stack;
  auto visit = [&](int t) {
    if (t >= 0 && triangleStamp_[t] != lifts_) {
      triangleStamp_[t] = lifts_;
      stack.push_back(t);
    }
  };
  for (int v : seeds) visit(where_[v].triangle);
  while (!stack.empty()) {
    const int t = stack.back();
    stack.pop_back();
    bool close = false;
    for (int c = 0; c < 3; ++c)
      close = close || (input_.V.row(input_.F(t, c)).transpose() - plane.origin).norm() <= radius;
    if (!close) continue;
    patch.push_back(t);
    for (int c = 0; c < 3; ++c) {
      const int x = input_.F(t, c);
      if (vertexStamp_[x] == lifts_) continue;
      vertexStamp_[x] = lifts_;
      for (int q = inputAround_.start[x]; q < inputAround_.start[x + 1]; ++q)
        visit(inputAround_.faces[q]);
    }
  }
  return patch;
}

// Lifts points[i] of the plane onto the input for output vertex movers[i]: among the
// input triangles of patchAround() facing the plane, the one above the point nearest to
// the vertex's old position; above none (off an edge of the surface, or over a gap
// between its layers), the nearest one's edge. False if some point has none.
bool Cleaner::lift(const Plane& plane, const std::vector<int>& seeds, double radius,
                   const std::vector<Vec2>& points, const std::vector<int>& movers,
                   std::vector<Vec3>& to, std::vector<Where>& found) {
  const std::vector<int> patch = patchAround(plane, seeds, radius);
  to.assign(points.size(), Vec3::Zero());
  found.assign(points.size(), Where());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Vec3 old = m_.V.row(movers[i]);
    double best = std::numeric_limits<double>::infinity(), closest = -0.5;
    for (int t : patch) {
      const Vec3 a = input_.V.row(input_.F(t, 0)), b = input_.V.row(input_.F(t, 1)),
                 c = input_.V.row(input_.F(t, 2));
      const Vec2 fa = plane.flat(a), fb = plane.flat(b), fc = plane.flat(c);
      if (cross2(fb - fa, fc - fa) <= 0) continue;  // facing away from the plane
      const auto bary = barycentric(points[i], fa, fb, fc);
      const bool inside = minOf(bary) >= -1e-12;
      if (!inside && (std::isfinite(best) || minOf(bary) <= closest)) continue;
      const auto on = clampedBarycentric(bary);
      const Vec3 x = on[0] * a + on[1] * b + on[2] * c;
      if (inside && (x - old).norm() >= best) continue;
      if (inside)
        best = (x - old).norm();
      else
        closest = minOf(bary);
      to[i] = x;
      found[i] = {t, on};
    }
    if (found[i].triangle < 0) return false;
  }
  return true;
}

// Moves the movers, unless a triangle around one of them comes out bad or crosses one
// nearby.
bool Cleaner::moveIfGood(const std::vector<int>& movers, const std::vector<Vec3>& to,
                         const std::vector<Where>& found) {
  std::vector<Vec3> oldPosition(movers.size());
  std::vector<Where> oldWhere(movers.size());
  for (std::size_t i = 0; i < movers.size(); ++i) {
    oldPosition[i] = m_.V.row(movers[i]);
    oldWhere[i] = where_[movers[i]];
    setPoint(movers[i], to[i], found[i]);
  }
  bool good = true;
  for (std::size_t i = 0; i < movers.size() && good; ++i) good = quality(movers[i]).first == 0;
  if (!good)
    for (std::size_t i = 0; i < movers.size(); ++i)
      setPoint(movers[i], oldPosition[i], oldWhere[i]);
  return good;
}

// First stage, in rounds: the free corners of bad triangles and their free neighbours
// move together to the input point nearest to their neighbours' centroid, unless that
// point faces the other way; the next round looks at the triangles around what moved
// and those still bad. Counts the bad triangles as it goes.
void Cleaner::projectNearBadTriangles() {
  std::vector<Eigen::Index> suspects(static_cast<std::size_t>(m_.F.rows()));
  for (Eigen::Index f = 0; f < m_.F.rows(); ++f) suspects[f] = f;
  constexpr int kRounds = 12;
  std::vector<int> stamp(m_.V.rows(), -1), near(m_.V.rows(), -1);
  for (int round = 0;; ++round) {
    report(0.1 * std::min(1.0, double(round) / kRounds));
    std::vector<Eigen::Index> still;
    out_.flippedTriangles = out_.degenerateTriangles = 0;
    for (Eigen::Index f : suspects) {
      bool degenerate = false;
      if (!bad(f, degenerate)) continue;
      still.push_back(f);
      ++(degenerate ? out_.degenerateTriangles : out_.flippedTriangles);
    }
    if (round == 0) out_.cleanupDefectsBefore = out_.flippedTriangles + out_.degenerateTriangles;
    if (still.empty() || round == kRounds) break;
    std::vector<int> moving;
    auto add = [&](int v) {
      if (free_[v] && stamp[v] != round) {
        stamp[v] = round;
        moving.push_back(v);
      }
    };
    for (Eigen::Index f : still)
      for (int k = 0; k < 3; ++k) {
        add(m_.F(f, k));
        for (int w : rings_.ring(m_.F(f, k))) add(w);
      }
    std::vector<Vec3> to(moving.size());
    std::vector<Where> at(moving.size());
    for (std::size_t i = 0; i < moving.size(); ++i) {
      Vec3 c = Vec3::Zero();
      const IndexSpan ring = rings_.ring(moving[i]);
      for (int w : ring) c += m_.V.row(w).transpose();
      const ClosestPoint cp = bvh_.closestPoint(c / std::max(1, ring.size()));
      if (faceNormal(input_, cp.face).dot(reference(moving[i])) <= 0) continue;  // the far side
      std::array<double, 3> bary;
      if (!barycentricIn(input_, cp.face, cp.point, bary)) continue;
      to[i] = cp.point;
      at[i] = {cp.face, bary};
    }
    for (std::size_t i = 0; i < moving.size(); ++i)
      if (at[i].triangle >= 0) setPoint(moving[i], to[i], at[i]);
    for (int v : moving)
      for (int w : rings_.ring(v)) near[w] = round;
    for (Eigen::Index f : still)
      for (int k = 0; k < 3; ++k) near[m_.F(f, k)] = round;
    suspects.clear();
    for (Eigen::Index f = 0; f < m_.F.rows(); ++f)
      if (near[m_.F(f, 0)] == round || near[m_.F(f, 1)] == round || near[m_.F(f, 2)] == round)
        suspects.push_back(f);
  }
}

// Second stage: the grid points within k rings of `center` (a corner of a bad
// triangle, the base vertex if one is) go to Tutte's embedding in the tangent plane
// there (each the average of its grid neighbours; the points k rings away and those
// held in place stay), lifted back onto the input triangles nearby that face the
// plane. Where the input is a height field over the plane that keeps the orientation;
// the move is kept only if no triangle around the moved points is bad afterwards. The
// base vertex at the centre moves too unless a feature or boundary runs through it:
// the grid around it says where the middle of its neighbourhood is.
Cleaner::Disk Cleaner::resampleDisk(int center, int k) {
  std::vector<int> order{center};
  dist_[center] = 0;
  for (std::size_t q = 0; q < order.size(); ++q) {
    if (dist_[order[q]] == k) continue;
    for (int w : rings_.ring(order[q]))
      if (dist_[w] < 0) {
        dist_[w] = dist_[order[q]] + 1;
        order.push_back(w);
      }
  }
  auto movable = [&](int v) {
    if (free_[v]) return true;
    if (v != center || v >= numBase_ || rings_.isBoundaryVertex(v)) return false;
    for (int w : rings_.ring(v))
      if (!free_[w]) return false;
    return true;
  };
  std::vector<int> inner;
  for (int v : order)
    if (dist_[v] < k && movable(v)) {
      local_[v] = static_cast<int>(inner.size());
      inner.push_back(v);
    }
  struct Reset {
    std::vector<int>& d;
    std::vector<int>& l;
    const std::vector<int>& o;
    ~Reset() {
      for (int v : o) d[v] = l[v] = -1;
    }
  } reset{dist_, local_, order};
  if (inner.empty()) return Disk::tryLarger;
  if (static_cast<long long>(inner.size()) > diskBudget_) {
    diskOverBudget_ = true;
    return Disk::tryLarger;
  }
  diskBudget_ -= static_cast<long long>(inner.size());
  Vec3 normal = reference(center);
  for (int v : inner) normal += reference(v);
  if (!(normal.norm() > 0)) return Disk::tryLarger;
  normal.normalize();
  // Lifting the embedding back needs the surface to be a height field over the plane:
  // where it turns away from it within k rings, it does within larger disks too. (On
  // the beast of docs/REMESH.md such disks were 63% of the disks' unknowns and 3 of
  // them in 37,337 came out embedded and better; on Nefertiti 20%, 2 in 2,907. A scan's
  // noise turns points away too: on the noisy copies of the corpus a few disks stopped
  // so would have been mended by larger ones.)
  for (int v : order)
    if (reference(v).dot(normal) <= 0) return Disk::stop;
  const Plane plane(m_.V.row(center).transpose(), normal);
  const int ni = static_cast<int>(inner.size());
  std::vector<Eigen::Triplet<double>> entries;
  Eigen::MatrixX2d rhs = Eigen::MatrixX2d::Zero(ni, 2);
  for (int i = 0; i < ni; ++i) {
    const IndexSpan ring = rings_.ring(inner[i]);
    entries.emplace_back(i, i, double(ring.size()));
    for (int w : ring)
      if (local_[w] >= 0)
        entries.emplace_back(i, local_[w], -1.0);
      else
        rhs.row(i) += plane.flat(m_.V.row(w).transpose()).transpose();
  }
  Eigen::SparseMatrix<double> A(ni, ni);
  A.setFromTriplets(entries.begin(), entries.end());
  const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(A);
  Eigen::MatrixX2d uv = solver.solve(rhs);
  if (solver.info() != Eigen::Success || !uv.allFinite() ||
      !embedInPlane(inner, order, plane, uv, k))
    return Disk::tryLarger;
  double radius = 0;
  for (int v : order) radius = std::max(radius, (m_.V.row(v).transpose() - plane.origin).norm());
  std::vector<Vec2> points(ni);
  for (int i = 0; i < ni; ++i) points[i] = uv.row(i).transpose();
  std::vector<Vec3> to;
  std::vector<Where> found;
  return lift(plane, order, 1.5 * radius, points, inner, to, found) && moveIfGood(inner, to, found)
             ? Disk::moved
             : Disk::tryLarger;
}

// Whether the flattening `uv` of a disk of k rings (rows: `inner`, in local_'s order;
// `order`: every point of the disk) is an embedding, positive around every inner point,
// or can be made one. Tutte's embedding is one only inside a convex boundary, and a
// disk's boundary flattened from a curved or rough surface is not: the bunny over 150
// faces at J = 5 kept a flipped triangle whose every disk, of 2 to 16 rings, came out
// folded in the plane and was never lifted. Where a disk of up to kUntangledRings rings
// folds, it is untangled in the plane (untangle.h) and `uv` updated.
bool Cleaner::embedInPlane(const std::vector<int>& inner, const std::vector<int>& order,
                           const Plane& plane, Eigen::MatrixX2d& uv, int k) {
  PlanarFans fans;
  fans.points.reserve(order.size());
  for (Eigen::Index i = 0; i < uv.rows(); ++i) fans.points.push_back(uv.row(i).transpose());
  // The disk's other points numbered after the inner ones (local_ is reset for all of
  // `order` when the disk is done).
  for (int v : order)
    if (local_[v] < 0) {
      local_[v] = static_cast<int>(fans.points.size());
      fans.points.push_back(plane.flat(m_.V.row(v).transpose()));
    }
  for (int v : inner) {
    fans.movers.push_back(local_[v]);
    for (int w : rings_.ring(v)) fans.ring.push_back(local_[w]);
    fans.ringStart.push_back(static_cast<int>(fans.ring.size()));
    fans.closed.push_back(!rings_.isBoundaryVertex(v));
  }
  if (embedded(fans)) return true;
  if (k > kUntangledRings || !untangle(fans, kUntangleInPlaneRounds, planeBudget_)) return false;
  for (Eigen::Index i = 0; i < uv.rows(); ++i) uv.row(i) = fans.points[i].transpose();
  return true;
}

// Third stage (Freitag and Plassmann's untangling, on the surface): one point at a time
// to where the worst of its triangles is best in its tangent plane: the largest t with
// every ring edge at least t to its left. With t > 0 that is inside the ring's kernel
// and all its triangles come out positive; short of that the move is kept if it makes
// the worst of them less bad, and the rounds go on. Only the point's own triangles
// change.
bool Cleaner::placeInKernel(int v) {
  const IndexSpan ring = rings_.ring(v);
  const bool closed = !rings_.isBoundaryVertex(v);
  const int last = closed ? ring.size() : ring.size() - 1;
  Vec3 normal = reference(v);
  for (int w : ring) normal += reference(w);
  if (last < 2 || !(normal.norm() > 0)) return false;
  const Plane plane(m_.V.row(v).transpose(), normal.normalized());
  std::vector<Vec2> around;
  double extent = 0;  // as deepestInFan() bounds the kernel: the starts of its edges
  for (int j = 0; j < ring.size(); ++j) {
    around.push_back(plane.flat(m_.V.row(ring[j]).transpose()));
    if (j < last) extent = std::max(extent, around.back().norm());
  }
  Vec2 best = Vec2::Zero();
  double bestT = 0;
  if (!deepestInFan(around, closed, best, bestT)) return false;
  std::vector<int> seeds(ring.begin(), ring.end());
  seeds.push_back(v);
  std::vector<Vec3> to;
  std::vector<Where> found;
  if (!lift(plane, seeds, 1.5 * extent, {best}, {v}, to, found)) return false;
  if (bestT > 0 && moveIfGood({v}, to, found)) return true;
  const auto before = quality(v);
  const Vec3 oldPosition = m_.V.row(v);
  const Where oldWhere = where_[v];
  setPoint(v, to[0], found[0]);
  if (quality(v) > before) return true;
  setPoint(v, oldPosition, oldWhere);
  return false;
}

// The input triangle with edge (a, b), or -1.
int Cleaner::triangleOf(int a, int b) const {
  for (int q = inputAround_.start[a]; q < inputAround_.start[a + 1]; ++q) {
    const int t = inputAround_.faces[q];
    for (int k = 0; k < 3; ++k)
      if (input_.F(t, k) == b) return t;
  }
  return -1;
}

// From the boundary point `at`, `distance` along the input's boundary (direction +1:
// the way of its outgoing boundary edges). False if `at` is not on a boundary.
bool Cleaner::alongBoundary(const Where& at, int direction, double distance, Where& to,
                            Vec3& x) const {
  if (at.triangle < 0) return false;
  // The boundary edge (a, b) it lies on, at fraction s from a, a -> b along `direction`.
  int a = -1, b = -1;
  double s = 0;
  for (int k = 0; k < 3 && a < 0; ++k) {
    const int p = input_.F(at.triangle, k), q = input_.F(at.triangle, (k + 1) % 3);
    const int r = (k + 2) % 3;
    if (at.bary[r] > 1e-9 || !inputRings_.isBoundaryVertex(p) || !inputRings_.isBoundaryVertex(q))
      continue;
    const IndexSpan ring = inputRings_.ring(p);
    const bool outgoing = ring[0] == q, incoming = ring[ring.size() - 1] == q;
    if (!outgoing && !incoming) continue;
    const double wq = at.bary[(k + 1) % 3] / std::max(at.bary[k] + at.bary[(k + 1) % 3], 1e-300);
    if (outgoing == (direction > 0)) {
      a = p, b = q, s = wq;
    } else {
      a = q, b = p, s = 1 - wq;
    }
  }
  if (a < 0) return false;
  for (int guard = 0; guard < 64; ++guard) {
    const Vec3 pa = input_.V.row(a), pb = input_.V.row(b);
    const double length = (pb - pa).norm(), left = (1 - s) * length;
    if (distance <= left || guard == 63) {
      const double t = length > 0 ? std::min(1.0, s + distance / length) : 1.0;
      x = (1 - t) * pa + t * pb;
      to.triangle = triangleOf(a, b);
      if (to.triangle < 0) return false;
      to.bary = {0, 0, 0};
      for (int k = 0; k < 3; ++k) {
        if (input_.F(to.triangle, k) == a) to.bary[k] = 1 - t;
        if (input_.F(to.triangle, k) == b) to.bary[k] = t;
      }
      return true;
    }
    distance -= left;
    const IndexSpan ring = inputRings_.ring(b);
    const int next = direction > 0 ? ring[0] : ring[ring.size() - 1];
    a = b;
    b = next;
    s = 0;
  }
  return false;
}

// A point held on a feature line or a boundary (not a base vertex, but for one on a
// boundary alone) may still slide along it: along the input's boundary, or towards
// either neighbour on the line onto the input nearest, if that makes the worst of its
// triangles less bad. (On a scan's rough rim the samples of the line can zig-zag at
// the grid's scale, and no free point can make up for it.)
bool Cleaner::slide(int v) {
  if (free_[v]) return false;
  const IndexSpan ring = rings_.ring(v);
  std::array<int, 2> ends{-1, -1};
  if (rings_.isBoundaryVertex(v)) {
    // A base vertex on a boundary slides too, unless a feature also ends there.
    for (int j = 1; v < numBase_ && j + 1 < ring.size(); ++j)
      if (!free_[ring[j]]) return false;
    ends = {ring[0], ring[ring.size() - 1]};
  } else if (v < numBase_) {
    return false;
  } else {
    // Its neighbours on the same base edge, or the base vertex at the edge's end.
    int count = 0;
    for (int w : ring)
      if (!free_[w] && (line_[w] == line_[v] || w < numBase_) && count++ < 2) ends[count - 1] = w;
    if (count != 2) return false;
  }
  const Vec3 from = m_.V.row(v);
  const Where fromWhere = where_[v];
  double spacing = 0;
  for (int end : ends) spacing += 0.5 * (m_.V.row(end).transpose() - from).norm();
  std::vector<std::pair<Vec3, Where>> candidates;
  if (rings_.isBoundaryVertex(v)) {
    for (int direction : {1, -1})
      for (double step : {0.1, 0.2, 0.3, 0.4}) {
        Where w;
        Vec3 x;
        if (alongBoundary(fromWhere, direction, step * spacing, w, x)) candidates.push_back({x, w});
      }
  } else {
    for (int end : ends)
      for (double step : {0.1, 0.2, 0.3, 0.4}) {
        const Vec3 target = (1 - step) * from + step * m_.V.row(end).transpose();
        const ClosestPoint cp = bvh_.closestPoint(target);
        if (faceNormal(input_, cp.face).dot(reference(v)) <= 0) continue;  // the far side
        std::array<double, 3> bary;
        if (barycentricIn(input_, cp.face, cp.point, bary))
          candidates.push_back({cp.point, {cp.face, bary}});
      }
  }
  const auto before = quality(v);
  auto bestQuality = before;
  Vec3 bestPosition = from;
  Where bestWhere = fromWhere;
  for (const auto& [x, w] : candidates) {
    bool apart = true;  // onto a neighbour (a corner of the rim, say) is no way out
    for (int u : ring) apart = apart && (m_.V.row(u).transpose() - x).norm() > 1e-7 * diag_;
    if (!apart) continue;
    setPoint(v, x, w);
    const auto q = quality(v);
    if (q > bestQuality) {
      bestQuality = q;
      bestPosition = x;
      bestWhere = w;
    }
  }
  setPoint(v, bestPosition, bestWhere);
  return bestQuality > before;
}

// Stages two and three on the faces of left_: a disk around each defective face, then
// rounds of untangling over the corners of what is left and their neighbours.
void Cleaner::repair(double from, double to) {
  constexpr int kMaxRings = 16;
  const double disksTo = from + 0.6 * (to - from);
  std::unordered_map<int, long long> inVain;  // centre -> the budget its disks spent
  for (std::size_t i = 0; i < left_.size(); ++i) {
    if (i % 32 == 0) report(from + (disksTo - from) * double(i) / double(left_.size()));
    const Eigen::Index f = left_[i];
    if (!defective(f)) continue;  // a disk around a neighbour fixed it
    int center = m_.F(f, 0);
    for (int c = 0; c < 3; ++c)
      if (m_.F(f, c) < numBase_) center = m_.F(f, c);
    // Disks that moved nothing around a centre come out the same while nothing has
    // moved since: not solved again (the bunny over 300 faces at J = 5: 329 sequences of
    // disks around 197 centres, none moving a point), their budget spent as if they were.
    const auto tried = inVain.find(center);
    if (tried != inVain.end() && tried->second <= diskBudget_) {
      diskBudget_ -= tried->second;
      continue;
    }
    const long long budget = diskBudget_;
    diskOverBudget_ = false;
    Disk disk = Disk::tryLarger;
    for (int k = 2; k <= kMaxRings && disk == Disk::tryLarger; ++k) disk = resampleDisk(center, k);
    if (disk == Disk::moved)
      inVain.clear();
    else if (!diskOverBudget_)
      inVain[center] = budget - diskBudget_;
  }
  constexpr int kUntangleRounds = 40;
  for (int round = 0; round < kUntangleRounds; ++round) {
    report(disksTo + (to - disksTo) * double(round) / kUntangleRounds);
    std::vector<Eigen::Index> still;
    for (Eigen::Index f : left_)
      if (defective(f)) still.push_back(f);
    left_.swap(still);
    if (left_.empty()) break;
    std::vector<int> candidates;
    for (Eigen::Index f : left_)
      for (int k = 0; k < 3; ++k) {
        candidates.push_back(m_.F(f, k));
        for (int w : rings_.ring(m_.F(f, k))) candidates.push_back(w);
      }
    sortUnique(candidates);
    bool moved = false;
    for (int v : candidates) {
      if (untangleBudget_-- <= 0) return;
      // A point on a boundary may, as a last resort, leave it for the inside (the
      // boundary of the remeshed surface then cuts a notch of the input's rim).
      const bool loose = v >= numBase_ && rings_.isBoundaryVertex(v);
      if (free_[v] ? placeInKernel(v) : (slide(v) || (loose && placeInKernel(v)))) moved = true;
    }
    if (!moved) break;
  }
}

// The free grid points of each base face with relaxFace set relax as a whole, each in
// turn walking along the surface towards the centroid of its neighbours (Gauss-Seidel
// on the uniform Laplacian, a discrete harmonic map of the face's grid onto the
// surface inside its edges). That undoes folds of the parameterisation wider than the
// disks of the second stage, where the surface bends too much for one tangent plane.
// Returns the points moved.
std::vector<int> Cleaner::relax(const std::vector<char>& relaxFace) {
  std::vector<int> movers;
  std::vector<char> seen(m_.V.rows(), 0);
  for (Eigen::Index f = 0; f < m_.F.rows(); ++f)
    if (relaxFace[f / perBase_])
      for (int k = 0; k < 3; ++k) {
        const int v = m_.F(f, k);
        if (free_[v] && !seen[v] && where_[v].triangle >= 0) seen[v] = 1, movers.push_back(v);
      }
  constexpr int kSweeps = 100;  // 50 to 400 gave the same results on the scans
  for (int sweep = 0; sweep < kSweeps; ++sweep)
    for (int v : movers) {
      Vec3 c = Vec3::Zero();
      const IndexSpan ring = rings_.ring(v);
      for (int w : ring) c += m_.V.row(w).transpose();
      touch(v);
      where_[v] = walker_.walk(where_[v], c / ring.size() - m_.V.row(v).transpose());
      m_.V.row(v) = walker_.position(where_[v]).transpose();
    }
  return movers;
}

// Last resort for what the repairs leave: the base faces with a defect relax, and the
// repairs run again. An attempt is kept only if fewer defects remain and the relaxed
// faces come no farther from the input (where the base is far from the input's shape
// relaxing can make things worse: the bunny asked for 150 faces at J = 5 once took a
// sliver face off the surface, Hausdorff 3.2% -> 10.7%, to leave 808 defects of 4,348).
void Cleaner::relaxWhatIsLeft(const std::function<void()>& lastResort) {
  long long before = countDefects();
  if (before > 0 && lastResort) lastResort();
  for (int attempt = 0; attempt < 3 && before > 0; ++attempt) {
    const Points keptV = m_.V;
    const std::vector<Where> keptWhere = where_;
    const CrossingPairs keptCrossings = crossings_;
    std::vector<char> relaxFace(out_.base.F.rows(), 0);
    for (Eigen::Index f : flagged_) relaxFace[f / perBase_] = 1;
    const double farBefore = farthest(relaxFace);
    std::vector<Eigen::Index> again;
    for (int v : relax(relaxFace))
      for (int q = outputAround_.start[v]; q < outputAround_.start[v + 1]; ++q)
        again.push_back(outputAround_.faces[q]);
    sortUnique(again);
    left_.clear();
    for (Eigen::Index f : again)
      if (defective(f)) left_.push_back(f);
    repair(0.8 + 0.2 * attempt / 3.0, 0.8 + 0.2 * (attempt + 1) / 3.0);
    const long long after = countDefects();
    if (after >= before || farthest(relaxFace) > farBefore) {
      m_.V = keptV;
      where_ = keptWhere;
      crossings_ = keptCrossings;
      reportCrossings();
      for (int v : touched_) isTouched_[v] = 0;
      touched_.clear();
      break;
    }
    before = after;
    out_.cleanupRelaxedFaces += static_cast<int>(std::count(relaxFace.begin(), relaxFace.end(), 1));
  }
}

void Cleaner::run(const Progress& progress, const std::function<void()>& lastResort) {
  progress_ = progress;
  projectNearBadTriangles();
  // What the first stage leaves: bad triangles, mostly next to base vertices whose grid
  // neighbours were sampled out of order around them or beside feature lines, and
  // triangles crossing another (the first stage only looks at orientation; a fold can
  // also lie flat over its neighbours).
  for (Eigen::Index f = 0; f < m_.F.rows(); ++f)
    if (bad(f)) left_.push_back(f);
  updateCrossings();
  for (const auto& pair : crossings_)
    if (!sheetsCross(pair)) left_.insert(left_.end(), pair.begin(), pair.end());
  sortUnique(left_);
  repair(0.1, 0.8);
  relaxWhatIsLeft(lastResort);
  countBad();
  // The base mesh is the remeshed surface's level 0: where a disk moved a base vertex.
  out_.base.V = m_.V.topRows(numBase_);
  for (Eigen::Index v = 0; v < m_.V.rows(); ++v)
    out_.cleanupMovedPoints += m_.V.row(v) != sampled_.row(v);
  report(1.0);
}

}  // namespace

std::vector<char> foldedTriangleFlags(const TriMesh& mesh, const std::vector<SurfacePoint>& where,
                                      const TriMesh& input, const Connectivity& inputConn) {
  const double tiny = tinyAreaFor(boundingBoxDiagonal(input.V));
  std::vector<char> flags(mesh.F.rows(), 0);
  bool degenerate = false;
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f)
    flags[f] = folded(mesh, where, {mesh.F(f, 0), mesh.F(f, 1), mesh.F(f, 2)}, input, inputConn,
                      tiny, degenerate);
  return flags;
}

long long foldedTriangles(const TriMesh& mesh, const std::vector<SurfacePoint>& where,
                          const TriMesh& input, const Connectivity& inputConn) {
  const std::vector<char> flags = foldedTriangleFlags(mesh, where, input, inputConn);
  return std::count(flags.begin(), flags.end(), 1);
}

void cleanUp(Remeshing& out, const TriMesh& input, const std::vector<char>& free,
             const std::vector<long long>& line, std::vector<Where>& where,
             const SurfaceWalker& walker, const Progress& progress,
             const std::function<void()>& lastResort, const CrossingPairs* inputCrossings) {
  Cleaner(out, input, free, line, where, walker, inputCrossings).run(progress, lastResort);
}

}  // namespace osdmra::remeshing
