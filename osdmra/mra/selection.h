// Selection: the order in which levels of detail take wavelet coefficients.
//
// A level of detail keeps a prefix of one order of the coefficients (approximation.h),
// so a budget is the longest prefix whose mesh fits. Two orders:
//
//   importance order: by |d| ||psi|| (or |d|) alone, the paper's truncation. It ignores
//   what a coefficient costs: a deep one can force a chain of coarser splits, many
//   triangles for little error removed.
//
//   rate-distortion order (default): by error removed per triangle added, a greedy
//   Lagrangian pruning of the refinement tree (Chou, Lookabaugh and Gray, "Optimal
//   pruning with applications to tree-structured source coding and modeling", 1989;
//   the tree pruning of wavelet image coders). Each step takes the refinement with the
//   largest ratio
//       gain = sum of importance^2 over the coefficients it makes available: the seed
//              and every coefficient whose edge now has both faces split (saturate()
//              keeps those at no triangle cost), an estimate of the squared L2 error
//              removed (exact for orthogonal wavelets, close for quasi-wavelets);
//       cost = triangles the closure adds to the mesh (lod.h: red, green, forced
//              coarser splits);
//   then lists the seed followed by what it made free. Ratios are kept in a priority
//   queue and re-evaluated lazily: a popped candidate is re-measured against the
//   current mesh and taken only if it still beats the next one; when a refinement is
//   taken, the candidates around and below it (whose cost it lowered) are re-measured,
//   and the coefficients of the faces it creates join the queue (the queue starts with
//   the base level's).
//   The error against triangle count then follows the lower convex hull of what single
//   refinements can reach, up to the greedy's myopia (a cheap refinement that only
//   opens the way to a valuable one is valued on its own).
//
// Both are computed once per surface; the rate-distortion one by one trial closure per
// evaluation, each touching only the faces it changes.
#pragma once

#include <Eigen/Core>
#include <string>
#include <utility>
#include <vector>

#include "osdmra/subdivision/hierarchy.h"

namespace osdmra {

enum class Selection {
  RateDistortion,  ///< error removed per triangle added (default)
  Importance,      ///< importance alone, the paper's truncation
};
const char* selectionName(Selection s);
/// Parses "rd" (also "rate-distortion") or "importance"; throws Error otherwise.
Selection parseSelection(const std::string& name);

/// A coefficient as (level j, index e of the new vertex n_j + e of M^{j+1}).
using CoefficientOrder = std::vector<std::pair<int, int>>;

/// Every coefficient, most important first (ties: coarser level, then lower index).
CoefficientOrder importanceOrder(const std::vector<Eigen::VectorXd>& importance);

/// Every coefficient of the hierarchy in rate-distortion order (see above), from the
/// importance of each (same shapes as the decomposition's details). Deterministic.
/// Throws Error when the importances do not fit the hierarchy.
CoefficientOrder rateDistortionOrder(const Hierarchy& h,
                                     const std::vector<Eigen::VectorXd>& importance);

}  // namespace osdmra
