// Distance: sampled geometric error between two triangle meshes.
//
// A level-of-detail mesh is judged by how far its surface lies from the
// full-resolution surface, measured in space (not parametrically, as l2Distance in
// truncation.h does), so that meshes with different connectivity compare. The tool
// has three parts:
//
//  - closestPointOnTriangle(): the exact closest point of one triangle, robust for
//    slivers and fully degenerate triangles (segments, points);
//  - TriangleBvh: a bounding-volume hierarchy over a mesh's triangles that answers
//    closest-point queries in about logarithmic time;
//  - samplePoints() and surfaceDistance(): area-uniform samples of each surface,
//    measured against the other, summarised as RMS / mean / Hausdorff distances.
//
// Everything is deterministic and identical across standard libraries: sampling
// draws raw 64-bit words from std::mt19937_64 (whose output the standard fixes) and
// converts them itself, and the hierarchy is built with a total order on triangles,
// so ties resolve the same way everywhere.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include "osdmra/mesh/mesh.h"

namespace osdmra {

/// A point on a mesh nearest to a query point.
struct ClosestPoint {
  double distance = 0.0;  ///< Euclidean distance from the query to `point`.
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  int face = -1;  ///< Row of TriMesh::F that contains `point` (one of them on a tie).
};

/// The point of triangle (a, b, c) nearest to p: a vertex, a point on an edge, or the
/// orthogonal projection of p into the interior.
///
/// The result always lies on the triangle (up to rounding in a + s (b - a) + t (c - a)
/// with s, t >= 0, s + t <= 1), so its distance underestimates the true one by
/// rounding at most. Exact up to rounding for coordinates below ~1e75, where
/// |(b - a) x (c - a)|^2 does not overflow.
/// Degenerate triangles are handled as what they are: collinear corners give the
/// nearest point of the longest segment, coincident corners give that point; nothing
/// divides by zero, and finite input gives finite output.
Eigen::Vector3d closestPointOnTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                       const Eigen::Vector3d& b, const Eigen::Vector3d& c);

/// Bounding-volume hierarchy over the triangles of a TriMesh, for closest-point
/// queries.
///
/// Built once in O(n log n): each node's triangles are split at the median of their
/// centroids along the longest axis of the centroid box, down to leaves of at most
/// kLeafSize triangles. The median split makes the depth 1 + ceil(log2(n / kLeafSize))
/// (1 for n <= kLeafSize) whatever the geometry, coincident or degenerate triangles
/// included, so a query needs only a small fixed-size stack.
///
/// Storage is flat: the nodes in one array (depth-first, left child right after its
/// parent), with float boxes rounded outward (32-byte nodes; pruning stays exact),
/// and the triangles' corners copied into a second array in leaf order so a leaf's
/// triangles are contiguous in memory. About 100 bytes per triangle; the mesh need
/// not outlive the hierarchy.
///
/// Queries are const and thread-safe.
class TriangleBvh {
 public:
  /// Most triangles in a leaf: small leaves prune well, and testing a few triangles
  /// costs about as much as testing two more boxes.
  static constexpr int kLeafSize = 4;

  /// Throws Error if the mesh has no face, an index out of range or a non-finite
  /// coordinate. Degenerate triangles are allowed.
  explicit TriangleBvh(const TriMesh& mesh);

  /// The point of the mesh nearest to p (exact up to rounding). Ordered depth-first
  /// traversal: the nearer child box first, and any subtree whose box is no nearer
  /// than the best point found so far is skipped. Throws Error for a non-finite p.
  /// (Squared distances beyond ~1e308 overflow: such a query gets distance infinity
  /// and some triangle.)
  ClosestPoint closestPoint(const Eigen::Vector3d& p) const;

  /// Appends to `faces` every face whose bounding box meets the box [lo, hi].
  void facesInBox(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                  std::vector<int>& faces) const;

  /// Pairs of nodes (a, b) that share out the hierarchy's traversal against itself:
  /// every pair of distinct triangles whose bounding boxes meet lies under exactly one
  /// of them (both in a == b, or one in each). About `count` of them (fewer when the
  /// tree runs out), so that threads can take them in turn.
  std::vector<std::array<int, 2>> selfPairTasks(int count) const;

  /// Calls visit(f, g) (rows of TriMesh::F, f < g) for every pair of distinct
  /// triangles under task (a, b) of selfPairTasks() whose bounding boxes meet: one
  /// traversal of two subtrees against each other, instead of one query per triangle.
  template <class Visit>
  void forBoxesMeeting(std::array<int, 2> task, Visit&& visit) const;

  int numTriangles() const { return static_cast<int>(faceOf_.size()); }
  int numNodes() const { return static_cast<int>(nodes_.size()); }
  /// Nodes on the longest root-to-leaf path (1 for a single leaf).
  int depth() const { return depth_; }

  /// One node: its box and either its triangles (a leaf, count > 0: triangles
  /// [first, first + count) in leaf order) or its children (count == 0: the left
  /// child is the next node, the right child is node `first`).
  struct Node {
    float lo[3];  ///< Rounded down from the triangles' extent.
    float hi[3];  ///< Rounded up.
    int first;
    int count;
  };

 private:
  /// Corners of triangle i in leaf order: corners_[3 i], corners_[3 i + 1],
  /// corners_[3 i + 2].
  std::vector<Eigen::Vector3d> corners_;
  /// Row of TriMesh::F of triangle i in leaf order.
  std::vector<int> faceOf_;
  std::vector<Node> nodes_;
  int depth_ = 0;

