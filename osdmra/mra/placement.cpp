#include "osdmra/mra/placement.h"

#include <Eigen/IterativeLinearSolvers>
#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "osdmra/base/detail/parallel.h"
#include "osdmra/base/error.h"
#include "osdmra/geometry/distance.h"
#include "osdmra/geometry/normals.h"
#include "osdmra/geometry/self_intersection.h"
#include "osdmra/geometry/surface_walk.h"
#include "osdmra/mesh/connectivity.h"

namespace osdmra {

const char* placementName(Placement p) {
  return p == Placement::Closest  ? "closest"
         : p == Placement::Fit    ? "fit"
         : p == Placement::Levels ? "levels"
                                  : "surface";
}

Placement parsePlacement(const std::string& name) {
  if (name == "surface") return Placement::Surface;
  if (name == "fit") return Placement::Fit;
  if (name == "closest") return Placement::Closest;
  if (name == "levels") return Placement::Levels;
  throw Error("placement must be surface, fit, closest or levels, got '" + name + "'");
}

namespace {

using Triplets = std::vector<Eigen::Triplet<double>>;

// One level-of-detail face's source: a hierarchy triangle (level, index) with corners
// (v0, v1, v2), and how its level-J vertices map onto the mesh's compact vertices.
struct Source {
  int level, face;
  // Whole triangle: the compact indices of v0, v1, v2.
  // Green pair: split edge i = (v_i, v_{i+1}); half 0 is (a, m, o), half 1 (m, b, o).
  int split = -1;
  std::array<int, 3> whole{};
  std::array<int, 3> half0{}, half1{};
};

// The weights of a level-J vertex with barycentric coordinates `w` in the source's
// hierarchy triangle.
void emit(const Source& s, int vertex, const Eigen::Vector3d& w, Triplets& out) {
  auto put = [&](int col, double x) {
    if (x != 0.0) out.emplace_back(vertex, col, x);
  };
  if (s.split < 0) {
    for (int k = 0; k < 3; ++k) put(s.whole[k], w(k));
    return;
  }
  const double a = w(s.split), b = w((s.split + 1) % 3), o = w((s.split + 2) % 3);
  // p = a A + b B + o O with M = (A + B) / 2: in half 0 (a >= b) B = 2M - A, in
  // half 1 A = 2M - B.
  if (a >= b) {
    put(s.half0[0], a - b);
    put(s.half0[1], 2 * b);
    put(s.half0[2], o);
  } else {
    put(s.half1[0], 2 * a);
    put(s.half1[1], b - a);
    put(s.half1[2], o);
  }
}

// Walks the hierarchy triangle of `s` down to M^J, carrying the barycentric
// coordinates of each sub-triangle's corners (columns), with the child layout of
// hierarchy.h: (c0, m0, m2), (m0, c1, m1), (m2, m1, c2), (m1, m2, m0).
void descend(const Hierarchy& h, const Source& s, std::vector<char>& done, Triplets& out) {
  const int J = h.levels();
  struct Item {
    int level, face;
    Eigen::Matrix3d corners;
  };
  std::vector<Item> stack{{s.level, s.face, Eigen::Matrix3d::Identity()}};
  while (!stack.empty()) {
    const Item it = stack.back();
    stack.pop_back();
    if (it.level == J) {
      for (int k = 0; k < 3; ++k) {
        const int v = h.faces(J)(it.face, k);
        if (done[v]) continue;
        done[v] = 1;
        emit(s, v, it.corners.col(k), out);
      }
      continue;
    }
    const Eigen::Vector3d c0 = it.corners.col(0), c1 = it.corners.col(1), c2 = it.corners.col(2);
    const Eigen::Vector3d m0 = 0.5 * (c0 + c1), m1 = 0.5 * (c1 + c2), m2 = 0.5 * (c2 + c0);
    const int f = 4 * it.face, l = it.level + 1;
    Eigen::Matrix3d m;
    m << c0, m0, m2;
    stack.push_back({l, f, m});
    m << m0, c1, m1;
    stack.push_back({l, f + 1, m});
    m << m2, m1, c2;
    stack.push_back({l, f + 2, m});
    m << m1, m2, m0;
    stack.push_back({l, f + 3, m});
  }
}

}  // namespace

SparseMatrix lodInterpolation(const Hierarchy& h, const LodMesh& lod) {
  const int nf = static_cast<int>(lod.compactFaces.rows());
  if (static_cast<int>(lod.faceOrigin.size()) != nf || static_cast<int>(lod.faceLevel.size()) != nf)
    throw Error("lodInterpolation: the level of detail has no face origins");
  const int nJ = h.numVertices(h.levels());
  std::vector<char> done(static_cast<std::size_t>(nJ), 0);
  Triplets triplets;
  triplets.reserve(static_cast<std::size_t>(nJ) * 3);
  for (int r = 0; r < nf; ++r) {
    Source s{lod.faceLevel[r], lod.faceOrigin[r]};
    const auto v = h.faces(s.level).row(s.face);
    const bool green =
        r + 1 < nf && lod.faceOrigin[r + 1] == s.face && lod.faceLevel[r + 1] == s.level;
    if (!green) {
      for (int k = 0; k < 3; ++k) s.whole[k] = lod.compactFaces(r, k);
    } else {
      // Half 0 is (a, m, o) with a = v_i: its first corner names the split edge.
      const int a = lod.faces(r, 0);
      s.split = a == v(0) ? 0 : a == v(1) ? 1 : 2;
      for (int k = 0; k < 3; ++k) {
        s.half0[k] = lod.compactFaces(r, k);
        s.half1[k] = lod.compactFaces(r + 1, k);
      }
      ++r;
    }
    descend(h, s, done, triplets);
  }
  SparseMatrix L(nJ, static_cast<Eigen::Index>(lod.vertices.size()));
  L.setFromTriplets(triplets.begin(), triplets.end());
  return L;
}

Points fitPositions(const SparseMatrix& L, const Points& target, const Points& start,
                    const FitOptions& options) {
  if (target.rows() != L.rows() || start.rows() != L.cols())
    throw Error("fitPositions: " + std::to_string(L.rows()) + " x " + std::to_string(L.cols()) +
                " interpolation, " + std::to_string(target.rows()) + " targets, " +
                std::to_string(start.rows()) + " starting points");
  const Eigen::SparseMatrix<double> A = (L.transpose() * L).pruned();
  const Points b = L.transpose() * target;
  Eigen::ConjugateGradient<Eigen::SparseMatrix<double>, Eigen::Lower | Eigen::Upper> cg;
  cg.setMaxIterations(options.iterations);
  cg.setTolerance(options.tolerance);
  cg.compute(A);
  if (cg.info() != Eigen::Success) throw Error("fitPositions: the normal equations are singular");
  Points x(start.rows(), 3);
  for (int k = 0; k < 3; ++k) x.col(k) = cg.solveWithGuess(b.col(k), start.col(k));
  return x;
}

namespace {

using Solver = Eigen::ConjugateGradient<Eigen::SparseMatrix<double>, Eigen::Lower | Eigen::Upper>;

// The normal equations of one Gauss-Newton step, assembled as 3 x 3 blocks: every
// residual lies on one face of the level of detail, so the blocks are those of vertices
// sharing a face, and each residual adds w_a w_c M to block (a, c) for its corners' weights
// w and its 3 x 3 form M (sum over its scalar rows d of d d^T), and w_a M-row targets to
// the right-hand side. Direct assembly: forming J^T J took a quarter of a round.
class NormalEquations {
 public:
  NormalEquations(const Faces& faces, int numVertices)
      : start_(static_cast<std::size_t>(numVertices) + 1, 0),
        rhs_(Eigen::VectorXd::Zero(3 * numVertices)) {
    std::vector<std::vector<int>> near(static_cast<std::size_t>(numVertices));
    for (int v = 0; v < numVertices; ++v) near[v].push_back(v);
    for (Eigen::Index f = 0; f < faces.rows(); ++f)
      for (int a = 0; a < 3; ++a)
        for (int c = 0; c < 3; ++c)
          if (a != c) near[faces(f, a)].push_back(faces(f, c));
    for (int v = 0; v < numVertices; ++v) {
      std::sort(near[v].begin(), near[v].end());
      near[v].erase(std::unique(near[v].begin(), near[v].end()), near[v].end());
      start_[v + 1] = start_[v] + static_cast<int>(near[v].size());
      column_.insert(column_.end(), near[v].begin(), near[v].end());
    }
    block_.assign(column_.size(), Eigen::Matrix3d::Zero());
  }
  // A residual on corners (`count` of them, weights w) with form M and M-row target b:
  // adds w_a w_c M to block (a, c) and w_a b to the right-hand side at a.
  void add(const std::array<int, 3>& corners, const std::array<double, 3>& w, int count,
           const Eigen::Matrix3d& M, const Eigen::Vector3d& b) {
    for (int i = 0; i < count; ++i) {
      rhs_.segment<3>(3 * corners[i]) += w[i] * b;
      for (int k = 0; k < count; ++k) block(corners[i], corners[k]) += w[i] * w[k] * M;
    }
  }
  Points solve(const Points& guess, const FitOptions& options) const {
    const Eigen::Index n = guess.rows();
    std::vector<Eigen::Triplet<double>> triplets;
    triplets.reserve(9 * block_.size());
    for (Eigen::Index v = 0; v < n; ++v)
      for (int q = start_[v]; q < start_[v + 1]; ++q)
        for (int r = 0; r < 3; ++r)
          for (int c = 0; c < 3; ++c)
            if (block_[q](r, c) != 0)
              triplets.emplace_back(static_cast<int>(3 * v + r), 3 * column_[q] + c,
                                    block_[q](r, c));
    Eigen::SparseMatrix<double> A(3 * n, 3 * n);
    A.setFromTriplets(triplets.begin(), triplets.end());
    Solver cg;
    cg.setMaxIterations(4 * options.iterations);  // xyz coupled: a system three times larger
    cg.setTolerance(options.tolerance);
    cg.compute(A);
    Eigen::VectorXd x0(3 * n);
    for (Eigen::Index v = 0; v < n; ++v) x0.segment<3>(3 * v) = guess.row(v).transpose();
    const Eigen::VectorXd x = cg.solveWithGuess(rhs_, x0);
    Points out(n, 3);
    for (Eigen::Index v = 0; v < n; ++v) out.row(v) = x.segment<3>(3 * v).transpose();
    return out;
  }

