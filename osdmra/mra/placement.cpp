#include "osdmra/mra/placement.h"

#include <Eigen/IterativeLinearSolvers>
#include <array>
#include <string>
#include <vector>

#include "osdmra/base/error.h"

namespace osdmra {

const char* placementName(Placement p) {
  return p == Placement::Fit ? "fit" : "surface";
}

Placement parsePlacement(const std::string& name) {
  if (name == "surface") return Placement::Surface;
  if (name == "fit") return Placement::Fit;
  throw Error("placement must be surface or fit, got '" + name + "'");
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

}  // namespace osdmra
