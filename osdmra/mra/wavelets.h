// Wavelets: the correction coefficients alpha of psi^j_m (paper 3.3, math.md 3).
//
//     psi^j_m = phi^{j+1}_m - sum_{i in S(m)} alpha_{i,m} phi^j_i
//
// for each new vertex m of M^{j+1} (midpoint of edge {a,b} of M^j). alpha solves
// the local Galerkin system I^j[S,S] alpha = b[S], b = P^T I^{j+1} e_m, so that
// <psi^j_m, phi^j_k> = 0 for every k in S(m):
//   lazy   S = {}                        psi = phi^{j+1}_m
//   quasi  S = the r-ring of {a,b}       local support, linear time
//   pre    S = every vertex of M^j       exactly orthogonal to V^j, dense (stored
//                                        without its exact zeros)
//
// The paper's quasi-wavelets "supported on k-discs" choose S as the vertices of the
// k-disc around the new vertex; r rings around the parent edge {a,b} contain the
// vertices within r+1 edges of m's position at level j, i.e. the paper's (r+1)-disc
// of M^j around the edge. r = 2 is the paper's configuration of section 4.
//
// alpha depends only on the topology of a bounded neighbourhood of the edge (the
// inner products depend on topology alone), so it is computed once per distinct
// neighbourhood, keyed by a canonical encoding, and shared: regular regions, which
// are almost everything at fine levels, cost one local solve in total.
#pragma once

#include <vector>

#include "osdmra/base/progress.h"
#include "osdmra/mra/decomposition.h"
#include "osdmra/subdivision/hierarchy.h"

namespace osdmra {

/// Default number of rings of quasi-wavelets (chosen from the measurements in
/// docs/WAVELETS.md).
constexpr int kDefaultRings = 1;

/// Largest finest-level vertex count for which pre-wavelets (dense) are allowed.
constexpr int kMaxPreWaveletVertices = 5000;

struct WaveletStats {
  long long localSolves = 0;  ///< distinct neighbourhoods actually solved
  long long reused = 0;       ///< new vertices that reused a cached solution
  /// Neighbourhoods whose canonical key was built: the others' were known from their
  /// parent edge's (or were the lattice's).
  long long keys = 0;
};

/// alpha^j: n_j x (n_{j+1} - n_j), column-major; column e belongs to the new vertex
/// n_j + e and its pattern is S(m).
using AlphaMatrix = Eigen::SparseMatrix<double>;

/// alpha^j for j = 0..J-1. When `norms` is given it receives ||psi^j_m|| for every
/// new vertex of every level (the importance weights of truncation, math.md 5).
std::vector<AlphaMatrix> waveletCorrections(const Hierarchy& h, Scheme scheme,
                                            const WaveletOptions& options,
                                            const Progress& progress = {},
                                            WaveletStats* stats = nullptr,
                                            std::vector<Eigen::VectorXd>* norms = nullptr);

/// The columns of alpha^j that `needed[j]` marks (one entry per new vertex of level
/// j + 1), the others left empty: what a decoder needs to synthesise where most
/// coefficients are zero (a wavelet whose coefficient is zero adds nothing, whatever its
/// column). The marked columns are those of the call above, value for value; only
/// quasi-wavelets skip work (their columns are solved), the others are cheap whole.
std::vector<AlphaMatrix> waveletCorrections(const Hierarchy& h, Scheme scheme,
                                            const WaveletOptions& options,
                                            const std::vector<std::vector<char>>& needed);

/// Whether alpha^j of these wavelets is read off the hierarchy alone, level by level
/// (fixed and lazy wavelets: no neighbourhood solved), as a decoder needs.
bool correctionsAreLocal(const WaveletOptions& options);

/// alpha^j of wavelets whose corrections are local (correctionsAreLocal), written into
/// `alpha`: the levels are independent, so a decoder can share them among threads.
void localCorrections(const Hierarchy& h, Scheme scheme, WaveletKind kind, int j,
                      AlphaMatrix& alpha);

/// The level-(j+1) coefficients of psi^j_m for every new vertex: Q^{j+1} = E - P alpha
/// (n_{j+1} x (n_{j+1} - n_j)). For tests and diagnostics; the filter bank never
/// forms it.
SparseMatrix synthesisMatrix(const Hierarchy& h, Scheme scheme, int j, const AlphaMatrix& alpha);

/// How far the psi^j_m are from the orthogonal complement of V^j, normalised:
/// c(m, k) = |<psi^j_m, phi^j_k>| / (||psi^j_m|| ||phi^j_k||).
struct OrthogonalityStats {
  double worstInside = 0;  ///< max of c over k in S(m) (0 up to rounding: Galerkin)
  double worst = 0;        ///< max of c over all m and k
  double mean = 0;         ///< mean of max_k c(m, k) over m
};

/// Measures OrthogonalityStats for level j. Assembles I^j and I^{j+1} in full:
/// meant for diagnostics and tests on meshes of moderate size.
OrthogonalityStats orthogonality(const Hierarchy& h, Scheme scheme, int j,
                                 const AlphaMatrix& alpha);

}  // namespace osdmra
