#include "osdmra/remesh/resample.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <mutex>
#include <optional>
#include <unordered_map>

#include "osdmra/base/detail/parallel.h"
#include "osdmra/geometry/normals.h"
#include "osdmra/remesh/charts.h"
#include "osdmra/remesh/fan_chart.h"
#include "osdmra/remesh/grid_refinement.h"
#include "osdmra/remesh/planar.h"

namespace osdmra::remeshing {

namespace {

// The angle from angles[k] to the next one (the last's to the first's), counter-
// clockwise around a vertex whose angles sum to `total`.
double gapAfter(const std::vector<double>& angles, std::size_t k, double total) {
  return std::fmod(angles[(k + 1) % angles.size()] - angles[k] + 2 * total, total);
}

// A parameter on an edge or at a corner of its base face also lies in the faces that
// share that edge or corner: the same point in face g's corner order, if so.
bool expressIn(const TriMesh& base, const Param& p, int g, std::array<double, 3>& bary) {
  if (p.face == g) {
    bary = p.bary;
    return true;
  }
  bary = {0, 0, 0};
  for (int i = 0; i < 3; ++i) {
    if (p.bary[i] == 0) continue;
    int k = 0;
    while (k < 3 && base.F(g, k) != base.F(p.face, i)) ++k;
    if (k == 3) return false;
    bary[k] = p.bary[i];
  }
  return true;
}

// The input's line under a base edge: its vertices, each with its parameter along the
// edge (0 at the first, 1 at the last, increasing).
struct Line {
  std::vector<int> vertices;
  std::vector<double> t;
};

// A grid point to place: at parameter `bary` of base face `face`, or at `at` along
// the input's line `line` when it has one.
struct Job {
  int face = -1;
  std::array<double, 3> bary{};
  const Line* line = nullptr;
  double at = 0;
  int across = -1;  // on a base edge between two faces: the face other than `face`
};

struct Cone;

class Resampler {
 public:
  Resampler(const TriMesh& input, const Connectivity& inputConn,
            const std::vector<std::array<int, 2>>& inputFeatures, const Simplification& s,
            const BaseCharts& charts)
      : input_(input),
        inputConn_(inputConn),
        s_(s),
        base_(s.base),
        baseConn_(s.base.F, static_cast<int>(s.base.V.rows())),
        inputOf_(historyIdsOfBase(s)),
        charts_(charts) {
    LineNeighbours along = lineNeighbours(inputConn, inputFeatures);
    alongFeature_ = std::move(along.feature);
    alongBoundary_ = std::move(along.boundary);
  }

  Resampled run(int levels, GridMap map, const Progress& progress, bool refine);

 private:
  bool isBoundaryEdge(int p, int q) const {
    const int e = baseConn_.findEdge(p, q);
    return e >= 0 && baseConn_.isBoundaryEdge(e);
  }
  bool featureEdge(int p, int q) const {
    return s_.featureEdges.count(edgeKey(inputOf_[p], inputOf_[q])) != 0;
  }
  bool imageIn(const BaseCharts& charts, int f, int t, std::array<Vec2, 3>& image) const;
  bool spansFaces(int t) const;
  bool imageAboutCorner(const BaseCharts& charts, int f, int t, std::array<Vec2, 3>& image) const;
  bool walkTo(const BaseCharts& charts, int f, const std::array<double, 3>& bary, int start,
              SurfacePoint& found) const;
  SurfacePoint straight(const Job& job, SurfacePoint from) const;
  SurfacePoint straightIn(int f, const std::array<double, 3>& bary, SurfacePoint from,
                          bool& arrived) const;
  int newPoint(const Job& job, bool isFree, long long edge);
  void place(const Job& job, GridMap map, SurfacePoint& where, Vec3& position) const;
  Line lineUnder(int f, int p, int q, const std::vector<std::vector<int>>& along) const;
  SurfacePoint onLine(const Line& path, double at) const;
  int edgePoint(int f, int p, int q, int step, const std::array<double, 3>& bary);
  void gridOfFace(int f);
  int refineFace(int f, GridMap map, std::vector<Vec3>& positions);
  bool folded(const std::array<int, 3>& t, const std::vector<Vec3>& positions) const;
  Cone coneOf(int x) const;
  double angleAround(int x, const Cone& cone, const Vec3& at, const SurfacePoint& where) const;
  SurfacePoint pointAround(int x, const Cone& cone, double angle, double radius) const;
  std::vector<int> nextToVertex(int v) const;
  bool turnedOverCorner(int v, const std::vector<int>& points, const std::vector<double>& angle,
                        double total, const std::vector<Vec3>& positions) const;
  void spreadCorners(int v, std::vector<Vec3>& positions);

