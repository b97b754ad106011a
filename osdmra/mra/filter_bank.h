// FilterBank: linear-time analysis and synthesis in lifted form (math.md section 4).
//
//   synthesis:  u = c^j - alpha d^j;  c^{j+1}_old = P_old u;  c^{j+1}_new = P_new u + d^j
//   analysis:   solve P_old u = c^{j+1}_old;  d^j = c^{j+1}_new - P_new u;  c^j = u + alpha d^j
//
// This is c^{j+1} = P c^j + Q d^j with Q = E - P alpha (paper sections 2.2, 3.3)
// without ever forming Q or [P Q]^{-1}. Polyhedral: P_old is the identity and every
// step is local. Loop: P_old is Loop's vertex rule on M^j, the one non-local step,
// solved by preconditioned BiCGSTAB (constant iteration count, so linear time); a
// singular P_old is reported with its level.
#pragma once

#include <vector>

#include "osdmra/base/progress.h"
#include "osdmra/mra/decomposition.h"
#include "osdmra/mra/wavelets.h"
#include "osdmra/subdivision/hierarchy.h"

namespace osdmra {

/// Everything analysis and synthesis need for one hierarchy, scheme and wavelet
/// choice; build once, then analyse or synthesise any number of surfaces.
struct FilterBank {
  Scheme scheme = Scheme::Loop;
  WaveletOptions wavelets;
  const Hierarchy* hierarchy = nullptr;  ///< not owned; must outlive the filter bank
  std::vector<AlphaMatrix> alpha;        ///< alpha^j, j = 0..J-1 (wavelets.h)
  std::vector<Eigen::VectorXd> norms;    ///< ||psi^j_m||, for truncation (truncation.h)
  WaveletStats stats;
};

/// With `norms` false, FilterBank::norms stays empty (analysis and synthesis do not
/// read it; truncation and importance do).
FilterBank makeFilterBank(const Hierarchy& h, Scheme scheme, const WaveletOptions& wavelets,
                          const Progress& progress = {}, bool norms = true);

/// Decomposes c^J (n_J x 3, canonical order) into c^0 and d^0..d^{J-1}.
/// The result's baseFaces, scheme, wavelets and levels are filled in.
Decomposition analyze(const FilterBank& bank, const Points& finest, const Progress& progress = {});

/// Rebuilds c^level (0 <= level <= J) from c^0 and d^0..d^{level-1}.
Points synthesize(const FilterBank& bank, const Decomposition& d, int level,
                  const Progress& progress = {});

/// The one non-local step of Loop analysis: solves P_old u = rhs (P_old: the
/// vertex-rule rows of P^{j+1}, n_j x n_j). Preconditioned BiCGSTAB, checked on its
/// true residual; a sparse LU when that fails. Throws Error naming level j when
/// P_old is singular.
Points solveOldBlock(const SparseMatrix& Pold, int j, const Points& rhs);

/// One analysis step: c^{j+1} -> (c^j, d^j).
void analysisStep(const FilterBank& bank, int j, const Points& fine, Points& coarse,
                  Points& detail);
/// One synthesis step: (c^j, d^j) -> c^{j+1}.
Points synthesisStep(const FilterBank& bank, int j, const Points& coarse, const Points& detail);

}  // namespace osdmra
