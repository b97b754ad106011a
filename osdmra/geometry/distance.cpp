#include "osdmra/geometry/distance.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>
#include <string>
#include <utility>

#include "osdmra/base/detail/parallel.h"
#include "osdmra/base/error.h"
#include "osdmra/mesh/spatial_order.h"

namespace osdmra {
namespace {

using Vec3 = Eigen::Vector3d;

// Meshes of at least twice this many faces build their hierarchy's two halves on two
// threads (TriangleBvh's constructor).
constexpr long long kParallelBuild = 1 << 15;

/// Rejects what no distance can be measured on: no face, an index out of range, a
/// non-finite coordinate. `what` names the caller and the mesh for the message.
void checkMesh(const TriMesh& mesh, const std::string& what) {
  if (mesh.F.rows() == 0) throw Error(what + ": the mesh has no faces");
  const Eigen::Index nv = mesh.V.rows();
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f)
    for (int k = 0; k < 3; ++k)
      if (mesh.F(f, k) < 0 || mesh.F(f, k) >= nv)
        throw Error(what + ": face " + std::to_string(f) + " refers to vertex " +
                    std::to_string(mesh.F(f, k)) + ", but the mesh has " + std::to_string(nv) +
                    " vertices");
  for (Eigen::Index v = 0; v < nv; ++v)
    if (!mesh.V.row(v).allFinite())
      throw Error(what + ": vertex " + std::to_string(v) + " has a non-finite coordinate");
}

Vec3 corner(const TriMesh& mesh, Eigen::Index f, int k) {
  return mesh.V.row(mesh.F(f, k)).transpose();
}

/// Nearest point of segment [a, a + d] to p. A zero-length segment is its point;
/// dividing only by a positive length keeps t finite, and clamping keeps it in [0, 1].
Vec3 nearestOnSegment(const Vec3& p, const Vec3& a, const Vec3& d) {
  const double dd = d.squaredNorm();
  double t = 0.0;
  if (dd > 0.0) t = std::clamp(d.dot(p - a) / dd, 0.0, 1.0);
  return a + t * d;
}

/// closestPointOnTriangle() with the squared distance as a by-product.
///
/// The interior candidate is the projection of p onto the triangle's plane, in
/// barycentric coordinates (s, t) from cross products with the unnormalised normal
/// n: s = ((p - a) x (c - a)) . n / |n|^2 and t = ((b - a) x (p - a)) . n / |n|^2.
/// It is taken only if s, t >= 0 and s + t <= 1, so the point it gives,
/// a + s (b - a) + t (c - a), lies on the triangle whatever rounding did to s and t.
/// Otherwise the nearest point is on the boundary, and the nearest of the three edges
/// is taken. This, unlike the usual Voronoi-region cascade, never classifies from
/// signs of nearly cancelling products, so slivers cannot send it to a wrong region
/// far away: near the boundary both candidates are within rounding of each other.
/// A degenerate triangle (|n|^2 == 0) skips the interior and is its edges. NaN from
/// an overflowing division fails the comparisons and falls through to the edges.
Vec3 nearestOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, double& distSq) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const Vec3 n = ab.cross(ac);
  const double nn = n.squaredNorm();
  if (nn > 0.0) {
    const double s = ap.cross(ac).dot(n) / nn;
    const double t = ab.cross(ap).dot(n) / nn;
    if (s >= 0.0 && t >= 0.0 && s + t <= 1.0) {
      const Vec3 x = a + s * ab + t * ac;
      distSq = (p - x).squaredNorm();
      return x;
    }
  }
  const std::array<Vec3, 3> onEdge{nearestOnSegment(p, a, ab), nearestOnSegment(p, a, ac),
                                   nearestOnSegment(p, b, c - b)};
  int best = 0;
  distSq = (p - onEdge[0]).squaredNorm();
  for (int e = 1; e < 3; ++e) {
    const double d = (p - onEdge[e]).squaredNorm();
    if (d < distSq) {
      distSq = d;
      best = e;
    }
  }
  return onEdge[best];
}

