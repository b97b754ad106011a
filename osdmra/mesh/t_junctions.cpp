#include "osdmra/mesh/t_junctions.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <utility>
#include <vector>

#include "osdmra/mesh/detail/edges.h"

namespace osdmra {

namespace {

using Vec3 = Eigen::Vector3d;

// Halfedges h = 3 f + k (corner k to k + 1 of face f) alone on their edge, in face
// order.
std::vector<int> boundaryHalfedges(const Faces& F) {
  const std::vector<std::pair<std::uint64_t, int>> byEdge = detail::halfedgesByEdge(F);
  std::vector<int> out;
  for (std::size_t i = 0, end; i < byEdge.size(); i = end) {
    end = detail::runEnd(byEdge, i);
    if (end - i == 1) out.push_back(byEdge[i].second);
  }
  std::sort(out.begin(), out.end());
  return out;
}

// Boundary vertices bucketed in a uniform grid of cubes of side `cell`.
class VertexGrid {
 public:
  VertexGrid(const Points& V, const std::vector<int>& vertices, double cell)
      : cell_(cell), all_(vertices) {
    for (int v : vertices) cells_[cellKey(cellOf(V.row(v).transpose()))].push_back(v);
  }
  // The vertices in the cells that the box [lo, hi] touches; every vertex when the box
  // spans more cells than there are vertices (a long edge across the grid).
  template <class F>
  void forEachIn(const Vec3& lo, const Vec3& hi, F&& visit) const {
    const Cell a = cellOf(lo), b = cellOf(hi);
    if ((b - a + 1).cast<double>().prod() > static_cast<double>(all_.size())) {
      for (int v : all_) visit(v);
      return;
    }
    for (long long x = a(0); x <= b(0); ++x)
      for (long long y = a(1); y <= b(1); ++y)
        for (long long z = a(2); z <= b(2); ++z) {
          const auto it = cells_.find(cellKey(Cell(x, y, z)));
          if (it != cells_.end())
            for (int v : it->second) visit(v);
        }
  }

 private:
  using Cell = Eigen::Array<long long, 3, 1>;
  // Clamped so that no coordinate over cell overflows the integer it is cast to.
  Cell cellOf(const Vec3& p) const {
    return (p.array() / cell_).floor().max(-1e15).min(1e15).cast<long long>();
  }
  static std::uint64_t cellKey(const Cell& c) {
    const auto h = [](long long i) { return static_cast<std::uint64_t>(i); };
    return h(c(0)) * 0x9E3779B97F4A7C15ull ^ h(c(1)) * 0xC2B2AE3D27D4EB4Full ^
           h(c(2)) * 0x165667B19E3779F9ull;
  }
  double cell_;
  std::vector<int> all_;
  std::unordered_map<std::uint64_t, std::vector<int>> cells_;
};

// Where boundary vertex v lies on segment [a, b] (0 < t < 1), or -1.
double placeOn(const Points& V, int a, int b, int v) {
  const Vec3 pa = V.row(a), pb = V.row(b), p = V.row(v);
  const Vec3 d = pb - pa;
  const double length2 = d.squaredNorm();
  if (!(length2 > 0)) return -1;
  const double t = (p - pa).dot(d) / length2;
  if (!(t > 0 && t < 1)) return -1;
  const double tolerance = kTJunctionTolerance * std::sqrt(length2);
  return (pa + t * d - p).squaredNorm() <= tolerance * tolerance ? t : -1;
}

// One pass: each face split along at most one of its edges.
int zipRound(TriMesh& mesh) {
  const std::vector<int> open = boundaryHalfedges(mesh.F);
  if (open.empty()) return 0;
  std::vector<int> vertices;
  double total = 0;
  for (int h : open) {
    const int a = mesh.F(h / 3, h % 3), b = mesh.F(h / 3, (h % 3 + 1) % 3);
    vertices.push_back(a);
    total += (mesh.V.row(b) - mesh.V.row(a)).norm();
  }
  std::sort(vertices.begin(), vertices.end());
  vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
  const double cell = total / static_cast<double>(open.size());
  if (!(cell > 0)) return 0;
  const VertexGrid grid(mesh.V, vertices, cell);
  std::vector<char> split(static_cast<std::size_t>(mesh.F.rows()), 0);
  std::vector<std::array<int, 3>> added;
  int edges = 0;
  // The vertices tested are bounded in proportion to the boundary, whatever its edges'
  // lengths: past the budget the rest of the edges are left as they are.
  const std::size_t budget = 64 * (open.size() + vertices.size());
  std::size_t tested = 0;
  for (int h : open) {
    const int f = h / 3, k = h % 3;
    if (split[f]) continue;
    if (tested > budget) break;
    const int a = mesh.F(f, k), b = mesh.F(f, (k + 1) % 3), c = mesh.F(f, (k + 2) % 3);
    const Vec3 pa = mesh.V.row(a), pb = mesh.V.row(b);
    const double tolerance = kTJunctionTolerance * (pb - pa).norm();
    std::vector<std::pair<double, int>> onEdge;
    grid.forEachIn(pa.cwiseMin(pb).array() - tolerance, pa.cwiseMax(pb).array() + tolerance,
                   [&](int v) {
                     ++tested;
                     if (v == a || v == b || v == c) return;
                     const double t = placeOn(mesh.V, a, b, v);
                     if (t > 0) onEdge.emplace_back(t, v);
                   });
    if (onEdge.empty()) continue;
    std::sort(onEdge.begin(), onEdge.end());
    // (a, b, c) becomes the fan (a, v1, c), (v1, v2, c), ..., (vk, b, c).
    int from = a;
    for (const auto& [t, v] : onEdge) {
      added.push_back({from, v, c});
      from = v;
    }
    mesh.F.row(f) << from, b, c;
    split[f] = 1;
    ++edges;
  }
  if (edges == 0) return 0;
  const Eigen::Index n = mesh.F.rows();
  mesh.F.conservativeResize(n + static_cast<Eigen::Index>(added.size()), 3);
  for (std::size_t i = 0; i < added.size(); ++i)
    mesh.F.row(n + static_cast<Eigen::Index>(i)) << added[i][0], added[i][1], added[i][2];
  return edges;
}

}  // namespace

int zipTJunctions(TriMesh& mesh) {
  if (mesh.F.rows() == 0 || !hasWellFormedFaces(mesh) || !mesh.V.allFinite()) return 0;
  // A face with T-junctions on two of its edges has the second split in a later round.
  constexpr int kMaxRounds = 8;
  int edges = 0;
  for (int round = 0; round < kMaxRounds; ++round) {
    const int split = zipRound(mesh);
    if (split == 0) break;
    edges += split;
  }
  return edges;
}

}  // namespace osdmra