 private:
  Eigen::Matrix3d& block(int a, int c) {
    const auto first = column_.begin() + start_[a], last = column_.begin() + start_[a + 1];
    return block_[static_cast<std::size_t>(std::lower_bound(first, last, c) - column_.begin())];
  }
  std::vector<int> start_, column_;  // CSR over vertices: the vertices sharing a face
  std::vector<Eigen::Matrix3d> block_;
  Eigen::VectorXd rhs_;
};

// Per halfedge 3f + k (from corner k to corner k + 1 of face f): on the boundary?
std::vector<char> boundaryHalfedges(const Faces& F, int numVertices) {
  const Connectivity c(F, numVertices);
  std::vector<char> out(static_cast<std::size_t>(3 * F.rows()));
  for (std::size_t h = 0; h < out.size(); ++h) out[h] = c.twin(static_cast<int>(h)) < 0;
  return out;
}

// Whether a closest point of `mesh` lies on one of its boundary edges (`boundary`:
// boundaryHalfedges). Past a boundary the surface's tangent plane bounds nothing, so a
// match there is taken point to point: matched to its plane, a level of detail's
// border slid off an open scan's rim (the lion over 300 faces at 1,667 triangles: its
// Hausdorff distance 1.3e-2 with the fit, 3.8e-2 after the rounds, all at the rim).
bool onBoundary(const TriMesh& mesh, const std::vector<char>& boundary, const ClosestPoint& c) {
  std::array<double, 3> b{};
  if (!barycentricIn(mesh, c.face, c.point, b)) return false;
  constexpr double kOnEdge = 1e-9;  // barycentric coordinate of the corner opposite it
  for (int k = 0; k < 3; ++k)
    if (b[k] < kOnEdge && boundary[3 * static_cast<std::size_t>(c.face) + (k + 1) % 3]) return true;
  return false;
}

// Where the level of detail X and the full surface are nearest each other, both ways:
// for each level-J point L_i X, the closest point of the full surface and the unit
// normal there; for each of the full surface's points (ClosestTarget::points), the
// closest point of the level of detail (a face and barycentric coordinates) and that
// face's unit normal; and which of them lie on the other surface's boundary.
struct Matches {
  Points toFull, fullNormal;
  std::vector<char> toFullBoundary;
  std::vector<int> lodFace;
  std::vector<std::array<double, 3>> lodBary;
  Points lodNormal;
  std::vector<char> lodBoundary;
  double squaredDistance = 0;  // summed over both: what the rounds lower
};

// `lodBoundary`: the level of detail's boundaryHalfedges, the same in every round.
Matches match(const Points& at, const TriMesh& lod, const std::vector<char>& lodBoundary,
              const ClosestTarget& target) {
  const TriMesh& full = target.mesh;
  Matches m{Points(at.rows(), 3),
            Points(at.rows(), 3),
            std::vector<char>(at.rows()),
            std::vector<int>(target.points.rows()),
            std::vector<std::array<double, 3>>(target.points.rows()),
            Points(target.points.rows(), 3),
            std::vector<char>(target.points.rows())};
  Eigen::VectorXd forward(at.rows()), backward(target.points.rows());
  const int n = static_cast<int>(at.rows());
  forChunks(n, numChunks(n, 1 << 12), [&](int, int begin, int end) {
    for (int i = begin; i < end; ++i) {
      const ClosestPoint c = target.bvh.closestPoint(at.row(i).transpose());
      m.toFull.row(i) = c.point.transpose();
      m.fullNormal.row(i) = faceNormal(full, c.face).normalized().transpose();
      m.toFullBoundary[i] = onBoundary(full, target.boundary, c);
      forward(i) = c.distance * c.distance;
    }
  });
  const TriangleBvh lodBvh(lod);
  const int nf = static_cast<int>(target.points.rows());
  forChunks(nf, numChunks(nf, 1 << 12), [&](int, int begin, int end) {
    for (int v = begin; v < end; ++v) {
      const ClosestPoint c = lodBvh.closestPoint(target.points.row(v).transpose());
      std::array<double, 3> bary{1.0 / 3, 1.0 / 3, 1.0 / 3};
      if (barycentricIn(lod, c.face, c.point, bary)) bary = clampedBarycentric(bary);
      m.lodFace[v] = c.face;
      m.lodBary[v] = bary;
      m.lodNormal.row(v) = faceNormal(lod, c.face).normalized().transpose();
      m.lodBoundary[v] = onBoundary(lod, lodBoundary, c);
      backward(v) = c.distance * c.distance;
    }
  });
  m.squaredDistance = forward.sum() + backward.sum();
  return m;
}

// One Gauss-Newton step of point-to-plane matching both ways, from x: each level-J point
// onto the full surface's tangent plane at its match, with weight w on sliding along it
// (else a flat region lets vertices slide freely), and each of the full surface's points
// onto the plane of the level of detail's face at its match; a match on either
// surface's boundary onto the matched point itself.
Points pointToPlaneStep(const SparseMatrix& L, const Faces& faces, const ClosestTarget& target,
                        const Points& at, const Matches& m, const Points& x,
                        const FitOptions& options) {
  NormalEquations equations(faces, static_cast<int>(x.rows()));
  const double w = options.tangentWeight;
  for (Eigen::Index i = 0; i < L.rows(); ++i) {
    std::array<int, 3> corners{};
    std::array<double, 3> weights{};
    int count = 0;
    for (SparseMatrix::InnerIterator a(L, i); a && count < 3; ++a, ++count) {
      corners[count] = static_cast<int>(a.col());
      weights[count] = a.value();
    }
    const Eigen::Vector3d normal = m.fullNormal.row(i).transpose();
    if (!normal.allFinite()) continue;  // a degenerate face of the full surface
    if (m.toFullBoundary[i]) {
      equations.add(corners, weights, count, Eigen::Matrix3d::Identity(),
                    m.toFull.row(i).transpose());
      continue;
    }
    // Across the plane: onto it; along it: weight w towards where the point is.
    const Eigen::Matrix3d across = normal * normal.transpose();
    const Eigen::Matrix3d along = Eigen::Matrix3d::Identity() - across;
    equations.add(corners, weights, count, across + w * along,
                  across * m.toFull.row(i).transpose() + w * along * at.row(i).transpose());
  }
  for (Eigen::Index v = 0; v < target.points.rows(); ++v) {
    const Eigen::Vector3d normal = m.lodNormal.row(v).transpose();
    if (!normal.allFinite()) continue;
    const int f = m.lodFace[v];
    const Eigen::Matrix3d across = m.lodBoundary[v] ? Eigen::Matrix3d::Identity()
                                                    : Eigen::Matrix3d(normal * normal.transpose());
    equations.add({faces(f, 0), faces(f, 1), faces(f, 2)}, m.lodBary[v], 3, across,
                  across * target.points.row(v).transpose());
  }
  return equations.solve(x, options);
}

// (b - a) x (c - a) of every face.
Points faceNormals(const Faces& F, const Points& X) {
  Points N(F.rows(), 3);
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const Eigen::Vector3d a = X.row(F(f, 0)), b = X.row(F(f, 1)), c = X.row(F(f, 2));
    N.row(f) = (b - a).cross(c - a).transpose();
  }
  return N;
}

// `to`, except that the vertices of every face it would turn over (against its normal
// in `reference`) stay at x, until no face turns over: that holds by construction once
// every vertex stays, x having none.
Points stepWithoutFolds(const Faces& F, const Points& reference, const Points& x,
                        const Points& to) {
  Points trial = to;
  for (;;) {
    const Eigen::VectorXd facing =
        (reference.array() * faceNormals(F, trial).array()).rowwise().sum();
    bool folded = false;
    for (Eigen::Index f = 0; f < F.rows(); ++f)
      if (!(facing(f) > 0))
        for (int k = 0; k < 3; ++k)
          if (trial.row(F(f, k)) != x.row(F(f, k))) {
            trial.row(F(f, k)) = x.row(F(f, k));
            folded = true;
          }
    if (!folded) return trial;
  }
}

CrossingPairs crossingPairs(const Faces& F, const Points& V) {
  if (F.rows() == 0) return {};  // nothing to cross (findSelfIntersections refuses it)
  TriMesh m;
  m.V = V;
  m.F = F;
  return osdmra::crossingPairs(m);  // sorted
}

// withoutNewCrossings with the crossing pairs of `from` given (`pairs`), which it
// replaces with those of the result: Closest's rounds start each from the last one's
// result, whose pairs the last check has just found.
Points withoutNewCrossings(const Faces& F, const Points& from, const Points& to,
                           CrossingPairs& pairs) {
  const CrossingPairs allowed = std::move(pairs);
  // A vertex of a newly crossing face first moves half as far, then a quarter, ..., and
  // after kHalvings back to `from`: taken back whole, the fit's gain went with it (a
  // screwdriver's level of detail at 66 triangles: 0.0077 -> 0.0119 RMS).
  constexpr int kHalvings = 4;
  std::vector<int> halvings(static_cast<std::size_t>(from.rows()), 0);
  Points trial = to;
  for (;;) {
    pairs = crossingPairs(F, trial);
    std::vector<char> hit(halvings.size(), 0);
    for (const std::array<int, 2>& pair : pairs)
      if (!std::binary_search(allowed.begin(), allowed.end(), pair))
        for (int f : pair)
          for (int k = 0; k < 3; ++k)
            if (trial.row(F(f, k)) != from.row(F(f, k))) hit[F(f, k)] = 1;
    bool moved = false;
    for (std::size_t v = 0; v < hit.size(); ++v) {
      if (!hit[v]) continue;
      const Eigen::Index i = static_cast<Eigen::Index>(v);
      const double t = ++halvings[v] > kHalvings ? 0.0 : std::ldexp(1.0, -halvings[v]);
      trial.row(i) = from.row(i) + t * (to.row(i) - from.row(i));
      moved = true;
    }
    if (!moved) return trial;
  }
}

}  // namespace