/// x rounded to float, clamped to the float range (a double beyond it has no
/// defined conversion).
float toFloat(double x) {
  constexpr double kMax = std::numeric_limits<float>::max();
  return static_cast<float>(std::clamp(x, -kMax, kMax));
}

/// The largest float <= x (-infinity below the float range): box corners in float
/// halve the nodes' size, and rounding outward keeps every box around its
/// triangles, so pruning stays exact.
float roundDown(double x) {
  constexpr float kMax = std::numeric_limits<float>::max();
  if (x < -double(kMax)) return -std::numeric_limits<float>::infinity();
  if (x > double(kMax)) return kMax;
  const float f = static_cast<float>(x);
  return double(f) > x ? std::nextafter(f, -std::numeric_limits<float>::infinity()) : f;
}

/// The smallest float >= x (+infinity above the float range).
float roundUp(double x) {
  return -roundDown(-x);
}

/// Squared distance from p to the box [lo, hi] (0 inside).
double boxDistSq(const TriangleBvh::Node& node, const Vec3& p) {
  double sum = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double d = std::max(std::max(node.lo[k] - p[k], p[k] - node.hi[k]), 0.0);
    sum += d * d;
  }
  return sum;
}

/// Uniform double in [0, 1) from the top 53 bits of one raw 64-bit word: exact, and
/// the same on every standard library (unlike std::uniform_real_distribution).
double unit(std::mt19937_64& rng) {
  return static_cast<double>(rng() >> 11) * 0x1.0p-53;
}

/// Sums of one direction of surfaceDistance().
struct Directed {
  double sumSq = 0.0, sum = 0.0, max = 0.0;
  Eigen::Index count = 0;
};

/// Queries in Morton order for speed (consecutive queries walk mostly the same tree
/// nodes, which are in cache: on a 500k-triangle mesh about 2.5x faster than in random
/// sample order), sums in sample order: the results do not depend on the query order.
Directed measure(const Points& samples, const TriangleBvh& target) {
  const Eigen::Index n = samples.rows();
  std::vector<double> distance(static_cast<std::size_t>(n));
  for (Eigen::Index i : mortonOrder(samples))
    distance[i] = target.closestPoint(samples.row(i).transpose()).distance;
  Directed r;
  r.count = n;
  for (double d : distance) {
    r.sumSq += d * d;
    r.sum += d;
    r.max = std::max(r.max, d);
  }
  return r;
}

/// distance / diagonal, without 0/0: a zero distance is zero relative error.
double relative(double distance, double diagonal) {
  if (distance == 0.0) return 0.0;
  if (diagonal == 0.0) return std::numeric_limits<double>::infinity();
  return distance / diagonal;
}

}  // namespace

Vec3 closestPointOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  double distSq = 0.0;
  return nearestOnTriangle(p, a, b, c, distSq);
}