  static bool boxesMeet(const Node& a, const Node& b) {
    for (int k = 0; k < 3; ++k)
      if (a.hi[k] < b.lo[k] || b.hi[k] < a.lo[k]) return false;
    return true;
  }
  /// The pairs that cover (a, b)'s: a node against itself gives its children against
  /// themselves and each other; distinct nodes split the larger one (an inner node).
  template <class Push>
  void splitPair(int a, int b, Push&& push) const;
  // A triangle's bounding box, exact (its corners' extremes).
  struct TriangleBox {
    Eigen::Vector3d lo, hi;
    bool meets(const TriangleBox& o) const {
      return (lo.array() <= o.hi.array()).all() && (hi.array() >= o.lo.array()).all();
    }
  };
  TriangleBox triangleBox(int i) const;
};

template <class Push>
void TriangleBvh::splitPair(int a, int b, Push&& push) const {
  const Node &na = nodes_[a], &nb = nodes_[b];
  if (a == b) {
    push(a + 1, a + 1);
    push(a + 1, na.first);
    push(na.first, na.first);
    return;
  }
  auto extent = [](const Node& n) {
    return (n.hi[0] - n.lo[0]) + (n.hi[1] - n.lo[1]) + (n.hi[2] - n.lo[2]);
  };
  if (nb.count > 0 || (na.count == 0 && extent(na) >= extent(nb))) {
    push(a + 1, b);
    push(na.first, b);
  } else {
    push(a, b + 1);
    push(a, nb.first);
  }
}

template <class Visit>
void TriangleBvh::forBoxesMeeting(std::array<int, 2> task, Visit&& visit) const {
  std::vector<std::array<int, 2>> stack{task};
  while (!stack.empty()) {
    const auto [a, b] = stack.back();
    stack.pop_back();
    const Node &na = nodes_[a], &nb = nodes_[b];
    if (!boxesMeet(na, nb)) continue;
    if (na.count == 0 || nb.count == 0) {
      splitPair(a, b, [&](int x, int y) { stack.push_back({x, y}); });
      continue;
    }
    // Each triangle's box once per pair of leaves, not once per pair of triangles.
    std::array<TriangleBox, kLeafSize> boxA, boxB;
    for (int i = 0; i < na.count; ++i) boxA[i] = triangleBox(na.first + i);
    for (int j = 0; j < nb.count; ++j) boxB[j] = triangleBox(nb.first + j);
    for (int i = 0; i < na.count; ++i)
      for (int j = a == b ? i + 1 : 0; j < nb.count; ++j)
        if (boxA[i].meets(boxB[j])) {
          const int f = faceOf_[na.first + i], g = faceOf_[nb.first + j];
          visit(std::min(f, g), std::max(f, g));
        }
  }
}

/// `count` points distributed uniformly by area over the surface of `mesh`
/// (zero-area faces are never drawn; a mesh of zero total area draws every face with
/// equal weight instead), followed, if `includeVertices`, by every row of mesh.V.
///
/// Each sample draws three 53-bit uniforms from std::mt19937_64(seed): one picks the
/// face from the cumulative areas, two place the point with the square-root rule
/// p = a + sqrt(r1) ((1 - r2) (b - a) + r2 (c - a)). Same mesh and seed give the same
/// points bit for bit on every platform. Throws Error for count < 0, a mesh without
/// faces, an index out of range or a non-finite coordinate.
Points samplePoints(const TriMesh& mesh, int count, std::uint64_t seed,
                    bool includeVertices = false);

struct DistanceOptions {
  /// Area-uniform samples drawn on each surface (>= 0).
  int samples = 100000;
  /// Seed of the samples of a; those of b use a seed derived from it, so the two
  /// sample sets are independent even when a and b are the same surface.
  std::uint64_t seed = 1;
  /// Also measure from every vertex of each mesh: vertices are where a
  /// level-of-detail mesh's largest deviations usually sit (corners, creases),
  /// and random samples would hit them only by chance.
  bool includeVertices = true;
};

/// Sampled symmetric distance between two surfaces. "AB" measures from samples of a
/// to the surface of b, "BA" from samples of b to a.
struct SurfaceDistance {
  /// Root mean square over the samples of both directions, each sample weighing the
  /// same (with includeVertices, the vertices of the denser mesh weigh most).
  double rms = 0.0;
  double hausdorff = 0.0;  ///< max(maxAB, maxBA): the (sampled) Hausdorff distance.
  double meanAB = 0.0, maxAB = 0.0;
  double meanBA = 0.0, maxBA = 0.0;
  /// rms and hausdorff divided by `diagonal`, so errors of differently sized models
  /// compare (0 when the distance is 0; +infinity when the diagonal is 0 and the
  /// distance is not).
  double rmsRelative = 0.0, hausdorffRelative = 0.0;
  /// Bounding-box diagonal of b: b is the reference (the full-resolution surface),
  /// so every approximation of it is measured on the same scale.
  double diagonal = 0.0;
};

/// Measures a against b and b against a (see DistanceOptions); b is the reference
/// for the relative values. Builds a TriangleBvh for each mesh (one at a time) and
/// runs one closest-point query per sample, the samples taken in Morton order so
/// that consecutive queries share cached tree nodes (the sums are still taken in
/// sample order). O(n log n) in all: about 0.25 s per million triangles to build and
/// about 1 us per sample near the other surface. A sampled Hausdorff distance is a
/// lower bound of the true one that converges as samples grow.
/// Throws Error if either mesh has no face or no vertex, an index out of range or a
/// non-finite coordinate, or if there is nothing to sample (samples == 0 without
/// vertices).
SurfaceDistance surfaceDistance(const TriMesh& a, const TriMesh& b,
                                const DistanceOptions& opts = {});

}  // namespace osdmra