Points withoutNewCrossings(const Faces& F, const Points& from, const Points& to) {
  CrossingPairs pairs = crossingPairs(F, from);
  return withoutNewCrossings(F, from, to, pairs);
}

ClosestTarget::ClosestTarget(const TriMesh& m, int samples)
    : mesh(m), bvh(m), boundary(boundaryHalfedges(m.F, static_cast<int>(m.V.rows()))), points(m.V) {
  if (samples <= 0) return;
  const Points drawn = samplePoints(m, samples, 1);
  points.conservativeResize(m.V.rows() + drawn.rows(), 3);
  points.bottomRows(drawn.rows()) = drawn;
}

Points fitToClosestPoints(const SparseMatrix& L, const Faces& faces, const ClosestTarget& target,
                          const Points& start, const FitOptions& options) {
  if (start.rows() != L.cols() || (faces.size() > 0 && faces.maxCoeff() >= start.rows()))
    throw Error("fitToClosestPoints: " + std::to_string(L.rows()) + " x " +
                std::to_string(L.cols()) + " interpolation, " + std::to_string(start.rows()) +
                " starting points, faces up to vertex " +
                std::to_string(faces.size() > 0 ? faces.maxCoeff() : -1));
  const Points reference = faceNormals(faces, start);
  const std::vector<char> lodBoundary = boundaryHalfedges(faces, static_cast<int>(start.rows()));
  auto matchAt = [&](const Points& X) {
    TriMesh lod;
    lod.V = X;
    lod.F = faces;
    return match(L * X, lod, lodBoundary, target);
  };
  Points x = start;
  Matches m = matchAt(x);
  CrossingPairs crossings = crossingPairs(faces, x);
  for (int round = 0; round < options.closestRounds; ++round) {
    const Points step = stepWithoutFolds(faces, reference, x,
                                         pointToPlaneStep(L, faces, target, L * x, m, x, options));
    CrossingPairs nextCrossings = crossings;
    const Points next = withoutNewCrossings(faces, x, step, nextCrossings);
    // A Gauss-Newton step can overshoot where matches jump (a rough surface): a round
    // that does not bring the two surfaces closer ends the rounds.
    Matches nextMatches = matchAt(next);
    if (!(nextMatches.squaredDistance < m.squaredDistance)) break;
    x = next;
    m = std::move(nextMatches);
    crossings = std::move(nextCrossings);
  }
  return x;
}

}  // namespace osdmra