TriangleBvh::TriangleBvh(const TriMesh& mesh) {
  checkMesh(mesh, "TriangleBvh");
  const int n = static_cast<int>(mesh.F.rows());

  // What the split needs of a triangle, in one array that nth_element permutes in
  // place: partitioning then reads memory sequentially instead of chasing indices.
  // The centroid is kept times 3 (the factor does not change the order), in float:
  // 16 bytes an item, and split positions need no more precision.
  struct Item {
    float centroid[3];
    int face;
  };
  std::vector<Item> items(static_cast<std::size_t>(n));
  for (int f = 0; f < n; ++f) {
    const Vec3 c = corner(mesh, f, 0) + corner(mesh, f, 1) + corner(mesh, f, 2);
    items[f] = Item{{toFloat(c[0]), toFloat(c[1]), toFloat(c[2])}, f};
  }

  // A median split of m > kLeafSize triangles leaves parts of floor(m/2) and
  // ceil(m/2) > kLeafSize / 2, so there are fewer than 2 n / (kLeafSize / 2) nodes.
  nodes_.reserve(static_cast<std::size_t>(n / (kLeafSize / 2) * 2 + 1));

  // Splits items[first, first + count) at its median along the longest axis of the
  // centroids; returns the size of the first part. The comparison is a total order
  // (centroid coordinate, then face index), so which triangles go first is unique:
  // the tree is the same with any standard library's nth_element.
  auto split = [&](int first, int count) {
    const auto begin = items.begin() + first, end = begin + count;
    float clo[3], chi[3];
    for (int k = 0; k < 3; ++k) clo[k] = chi[k] = begin->centroid[k];
    for (auto it = begin; it != end; ++it)
      for (int k = 0; k < 3; ++k) {
        clo[k] = std::min(clo[k], it->centroid[k]);
        chi[k] = std::max(chi[k], it->centroid[k]);
      }
    int axis = 0;
    for (int k = 1; k < 3; ++k)
      if (chi[k] - clo[k] > chi[axis] - clo[axis]) axis = k;
    const int half = count / 2;
    std::nth_element(begin, begin + half, end, [axis](const Item& x, const Item& y) {
      return x.centroid[axis] < y.centroid[axis] ||
             (x.centroid[axis] == y.centroid[axis] && x.face < y.face);
    });
    return half;
  };
  // A node over its two children: the union of their boxes, the second child's index.
  auto join = [](Node& node, const Node& l, const Node& r, int right) {
    for (int k = 0; k < 3; ++k) {
      node.lo[k] = std::min(l.lo[k], r.lo[k]);
      node.hi[k] = std::max(l.hi[k], r.hi[k]);
    }
    node.first = right;
    node.count = 0;
  };
  // Builds the subtree of items[first, first + count) into `out`, depth first (a node,
  // its first subtree, its second), indices counted in `out`; returns its depth. Leaves
  // are sorted by face index.
  auto build = [&](auto&& self, std::vector<Node>& out, int first, int count) -> int {
    const int index = static_cast<int>(out.size());
    out.push_back(Node{});
    const auto begin = items.begin() + first, end = begin + count;
    if (count <= kLeafSize) {
      std::sort(begin, end, [](const Item& x, const Item& y) { return x.face < y.face; });
      Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
      for (auto it = begin; it != end; ++it)
        for (int k = 0; k < 3; ++k) {
          lo = lo.cwiseMin(corner(mesh, it->face, k));
          hi = hi.cwiseMax(corner(mesh, it->face, k));
        }
      Node& leaf = out[index];
      for (int k = 0; k < 3; ++k) {
        leaf.lo[k] = roundDown(lo[k]);
        leaf.hi[k] = roundUp(hi[k]);
      }
      leaf.first = first;
      leaf.count = count;
      return 1;
    }
    const int half = split(first, count);
    const int leftDepth = self(self, out, first, half);
    const int right = static_cast<int>(out.size());
    const int rightDepth = self(self, out, first + half, count - half);
    // The recursion grew `out`: index afresh rather than hold a reference.
    join(out[index], out[index + 1], out[right], right);
    return 1 + std::max(leftDepth, rightDepth);
  };
  if (numChunks(n, kParallelBuild) < 2) {
    depth_ = build(build, nodes_, 0, n);
  } else {
    // The root's two subtrees on two threads (disjoint ranges of items), the second
    // into its own array, then appended with its nodes' child indices moved: the same
    // nodes in the same order as the serial build (a 307,200-face remesh: 0.12 s).
    nodes_.push_back(Node{});
    const int half = split(0, n);
    std::vector<Node> second;
    int depths[2] = {0, 0};
    forChunks(2, 2, [&](int chunk, int, int) {
      depths[chunk] =
          chunk == 0 ? build(build, nodes_, 0, half) : build(build, second, half, n - half);
    });
    const int right = static_cast<int>(nodes_.size());
    for (Node node : second) {
      if (node.count == 0) node.first += right;
      nodes_.push_back(node);
    }
    join(nodes_[0], nodes_[1], nodes_[right], right);
    depth_ = 1 + std::max(depths[0], depths[1]);
  }

  corners_.resize(3 * static_cast<std::size_t>(n));
  faceOf_.resize(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    faceOf_[i] = items[i].face;
    for (int k = 0; k < 3; ++k) corners_[3 * i + k] = corner(mesh, items[i].face, k);
  }
}

