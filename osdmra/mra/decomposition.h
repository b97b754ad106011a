// Decomposition: a surface written as a base mesh plus wavelet coefficients.
//
// S(x) = sum_i c^0_i phi^0_i(x) + sum_{j<J} sum_m d^j_m psi^j_m(x)   (paper, section 4)
// Plain data: the filter bank produces and consumes it, the .mra file stores it.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "osdmra/mesh/mesh.h"
#include "osdmra/subdivision/hierarchy.h"

namespace osdmra {

/// Which complement of V^j in V^{j+1} the psi^j_m span (math.md section 3).
enum class WaveletKind : std::uint8_t {
  Lazy = 0,   ///< psi = phi^{j+1}_m: no correction
  Quasi = 1,  ///< local Galerkin correction over the r-ring of the parent edge
  Pre = 2,    ///< exact orthogonal projection onto V^j (dense; small meshes only)
  /// Quasi-wavelets of the regular lattice at every edge (r = 1 where both ends are
  /// interior of valence 6, r = 0 elsewhere): no local solves, so a decoder builds
  /// them as fast as lazy ones; exact quasi-wavelets wherever the neighbourhood is
  /// the lattice's, an approximation of them elsewhere (rings unused).
  Fixed = 3,
};
const char* waveletKindName(WaveletKind k);
/// Parses "lazy", "quasi", "pre" or "fixed"; throws Error otherwise.
WaveletKind parseWaveletKind(const std::string& name);

/// Options of the wavelet construction.
struct WaveletOptions {
  WaveletKind kind = WaveletKind::Quasi;
  /// Quasi-wavelets: rings around the parent edge {a,b} allowed in the correction;
  /// 0 means {a,b} only. Rings r cover the paper's (r+1)-disc around each of a, b.
  int rings = 1;  // kDefaultRings in wavelets.h
};

struct Decomposition {
  Scheme scheme = Scheme::Loop;
  WaveletOptions wavelets;
  int levels = 0;               ///< J
  Faces baseFaces;              ///< M^0
  Points base;                  ///< c^0: n_0 x 3
  std::vector<Points> details;  ///< d^j for j = 0..J-1: (n_{j+1} - n_j) x 3
  /// Input vertex of each canonical level-J vertex (empty: the input was canonical).
  /// AnalysedSurface::reconstruct (pipeline.h) writes level-J vertices back in the
  /// input's order with it.
  std::vector<int> inputOrder;
  /// The input's faces in its own order and numbering (empty: canonical faces).
  Faces inputFaces;
};

}  // namespace osdmra