  const TriMesh& input_;
  const Connectivity& inputConn_;
  const Simplification& s_;
  const TriMesh& base_;
  const Connectivity baseConn_;
  std::vector<int> inputOf_;  // base vertex -> its id in the history (historyIdsOfBase)
  std::vector<std::vector<int>> alongFeature_, alongBoundary_;
  const BaseCharts& charts_;
  // Charts over two rings of faces, where charts_ lacks a corner: made on first need (most
  // scans never need them; 0.3 s for a base of 20,000 faces), by whichever thread first
  // places such a point.
  const BaseCharts& wider() const {
    std::call_once(widerMade_, [this] { wider_.emplace(base_, 2); });
    return *wider_;
  }
  mutable std::once_flag widerMade_;
  mutable std::optional<BaseCharts> wider_;
  // The output under construction.
  int levels_ = 0, N_ = 1;
  std::unordered_map<std::uint64_t, int> edgePoints_;
  std::unordered_map<long long, Line> lines_;  // by base edge p * nbv + q, p < q
  std::vector<Job> jobs_;                      // per vertex after the base vertices
  std::vector<std::array<int, 3>> faces_;
  std::vector<std::vector<int>> faceGrids_;  // per base face: gridOfFace()'s point ids
  double tinyArea_ = 0;
  Resampled out_;
};

// Whether input triangle t's corners lie in base faces other than one face or two that
// share an edge: its image then depends on how the faces between them are laid.
bool Resampler::spansFaces(int t) const {
  std::array<int, 3> faces{}, vertices{};
  int nf = 0, nv = 0;
  for (int k = 0; k < 3; ++k) {
    const int x = input_.F(t, k);
    if (s_.baseOf[x] >= 0) {
      vertices[nv++] = s_.baseOf[x];
    } else if (std::find(faces.begin(), faces.begin() + nf, s_.params[x].face) ==
               faces.begin() + nf) {
      faces[nf++] = s_.params[x].face;
    }
  }
  const auto holds = [&](int g, int w) {
    return base_.F(g, 0) == w || base_.F(g, 1) == w || base_.F(g, 2) == w;
  };
  const auto sharedCorners = [&](int g, int h) {
    return holds(h, base_.F(g, 0)) + holds(h, base_.F(g, 1)) + holds(h, base_.F(g, 2));
  };
  if (nf == 3 || (nf == 2 && sharedCorners(faces[0], faces[1]) < 2)) return true;
  // A corner at a base vertex that none of the other corners' faces has.
  for (int i = 0; i < nv; ++i)
    if (nf > 0 && std::none_of(faces.begin(), faces.begin() + nf,
                               [&](int g) { return holds(g, vertices[i]); }))
      return true;
  return false;
}

// Input triangle t laid about the first corner of base face f whose faces hold all its
// corners (fan_chart.h), where there is one: the same image from every face around that
// corner, where the breadth-first charts give one per chart.
bool Resampler::imageAboutCorner(const BaseCharts& charts, int f, int t,
                                 std::array<Vec2, 3>& image) const {
  std::array<BasePoint, 3> corners;
  for (int k = 0; k < 3; ++k) {
    const int x = input_.F(t, k);
    corners[k] = s_.baseOf[x] >= 0 ? BasePoint{s_.baseOf[x], {}} : BasePoint{-1, s_.params[x]};
  }
  for (int iv = 0; iv < 3; ++iv)
    if (layAboutCorner(base_, baseConn_, f, iv, charts.own(f), corners, image)) return true;
  return false;
}

// Input triangle t's corners, at their places on the base, in base face f's chart; a
// triangle whose corners lie in faces apart, laid about a corner of f that they
// surround where they do (imageAboutCorner).
bool Resampler::imageIn(const BaseCharts& charts, int f, int t, std::array<Vec2, 3>& image) const {
  if (spansFaces(t) && imageAboutCorner(charts, f, t, image)) return true;
  for (int k = 0; k < 3; ++k)
    if (!placeInputVertex(charts, s_, f, input_.F(t, k), image[k])) return false;
  return true;
}

// The input triangle whose corners' parameters hold the point at `bary` of base face f
// in f's chart of `charts`, found by walking from triangle `start`, and the same
// barycentric coordinates in it; false where the walk meets a triangle with a corner
// beyond the chart or turned over in it, or does not arrive.
bool Resampler::walkTo(const BaseCharts& charts, int f, const std::array<double, 3>& bary,
                       int start, SurfacePoint& found) const {
  const Vec2 at = pointIn(charts.own(f), bary);
  int t = start, previous = -1;
  for (int step = 0; step < 16; ++step) {
    std::array<Vec2, 3> image;
    if (!imageIn(charts, f, t, image)) return false;
    const double area = cross2(image[1] - image[0], image[2] - image[0]);
    if (!(area > 0)) return false;
    std::array<double, 3> l;
    for (int k = 0; k < 3; ++k)
      l[k] = cross2(image[(k + 2) % 3] - image[(k + 1) % 3], at - image[(k + 1) % 3]) / area;
    const int worst = static_cast<int>(std::min_element(l.begin(), l.end()) - l.begin());
    if (l[worst] >= -1e-12) {
      found = {t, clampedBarycentric(l)};
      return true;
    }
    // Across the edge facing the most negative coordinate.
    const int h = 3 * t + (worst + 1) % 3;
    const int twin = inputConn_.twin(h);
    if (twin < 0 || twin / 3 == previous) return false;
    previous = t;
    t = twin / 3;
  }
  return false;
}

// The point at `bary` of base face f through the parameterisation made straight on
// every input triangle (walkTo, from `from`: the exact inverse's answer, close by). Its
// corners' images are what the simplification's distortion bound checks, so on each
// input triangle this map is affine and as little distorted as that bound allows: a
// grid triangle inside one input triangle keeps its orientation. Where a triangle on
// the way has a corner beyond the faces around f's corners (a fan of slivers into a
// removed vertex: a cylinder's cap), the walk is made again in a chart of two rings, so
// that neighbouring grid points do not go through different maps (they folded the
// cap); `from` is kept where neither arrives.
SurfacePoint Resampler::straightIn(int f, const std::array<double, 3>& bary, SurfacePoint from,
                                   bool& arrived) const {
  SurfacePoint found;
  arrived = walkTo(charts_, f, bary, from.triangle, found) ||
            walkTo(wider(), f, bary, from.triangle, found);
  return arrived ? found : from;
}

// A point on a base edge between two faces is where either face's map takes it: the
// other face's charts reach it where the first one's do not (each face's charts lay the
// faces around its corners their own way, so a walk may stop in one and arrive in the
// other). Falling back to the exact inverse there put it up to several grid steps from
// where the other face's grid points next to it are sampled, and folded the triangles
// between (armadillo, the decimated knight: most folds left along base edges).
SurfacePoint Resampler::straight(const Job& job, SurfacePoint from) const {
  bool arrived = false;
  const SurfacePoint found = straightIn(job.face, job.bary, from, arrived);
  if (arrived || job.across < 0) return found;
  std::array<double, 3> bary{};  // the same point in the other face's coordinates
  for (int k = 0; k < 3; ++k)
    for (int m = 0; m < 3; ++m)
      if (base_.F(job.across, m) == base_.F(job.face, k)) bary[m] = job.bary[k];
  return straightIn(job.across, bary, from, arrived);
}

// Where a grid point lies on the input: on the input's line under its base edge, or at
// its parameter through the exact inverse of the removals (traceToInput), made
// straight on each input triangle (straight()) for GridMap::straightened.
void Resampler::place(const Job& job, GridMap map, SurfacePoint& where, Vec3& position) const {
  if (job.line) {
    where = onLine(*job.line, job.at);
  } else {
    where = traceToInput(s_.history, job.face, job.bary);
    if (map == GridMap::straightened) where = straight(job, where);
  }
  position = Vec3::Zero();
  for (int i = 0; i < 3; ++i)
    position += where.bary[i] * input_.V.row(input_.F(where.triangle, i)).transpose();
}

// A new output vertex, placed later (run() places them all at once, on every core).
int Resampler::newPoint(const Job& job, bool isFree, long long edge) {
  jobs_.push_back(job);
  out_.free.push_back(isFree);
  out_.line.push_back(edge);
  return static_cast<int>(base_.V.rows() + jobs_.size() - 1);
}

// The input's line under base edge (p, q) as seen from base face f; none if there is
// no such chain or its parameters are out of order (the points are then located like
// the others). Locating such points through the charts can land on the far side of a
// sharp corner of the line, where a vertex chart's triangles overlap the edge.
Line Resampler::lineUnder(int f, int p, int q, const std::vector<std::vector<int>>& along) const {
  const int from = inputOf_[p], to = inputOf_[q];
  Line path;
  std::vector<int>& chain = path.vertices;
  for (int first : along[from]) {
    chain = followLine(along, from, first, [&](int v) { return s_.baseOf[v] >= 0; });
    if (chain.back() == to) break;
    chain.clear();
  }
  if (chain.empty()) return path;
  int ip = 0, iq = 0;
  while (base_.F(f, ip) != p) ++ip;
  while (base_.F(f, iq) != q) ++iq;
  path.t.push_back(0);
  for (std::size_t i = 1; i + 1 < chain.size(); ++i) {
    std::array<double, 3> b;
    if (!expressIn(base_, s_.params[chain[i]], f, b) || !(b[ip] + b[iq] > 0) ||
        !(b[iq] / (b[ip] + b[iq]) > path.t.back()))
      return Line();
    path.t.push_back(b[iq] / (b[ip] + b[iq]));
  }
  if (!(path.t.back() < 1)) return Line();
  path.t.push_back(1);
  return path;
}

// The point at parameter `at` along a path, on the input edge whose ends bracket it.
SurfacePoint Resampler::onLine(const Line& path, double at) const {
  std::size_t i = 0;
  while (i + 2 < path.vertices.size() && path.t[i + 1] < at) ++i;
  const double u = std::clamp((at - path.t[i]) / (path.t[i + 1] - path.t[i]), 0.0, 1.0);
  const int a = path.vertices[i], b = path.vertices[i + 1];
  const int tri = inputConn_.edgeHalfedge(inputConn_.findEdge(a, b)) / 3;
  SurfacePoint w{tri, {0, 0, 0}};
  for (int k = 0; k < 3; ++k) {
    if (input_.F(tri, k) == a) w.bary[k] = 1 - u;
    if (input_.F(tri, k) == b) w.bary[k] = u;
  }
  return w;
}

// The grid point at `step` of N along base edge (p, q), p < q, shared with the face on
// the other side through a key on the undirected edge. Points on feature and boundary
// edges are not free to move in the clean-up.
int Resampler::edgePoint(int f, int p, int q, int step, const std::array<double, 3>& bary) {
  const long long nbv = base_.V.rows();
  const std::uint64_t key = (static_cast<std::uint64_t>(p) * nbv + q) * (N_ + 1) + step;
  const auto known = edgePoints_.find(key);
  if (known != edgePoints_.end()) return known->second;
  const long long edge = static_cast<long long>(p) * nbv + q;
  const bool feature = featureEdge(p, q), boundary = isBoundaryEdge(p, q);
  Job job{f, bary};
  const int h = baseConn_.edgeHalfedge(baseConn_.findEdge(p, q));
  if (baseConn_.twin(h) >= 0) job.across = h / 3 == f ? baseConn_.twin(h) / 3 : h / 3;
  if (feature || boundary) {
    auto [line, first] = lines_.try_emplace(edge);
    if (first) line->second = lineUnder(f, p, q, boundary ? alongBoundary_ : alongFeature_);
    if (!line->second.vertices.empty()) job = {-1, {}, &line->second, double(step) / N_};
  }
  return edgePoints_[key] = newPoint(job, !feature && !boundary, edge);
}

// The grid of base face f, J times split: corners are base vertices, edge points are
// shared with the neighbours.
void Resampler::gridOfFace(int f) {
  const int N = N_;
  const int a = base_.F(f, 0), b = base_.F(f, 1), c = base_.F(f, 2);
  std::vector<int> id((N + 1) * (N + 1), -1);
  auto at = [&](int i, int j) -> int& { return id[i * (N + 1) + j]; };
  for (int i = 0; i <= N; ++i)
    for (int j = 0; i + j <= N; ++j) {
      const std::array<double, 3> bary{double(N - i - j) / N, double(i) / N, double(j) / N};
      int& slot = at(i, j);
      if (i + j == 0) {
        slot = a;
      } else if (i == N) {
        slot = b;
      } else if (j == N) {
        slot = c;
      } else if (j == 0 || i == 0 || i + j == N) {
        int p = j == 0 ? a : i == 0 ? a : b, q = j == 0 ? b : c, step = j == 0 ? i : j;
        if (p > q) std::swap(p, q), step = N - step;
        slot = edgePoint(f, p, q, step, bary);
      } else {
        slot = newPoint({f, bary}, true, -1);
      }
    }
  faceGrids_.push_back(id);
  for (int i = 0; i < N; ++i)
    for (int j = 0; i + j < N; ++j) {
      faces_.push_back({at(i, j), at(i + 1, j), at(i, j + 1)});
      if (i + j + 1 < N) faces_.push_back({at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)});
    }
}

// Whether output triangle t (grid point ids), as placed, is folded as the clean-up counts
// it (cleanup.h's foldedTriangles): facing against the input under each of its corners,
// or of no area.
bool Resampler::folded(const std::array<int, 3>& t, const std::vector<Vec3>& positions) const {
  const int nbv = static_cast<int>(base_.V.rows());
  const auto at = [&](int v) -> Vec3 {
    return v < nbv ? Vec3(out_.mesh.V.row(v).transpose()) : positions[v - nbv];
  };
  bool degenerate = false;
  return foldedAgainst(input_, inputConn_, {at(t[0]), at(t[1]), at(t[2])},
                       {out_.where[t[0]], out_.where[t[1]], out_.where[t[2]]}, tinyArea_,
                       degenerate);
}

// The interior points of base face f's grid, placed level by level through the map and
// kept from folding their level's triangles where a step in the face's domain mends them
// (grid_refinement.h); the points on its sides are placed already. Returns the steps kept.
int Resampler::refineFace(int f, GridMap map, std::vector<Vec3>& positions) {
  const int N = N_, nbv = static_cast<int>(base_.V.rows());
  const std::vector<int>& id = faceGrids_[f];
  const auto point = [&](int i, int j) { return id[static_cast<std::size_t>(i) * (N + 1) + j]; };
  GridCallbacks grid;
  grid.place = [&](int i, int j, const Vec2& uv) {
    const int v = point(i, j);
    place({f, {1 - uv.x() - uv.y(), uv.x(), uv.y()}}, map, out_.where[v], positions[v - nbv]);
  };
  grid.folded = [&](const std::array<int, 2>& a, const std::array<int, 2>& b,
                    const std::array<int, 2>& c) {
    return folded({point(a[0], a[1]), point(b[0], b[1]), point(c[0], c[1])}, positions);
  };
  return refineGrid(levels_, grid);
}

// Input vertex x's cone: the angle of each of its faces at x (in its fan's order) and
// where each starts, counted from the first.
struct Cone {
  std::vector<double> sector, start;
  double total() const { return start.back(); }
};

Cone Resampler::coneOf(int x) const {
  Cone cone;
  cone.start.assign(1, 0.0);
  for (int h : inputConn_.fan(x)) {
    cone.sector.push_back(faceAngle(input_, h / 3, h % 3));
    cone.start.push_back(cone.start.back() + cone.sector.back());
  }
  return cone;
}

// Where point `at` (sampled at `where`) lies around input vertex x, in x's own angles
// (coneOf): in the face of x's fan it was sampled in, or, beyond x's faces, in the
// face whose sides' directions it lies between most nearly.
double Resampler::angleAround(int x, const Cone& cone, const Vec3& at,
                              const SurfacePoint& where) const {
  const IndexSpan fan = inputConn_.fan(x);
  const Vec3 c = input_.V.row(x).transpose(), d = at - c;
  double bestMiss = std::numeric_limits<double>::infinity(), angle = -1;
  for (int k = 0; k < fan.size(); ++k) {
    const Vec3 a = input_.V.row(inputConn_.to(fan[k])).transpose() - c;
    const Vec3 b = input_.V.row(inputConn_.from(Connectivity::prev(fan[k]))).transpose() - c;
    const double ta = angleBetween(a, d), tb = angleBetween(d, b);
    const double miss = fan[k] / 3 == where.triangle ? -1 : ta + tb - cone.sector[k];
    if (!(miss < bestMiss)) continue;
    bestMiss = miss;
    angle = cone.start[k] + (ta + tb > 0 ? cone.sector[k] * ta / (ta + tb) : 0);
  }
  return angle;
}

// The point at angle `angle` around input vertex x (coneOf), in the face of x's fan
// that holds that angle, `radius` of the way from x to the face's far side.
SurfacePoint Resampler::pointAround(int x, const Cone& cone, double angle, double radius) const {
  const IndexSpan fan = inputConn_.fan(x);
  int k = 0;
  while (k + 1 < fan.size() && cone.start[k + 1] <= angle) ++k;
  const double u =
      cone.sector[k] > 0 ? std::clamp((angle - cone.start[k]) / cone.sector[k], 0.0, 1.0) : 0.0;
  const int h = fan[k], corner = h % 3;
  SurfacePoint w{h / 3, {0, 0, 0}};
  w.bary[corner] = 1 - radius;
  w.bary[(corner + 1) % 3] = radius * (1 - u);
  w.bary[(corner + 2) % 3] = radius * u;
  return w;
}

// The grid points next to base vertex v, one on each base edge out of it (free ones:
// not on a feature line or a boundary), counter-clockwise; empty if v has another.
std::vector<int> Resampler::nextToVertex(int v) const {
  const long long nb = base_.V.rows();
  std::vector<int> points;
  for (int h : baseConn_.fan(v)) {
    const int w = baseConn_.to(h), p = std::min(v, w), q = std::max(v, w);
    const int step = v == p ? 1 : N_ - 1;
    const auto it = edgePoints_.find((static_cast<std::uint64_t>(p) * nb + q) * (N_ + 1) + step);
    if (it == edgePoints_.end() || !out_.free[it->second]) return {};
    points.push_back(it->second);
  }
  return points;
}

// Whether a grid triangle at a corner of base vertex v (joining it to two consecutive
// `points` next to it, at `angle` around it) spans more than a half turn of the input
// around v and is turned over: it faces along the input under none of its corners, as
// the clean-up counts a flipped triangle (facesAlong).
bool Resampler::turnedOverCorner(int v, const std::vector<int>& points,
                                 const std::vector<double>& angle, double total,
                                 const std::vector<Vec3>& positions) const {
  const int nbv = static_cast<int>(base_.V.rows()), m = static_cast<int>(points.size());
  const Vec3 c = input_.V.row(inputOf_[v]).transpose();
  for (int k = 0; k < m; ++k) {
    const int p = points[k], q = points[(k + 1) % m];
    if (gapAfter(angle, k, total) <= kPi) continue;
    const Vec3 n = (positions[p - nbv] - c).cross(positions[q - nbv] - c);
    const bool along = facesAlong(input_, inputConn_, out_.where[v], n) ||
                       facesAlong(input_, inputConn_, out_.where[p], n) ||
                       facesAlong(input_, inputConn_, out_.where[q], n);
    if (!along) return true;
  }
  return false;
}

// A grid triangle at a corner of base vertex v joins v to two grid points next to it;
// spanning more than a half turn of the input around v, it faces against the input
// wherever on the corner's sides they lie (armadillo over 150 base faces at J = 5,
// docs/REMESH.md: a base face's corner covering about 200 degrees of the input's cone;
// the clean-up may not move v and did not mend it). Where such a triangle comes out
// turned over (turnedOverCorner), the points next to v are placed around it again at
// angles spread by spreadAround, in its input one-ring, each as far out (up to 3/4 of
// the ring) as it was. Elsewhere nothing is touched: a corner over a half turn of a
// cone far from flat (a saddle, a crumple where the input crosses itself) need not turn
// over, and spreading there folded the ogre's grid more (docs/REMESH.md).
void Resampler::spreadCorners(int v, std::vector<Vec3>& positions) {
  const int x = inputOf_[v], nbv = static_cast<int>(base_.V.rows());
  if (x >= input_.V.rows() || baseConn_.isBoundaryVertex(v) || !baseConn_.isManifoldVertex(v) ||
      inputConn_.isBoundaryVertex(x) || !inputConn_.isManifoldVertex(x))
    return;
  const std::vector<int> points = nextToVertex(v);
  if (points.size() < 3) return;
  const Cone cone = coneOf(x);
  std::vector<double> angle;
  for (int id : points) {
    angle.push_back(angleAround(x, cone, positions[id - nbv], out_.where[id]));
    if (angle.back() < 0) return;
  }
  if (!turnedOverCorner(v, points, angle, cone.total(), positions)) return;
  const std::vector<double> spread = spreadAround(angle, cone.total(), kSpreadTo);
  if (spread == angle) return;  // out of order, or too many turns to spread
  const Vec3 c = input_.V.row(x).transpose();
  for (std::size_t k = 0; k < points.size(); ++k) {
    SurfacePoint w = pointAround(x, cone, spread[k], 1.0);  // on the ring's far side
    Vec3 rim = Vec3::Zero();
    for (int i = 0; i < 3; ++i)
      rim += w.bary[i] * input_.V.row(input_.F(w.triangle, i)).transpose();
    const double radius =
        std::min(0.75, (positions[points[k] - nbv] - c).norm() / (rim - c).norm());
    w = pointAround(x, cone, spread[k], radius);
    out_.where[points[k]] = w;
    positions[points[k] - nbv] = c + radius * (rim - c);
  }
}

Resampled Resampler::run(int levels, GridMap map, const Progress& progress, bool refine) {
  levels_ = levels;
  N_ = 1 << levels;
  const int nbv = static_cast<int>(base_.V.rows()), nb = static_cast<int>(base_.F.rows());
  // Base vertices are input vertices: a corner of any of their input triangles.
  out_.where.assign(nbv, SurfacePoint());
  for (Eigen::Index t = 0; t < input_.F.rows(); ++t)
    for (int k = 0; k < 3; ++k) {
      const int b = s_.baseOf[input_.F(t, k)];
      if (b >= 0) {
        out_.where[b].triangle = static_cast<int>(t);
        out_.where[b].bary = {0, 0, 0};
        out_.where[b].bary[k] = 1;
      }
    }
  out_.free.assign(nbv, 0);
  out_.line.assign(nbv, -1);
  // Added base vertices (base_flips.h) are points of the input, placed as grid points are.
  std::vector<Vec3> addedAt(s_.added.size());
  for (std::size_t k = 0; k < s_.added.size(); ++k) {
    const int v = s_.added[k].base, f = baseConn_.fan(v)[0] / 3;
    Job job;
    job.face = f;
    for (int i = 0; i < 3; ++i) job.bary[i] = base_.F(f, i) == v ? 1.0 : 0.0;
    place(job, map, out_.where[v], addedAt[k]);
  }
  for (int f = 0; f < nb; ++f) gridOfFace(f);
  // The grid points, each independent of the others.
  const int n = static_cast<int>(jobs_.size());
  out_.where.resize(nbv + jobs_.size());
  out_.mesh.V.resize(nbv + n, 3);
  out_.mesh.V.topRows(nbv) = base_.V;
  for (std::size_t k = 0; k < s_.added.size(); ++k)
    out_.mesh.V.row(s_.added[k].base) = addedAt[k].transpose();
  std::vector<Vec3> positions(jobs_.size());
  tinyArea_ = tinyAreaFor(boundingBoxDiagonal(input_.V));
  // The points on base edges first, each independent of the others; then each base
  // face's interior, level by level (refineFace), the faces independent of each other.
  // Progress: the first pass is a fifth of the work where the second one runs.
  const double firstShare = refine ? 0.2 : 1.0;
  const int chunks = numChunks(n, 1 << 12);
  constexpr int kSteps = 64;  // progress reports, and the pieces each chunk works in
  std::atomic<int> done{0};
  forChunks(n, chunks, [&](int chunk, int begin, int end) {
    for (int piece = 0; piece < kSteps; ++piece) {
      const int from = begin + (end - begin) * piece / kSteps;
      const int to = begin + (end - begin) * (piece + 1) / kSteps;
      for (int i = from; i < to; ++i)
        if (!refine || out_.line[nbv + i] >= 0)  // on a base edge (refineFace: the others)
          place(jobs_[i], map, out_.where[nbv + i], positions[i]);
      ++done;
      if (chunk == 0 && progress)
        progress("resample", firstShare * double(done) / (chunks * kSteps));
    }
  });
  // The points next to each base vertex spread where a corner would turn over, before
  // the faces' interiors: the refinement then mends the triangles next to them (spread
  // after it, they folded the triangles between them and the points after them).
  for (int v = 0; v < nbv; ++v) spreadCorners(v, positions);
  if (refine) {
    std::atomic<int> moves{0}, faces{0};
    forChunks(nb, numChunks(nb, 16), [&](int chunk, int begin, int end) {
      for (int f = begin; f < end; ++f) {
        moves += refineFace(f, map, positions);
        ++faces;
        if (chunk == 0 && progress)
          progress("resample", firstShare + (1 - firstShare) * double(faces) / nb);
      }
    });
    out_.refinementMoves = moves;
  }
  if (progress) progress("resample", 1.0);
  for (int i = 0; i < n; ++i) out_.mesh.V.row(nbv + i) = positions[i].transpose();
  out_.mesh.F.resize(static_cast<Eigen::Index>(faces_.size()), 3);
  for (std::size_t f = 0; f < faces_.size(); ++f)
    for (int k = 0; k < 3; ++k) out_.mesh.F(f, k) = faces_[f][k];
  return std::move(out_);
}

}  // namespace