ClosestPoint TriangleBvh::closestPoint(const Vec3& p) const {
  if (!p.allFinite()) throw Error("TriangleBvh::closestPoint: the query point is not finite");
  // Deferred subtrees: at most one per level of the current path, and depth_ is at
  // most 1 + ceil(log2(n / kLeafSize)) < 32 for any int n.
  struct Pending {
    int node;
    double distSq;
  };
  std::array<Pending, 64> stack;
  int top = 0;

  double bestSq = std::numeric_limits<double>::infinity();
  int bestTri = -1;
  Vec3 bestPoint = Vec3::Zero();
  int node = 0;
  for (;;) {
    const Node& nd = nodes_[node];
    if (nd.count > 0) {
      for (int i = nd.first; i < nd.first + nd.count; ++i) {
        double d = 0.0;
        const Vec3 x =
            nearestOnTriangle(p, corners_[3 * i], corners_[3 * i + 1], corners_[3 * i + 2], d);
        if (d < bestSq || bestTri < 0) {
          bestSq = d;
          bestTri = i;
          bestPoint = x;
        }
      }
    } else {
      int nearNode = node + 1, farNode = nd.first;
      double nearSq = boxDistSq(nodes_[nearNode], p), farSq = boxDistSq(nodes_[farNode], p);
      if (farSq < nearSq) {
        std::swap(nearNode, farNode);
        std::swap(nearSq, farSq);
      }
      if (farSq < bestSq) stack[top++] = Pending{farNode, farSq};
      // Until a triangle is found, go down even if the box distance overflowed to
      // infinity (a query ~1e154 away): every query gets some triangle.
      if (nearSq < bestSq || bestTri < 0) {
        node = nearNode;
        continue;
      }
    }
    // Next deferred subtree that may still hold something nearer.
    while (top > 0 && stack[top - 1].distSq >= bestSq) --top;
    if (top == 0) break;
    node = stack[--top].node;
  }
  return ClosestPoint{std::sqrt(bestSq), bestPoint, faceOf_[bestTri]};
}

void TriangleBvh::facesInBox(const Vec3& lo, const Vec3& hi, std::vector<int>& faces) const {
  auto meets = [&](const Node& nd) {
    for (int k = 0; k < 3; ++k)
      if (nd.hi[k] < lo[k] || nd.lo[k] > hi[k]) return false;
    return true;
  };
  std::array<int, 64> stack;
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& nd = nodes_[stack[--top]];
    if (!meets(nd)) continue;
    if (nd.count == 0) {
      stack[top++] = nd.first;
      stack[top++] = static_cast<int>(&nd - nodes_.data()) + 1;
      continue;
    }
    for (int i = nd.first; i < nd.first + nd.count; ++i) {
      const Vec3 &a = corners_[3 * i], &b = corners_[3 * i + 1], &c = corners_[3 * i + 2];
      if ((a.cwiseMin(b).cwiseMin(c).array() <= hi.array()).all() &&
          (a.cwiseMax(b).cwiseMax(c).array() >= lo.array()).all())
        faces.push_back(faceOf_[i]);
    }
  }
}

TriangleBvh::TriangleBox TriangleBvh::triangleBox(int i) const {
  const Vec3* p = &corners_[3 * static_cast<std::size_t>(i)];
  return {p[0].cwiseMin(p[1]).cwiseMin(p[2]), p[0].cwiseMax(p[1]).cwiseMax(p[2])};
}

std::vector<std::array<int, 2>> TriangleBvh::selfPairTasks(int count) const {
  // Breadth first from the root against itself: every pair that stays stands for the
  // leaf pairs under it, so splitting pairs (and dropping those whose boxes are apart)
  // keeps the cover exact.
  std::vector<std::array<int, 2>> tasks{{0, 0}};
  for (bool split = true; split && static_cast<int>(tasks.size()) < count;) {
    split = false;
    std::vector<std::array<int, 2>> next;
    for (const auto& [a, b] : tasks) {
      if (!boxesMeet(nodes_[a], nodes_[b])) continue;
      if (nodes_[a].count > 0 && nodes_[b].count > 0) {
        next.push_back({a, b});
        continue;
      }
      split = true;
      splitPair(a, b, [&](int x, int y) { next.push_back({x, y}); });
    }
    tasks.swap(next);
  }
  return tasks;
}

