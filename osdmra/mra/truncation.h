// Truncation: keep the significant wavelet coefficients (paper section 4, math.md 5).
//
// A coefficient's importance is |d^j_m| * ||psi^j_m|| by default, so coefficients of
// different levels compare by their effect on the surface (||psi|| shrinks about 2x
// per level); the paper's plain |d^j_m| is available too. Quasi-wavelets are not
// orthogonal, so the error of a truncation is measured, not summed from the dropped
// terms: l2Distance() is the exact parametric L2 norm of the difference.
#pragma once

#include <memory>
#include <vector>

#include "osdmra/mra/decomposition.h"
#include "osdmra/mra/filter_bank.h"
#include "osdmra/subdivision/hierarchy.h"

namespace osdmra {

class ElementGram;

enum class Importance {
  Scaled,  ///< |d| * ||psi|| (default)
  Plain,   ///< |d|, as in the paper
};

/// Importance of every detail coefficient, level by level (same shapes as d.details).
/// `norms` are the ||psi^j_m|| from waveletCorrections (needed for Scaled only).
std::vector<Eigen::VectorXd> importance(const Decomposition& d,
                                        const std::vector<Eigen::VectorXd>& norms,
                                        Importance kind = Importance::Scaled);

/// Weights that put importance in the surface's own metric (multiply them in). The
/// paper's inner product gives every base triangle area 1, so a region that the
/// parameterisation shrinks (an ear over an octahedron) counts for little though it
/// is large on the surface. Weight of coefficient (j, e): the square root of the
/// surface area of the level-j triangles on its edge (one on a boundary, else two)
/// over their parametric share of the whole, both measured on the level-J mesh with
/// positions `fine` (each level-j triangle's area is that of its 4^(J-j) level-J
/// descendants). The squared importance, an L2 error, then scales with the surface
/// area it covers; on a surface whose parameterisation preserves area every weight
/// is 1. Throws Error when `fine` is not n_J x 3 or the surface has no area.
std::vector<Eigen::VectorXd> surfaceAreaWeights(const Hierarchy& h, const Points& fine);

/// Mask of kept coefficients, level by level.
using KeepMask = std::vector<std::vector<char>>;

/// Keeps the `count` most important coefficients (ties: coarser level first, then
/// lower index, so the result is deterministic).
KeepMask keepLargest(const std::vector<Eigen::VectorXd>& importance, long long count);
/// Keeps every coefficient whose importance is at least `epsilon`.
KeepMask keepAbove(const std::vector<Eigen::VectorXd>& importance, double epsilon);
/// Number of kept coefficients.
long long countKept(const KeepMask& keep);

/// A copy of `d` with the coefficients outside `keep` set to zero.
Decomposition truncate(const Decomposition& d, const KeepMask& keep);

/// c^level of the truncated surface: synthesize(bank, truncate(d, keep), level) bit for
/// bit, without copying d, and with the lifting's alpha d^j (the largest product of a
/// synthesis step) over the kept coefficients alone, since the others are zero. A level
/// of detail's extraction then costs the refinement products plus its own coefficients.
Points synthesizeTruncated(const FilterBank& bank, const Decomposition& d, const KeepMask& keep,
                           int level);

/// Exact parametric L2 distance between two functions of V^J given by their level-J
/// coefficients: sqrt(sum over x, y, z of e^T I^J e), e = a - b. Each base triangle
/// has area 1, so dividing the square by the base face count gives a mean square.
double l2Distance(const Hierarchy& h, Scheme scheme, const Points& a, const Points& b);

/// l2Distance for many pairs on one hierarchy: each level-J face's element (its
/// control set and matrix, element_gram.h) is looked up once, when it is made, instead
/// of on every call. Same values as l2Distance, bit for bit. `h` must outlive it.
class L2Distance {
 public:
  L2Distance(const Hierarchy& h, Scheme scheme);
  ~L2Distance();
  double operator()(const Points& a, const Points& b) const;

 private:
  const Hierarchy& h_;
  std::unique_ptr<ElementGram> elements_;    // owns the matrices
  std::vector<int> controlStart_, control_;  // face f: control_[controlStart_[f]...]
  std::vector<const Eigen::MatrixXd*> matrix_;
};

}  // namespace osdmra
