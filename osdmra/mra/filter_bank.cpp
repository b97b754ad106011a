#include "osdmra/mra/filter_bank.h"

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseLU>
#include <string>

#include "osdmra/base/error.h"

namespace osdmra {

FilterBank makeFilterBank(const Hierarchy& h, Scheme scheme, const WaveletOptions& wavelets,
                          const Progress& progress, bool norms) {
  FilterBank bank;
  bank.scheme = scheme;
  bank.wavelets = wavelets;
  bank.hierarchy = &h;
  bank.alpha =
      waveletCorrections(h, scheme, wavelets, progress, &bank.stats, norms ? &bank.norms : nullptr);
  return bank;
}

namespace {

using Row3 = Eigen::Array<double, 1, 3>;

// Column-wise dot products of two n x 3 blocks.
Row3 dots(const Points& a, const Points& b) {
  return (a.array() * b.array()).colwise().sum();
}

// Diagonally preconditioned BiCGSTAB on the three coordinates at once: every product
// with A serves x, y and z together (one pass over the matrix instead of three),
// while each coordinate keeps its own scalars, so this is three independent solves
// in lockstep. A is P_old, or a row block of P that is P_old, so nothing is copied.
// Returns false if it does not reach the true relative residual `tol`.
template <class Matrix>
bool bicgstab3(const Matrix& A, const Eigen::VectorXd& invDiag, const Points& b, Points& x,
               double tol, int maxIterations) {
  const Row3 bnorm = b.colwise().norm().array().max(1e-300);
  x = invDiag.asDiagonal() * b;  // Jacobi guess: P_old is close to its diagonal
  Points r = b - A * x;
  const Points r0 = r;
  const Eigen::Index n = b.rows();
  Points p = Points::Zero(n, 3), v = Points::Zero(n, 3), y(n, 3), z(n, 3), sres(n, 3), t(n, 3);
  Row3 rho = Row3::Ones(), alpha = Row3::Ones(), omega = Row3::Ones();
  auto safeDiv = [](const Row3& num, const Row3& den) -> Row3 {
    return (den != 0.0).select(num / den, Row3::Zero());
  };
  // Array expressions with row-wise broadcasts of the per-coordinate scalars: no
  // temporaries of size n inside the loop.
  for (int it = 0; it < maxIterations; ++it) {
    if (((r.colwise().norm().array() / bnorm) <= tol).all()) return x.allFinite();
    const Row3 rhoNew = dots(r0, r);
    const Row3 beta = safeDiv(rhoNew, rho) * safeDiv(alpha, omega);
    rho = rhoNew;
    p.array() = r.array() + (p.array() - v.array().rowwise() * omega).rowwise() * beta;
    y.noalias() = invDiag.asDiagonal() * p;
    v.noalias() = A * y;
    alpha = safeDiv(rho, dots(r0, v));
    sres.array() = r.array() - v.array().rowwise() * alpha;
    z.noalias() = invDiag.asDiagonal() * sres;
    t.noalias() = A * z;
    omega = safeDiv(dots(t, sres), dots(t, t));
    x.array() += y.array().rowwise() * alpha + z.array().rowwise() * omega;
    r.array() = sres.array() - t.array().rowwise() * omega;
  }
  return false;
}

template <class Matrix>
Points solveVertexRule(const Matrix& A, int j, const Points& rhs) {
  const Eigen::Index n = A.rows();
  Eigen::VectorXd invDiag(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double d = A.coeff(i, i);
    invDiag(i) = d != 0.0 ? 1.0 / d : 1.0;
  }
  Points u;
  // The residual is checked on the true residual: reconstruction depends on it.
  if (bicgstab3(A, invDiag, rhs, u, 1e-15, 300)) return u;
  // Fall back on a direct factorisation, which also tells a singular P_old apart.
  Eigen::SparseLU<Eigen::SparseMatrix<double>> lu;
  lu.compute(Eigen::SparseMatrix<double>(A));
  if (lu.info() != Eigen::Success)
    throw Error("Loop vertex-rule block P_old of level " + std::to_string(j) + " is singular: V^" +
                std::to_string(j) + " and the new-vertex functions do not span V^" +
                std::to_string(j + 1) + " for this mesh");
  u.resize(n, 3);
  for (int c = 0; c < 3; ++c) {
    const Eigen::VectorXd b = rhs.col(c);
    u.col(c) = lu.solve(b);
  }
  return u;
}

}  // namespace

Points solveOldBlock(const SparseMatrix& Pold, int j, const Points& rhs) {
  return solveVertexRule(Pold, j, rhs);
}

void analysisStep(const FilterBank& bank, int j, const Points& fine, Points& coarse,
                  Points& detail) {
  const Hierarchy& h = *bank.hierarchy;
  const int n = h.numVertices(j), nn = h.numVertices(j + 1);
  if (fine.rows() != nn)
    throw Error("analysis: level " + std::to_string(j + 1) + " needs " + std::to_string(nn) +
                " points");
  const SparseMatrix& P = h.refinement(bank.scheme, j);
  const Points u = bank.scheme == Scheme::Linear
                       ? Points(fine.topRows(n))
                       : solveVertexRule(P.topRows(n), j, fine.topRows(n));
  detail = fine.bottomRows(nn - n) - P.bottomRows(nn - n) * u;
  coarse = u + bank.alpha[j] * detail;
}

Points synthesisStep(const FilterBank& bank, int j, const Points& coarse, const Points& detail) {
  const Hierarchy& h = *bank.hierarchy;
  const int n = h.numVertices(j), nn = h.numVertices(j + 1);
  if (coarse.rows() != n || detail.rows() != nn - n)
    throw Error("synthesis: level " + std::to_string(j) + " expects " + std::to_string(n) +
                " coarse points and " + std::to_string(nn - n) + " details");
  const Points u = coarse - bank.alpha[j] * detail;
  Points fine(nn, 3);
  fine.noalias() = h.refinement(bank.scheme, j) * u;
  fine.bottomRows(nn - n) += detail;
  return fine;
}

Decomposition analyze(const FilterBank& bank, const Points& finest, const Progress& progress) {
  const Hierarchy& h = *bank.hierarchy;
  const int J = h.levels();
  Decomposition d;
  d.scheme = bank.scheme;
  d.wavelets = bank.wavelets;
  d.levels = J;
  d.baseFaces = h.faces(0);
  d.details.resize(J);
  Points c = finest;
  for (int j = J - 1; j >= 0; --j) {
    if (progress) progress("analysis", double(J - 1 - j) / J);
    Points coarse;
    analysisStep(bank, j, c, coarse, d.details[j]);
    c = std::move(coarse);
  }
  if (progress) progress("analysis", 1.0);
  d.base = std::move(c);
  return d;
}

Points synthesize(const FilterBank& bank, const Decomposition& d, int level,
                  const Progress& progress) {
  if (level < 0 || level > d.levels)
    throw Error("synthesis level " + std::to_string(level) + " is outside 0.." +
                std::to_string(d.levels));
  Points c = d.base;
  for (int j = 0; j < level; ++j) {
    if (progress) progress("synthesis", double(j) / level);
    c = synthesisStep(bank, j, c, d.details[j]);
  }
  if (progress) progress("synthesis", 1.0);
  return c;
}

}  // namespace osdmra