Points samplePoints(const TriMesh& mesh, int count, std::uint64_t seed, bool includeVertices) {
  checkMesh(mesh, "samplePoints");
  if (count < 0) throw Error("samplePoints: negative sample count " + std::to_string(count));
  const Eigen::Index nf = mesh.F.rows();

  // Cumulative face weights: areas, or 1 per face if the whole surface has zero area.
  std::vector<double> cumulative(static_cast<std::size_t>(nf));
  double total = 0.0;
  for (Eigen::Index f = 0; f < nf; ++f) {
    const Vec3 a = corner(mesh, f, 0);
    total += 0.5 * (corner(mesh, f, 1) - a).cross(corner(mesh, f, 2) - a).norm();
    cumulative[f] = total;
  }
  if (!(total > 0.0)) {
    std::iota(cumulative.begin(), cumulative.end(), 1.0);
    total = static_cast<double>(nf);
  }
  // A draw that rounds up to the total must still land on a face of positive weight.
  Eigen::Index lastPositive = nf - 1;
  while (lastPositive > 0 && cumulative[lastPositive] == cumulative[lastPositive - 1])
    --lastPositive;

  const Eigen::Index nv = includeVertices ? mesh.V.rows() : 0;
  Points out(count + nv, 3);
  std::mt19937_64 rng(seed);
  for (int i = 0; i < count; ++i) {
    const double target = unit(rng) * total;
    const auto it = std::upper_bound(cumulative.begin(), cumulative.end(), target);
    const Eigen::Index f = std::min<Eigen::Index>(it - cumulative.begin(), lastPositive);
    const double s = std::sqrt(unit(rng)), r = unit(rng);
    // a + offset, not a barycentric blend of all three corners: a point on a face
    // parallel to a coordinate plane keeps that coordinate exactly.
    const Vec3 a = corner(mesh, f, 0);
    out.row(i) =
        (a + s * ((1.0 - r) * (corner(mesh, f, 1) - a) + r * (corner(mesh, f, 2) - a))).transpose();
  }
  if (nv > 0) out.bottomRows(nv) = mesh.V;
  return out;
}

SurfaceDistance surfaceDistance(const TriMesh& a, const TriMesh& b, const DistanceOptions& opts) {
  checkMesh(a, "surfaceDistance (mesh a)");
  checkMesh(b, "surfaceDistance (mesh b)");
  if (opts.samples < 0)
    throw Error("surfaceDistance: negative sample count " + std::to_string(opts.samples));
  if (opts.samples == 0 && !opts.includeVertices)
    throw Error("surfaceDistance: nothing to measure (no samples and no vertices)");

  // Golden-ratio offset: a's and b's streams differ even for the same seed.
  const std::uint64_t seedB = opts.seed + 0x9E3779B97F4A7C15ull;
  const Points onA = samplePoints(a, opts.samples, opts.seed, opts.includeVertices);
  const Points onB = samplePoints(b, opts.samples, seedB, opts.includeVertices);
  const Directed ab = measure(onA, TriangleBvh(b));
  const Directed ba = measure(onB, TriangleBvh(a));

  SurfaceDistance r;
  r.meanAB = ab.sum / static_cast<double>(ab.count);
  r.maxAB = ab.max;
  r.meanBA = ba.sum / static_cast<double>(ba.count);
  r.maxBA = ba.max;
  r.rms = std::sqrt((ab.sumSq + ba.sumSq) / static_cast<double>(ab.count + ba.count));
  r.hausdorff = std::max(ab.max, ba.max);
  r.diagonal = boundingBoxDiagonal(b.V);
  r.rmsRelative = relative(r.rms, r.diagonal);
  r.hausdorffRelative = relative(r.hausdorff, r.diagonal);
  return r;
}

}  // namespace osdmra
