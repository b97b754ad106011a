#include "osdmra/filter_bank.h"

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseLU>
#include <string>

#include "osdmra/error.h"

namespace osdmra {

FilterBank makeFilterBank(const Hierarchy& h, Scheme scheme, const WaveletOptions& wavelets,
                          const Progress& progress) {
  FilterBank bank;
  bank.scheme = scheme;
  bank.wavelets = wavelets;
  bank.hierarchy = &h;
  bank.alpha = waveletCorrections(h, scheme, wavelets, progress, &bank.stats, &bank.norms);
  return bank;
}

Points solveOldBlock(const SparseMatrix& Pold, int j, const Points& rhs) {
  const Eigen::Index n = Pold.rows();
  Points u(n, 3);
  Eigen::BiCGSTAB<SparseMatrix, Eigen::DiagonalPreconditioner<double>> solver;
  solver.setTolerance(1e-15);
  solver.setMaxIterations(500);
  solver.compute(Pold);
  bool ok = solver.info() == Eigen::Success;
  for (int c = 0; c < 3 && ok; ++c) {
    const Eigen::VectorXd b = rhs.col(c);
    Eigen::VectorXd x = solver.solve(b);
    // BiCGSTAB reports NoConvergence when it stalls a hair above 1e-15; accept the
    // answer on its true residual, which is what reconstruction depends on.
    const double scale = std::max(1.0, b.lpNorm<Eigen::Infinity>());
    ok = x.allFinite() && (Pold * x - b).lpNorm<Eigen::Infinity>() <= 1e-13 * scale;
    if (ok) u.col(c) = x;
  }
  if (ok) return u;
  // Fall back on a direct factorisation, which also tells a singular P_old apart.
  Eigen::SparseLU<Eigen::SparseMatrix<double>> lu;
  lu.compute(Eigen::SparseMatrix<double>(Pold));
  if (lu.info() != Eigen::Success)
    throw Error("Loop vertex-rule block P_old of level " + std::to_string(j) + " is singular: V^" +
                std::to_string(j) + " and the new-vertex functions do not span V^" +
                std::to_string(j + 1) + " for this mesh");
  for (int c = 0; c < 3; ++c) {
    const Eigen::VectorXd b = rhs.col(c);
    u.col(c) = lu.solve(b);
  }
  return u;
}

void analysisStep(const FilterBank& bank, int j, const Points& fine, Points& coarse,
                  Points& detail) {
  const Hierarchy& h = *bank.hierarchy;
  const int n = h.numVertices(j), nn = h.numVertices(j + 1);
  if (fine.rows() != nn)
    throw Error("analysis: level " + std::to_string(j + 1) + " needs " + std::to_string(nn) +
                " points");
  const SparseMatrix& P = h.refinement(bank.scheme, j);
  const Points u = bank.scheme == Scheme::Linear ? Points(fine.topRows(n))
                                                 : solveOldBlock(P.topRows(n), j, fine.topRows(n));
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
  fine = h.refinement(bank.scheme, j) * u;
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