double widestGap(const std::vector<double>& angles, double total) {
  double widest = 0;
  const std::size_t m = angles.size();
  for (std::size_t k = 0; k < m; ++k) widest = std::max(widest, gapAfter(angles, k, total));
  return widest;
}

std::vector<double> spreadAround(const std::vector<double>& angles, double total, double most) {
  const std::size_t m = angles.size();
  if (m < 2 || !(m * most > total)) return angles;
  std::vector<double> gap(m);
  double sum = 0;
  for (std::size_t k = 0; k < m; ++k) {
    gap[k] = gapAfter(angles, k, total);
    sum += gap[k];
  }
  if (!(std::abs(sum - total) <= 1e-9 * total)) return angles;  // not in order
  // The gaps over `most` cut to it, the excess shared among the others by their room
  // under it: the room is m most - total more than the excess, so none goes over.
  double excess = 0, room = 0;
  for (double& g : gap)
    if (g > most) {
      excess += g - most;
      g = most;
    } else {
      room += most - g;
    }
  if (excess <= 0) return angles;
  for (double& g : gap)
    if (g < most) g = std::min(most, g + excess * (most - g) / room);
  // Laid from the first, then turned so that the points move by nothing on average.
  std::vector<double> out(m, 0.0);
  for (std::size_t k = 1; k < m; ++k) out[k] = out[k - 1] + gap[k - 1];
  double shift = 0;
  for (std::size_t k = 0; k < m; ++k) {
    double d = std::fmod(angles[k] - angles[0] - out[k] + 3 * total, total);
    if (d > total / 2) d -= total;
    shift += d / m;
  }
  for (double& a : out) a = std::fmod(a + angles[0] + shift + 2 * total, total);
  return out;
}

Resampled resample(const TriMesh& input, const Connectivity& inputConn,
                   const std::vector<std::array<int, 2>>& inputFeatures, const Simplification& s,
                   const BaseCharts& charts, int levels, GridMap map, const Progress& progress,
                   bool refine) {
  Resampler r(input, inputConn, inputFeatures, s, charts);
  return r.run(levels, map, progress, refine);
}

}  // namespace osdmra::remeshing
