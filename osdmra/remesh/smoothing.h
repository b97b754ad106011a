// Step 2 of remesh.h: smoothing of the parameterisation (MAPS, Lee et al. 1998,
// section 4.3, here as Floater's mean value map). The simplification places each input
// vertex where the removals happened to put it; the map between those places, affine on
// each input triangle (charts.h), is then bijective and bounded in distortion, but it
// kinks from one input triangle to the next, and a uniform grid sampled across a kink
// folds. Each free input vertex moves, in its base face's chart, towards the mean value
// combination of its neighbours' places (weights from the input's own angles and
// lengths: positive, and exact for a flat one-ring, so a planar region is mapped
// affinely); a move is kept only if every triangle around the vertex stays positively
// oriented with anisotropy within the bound, so the map stays a bijection with bounded
// distortion at every step.
#pragma once

#include <vector>

#include "osdmra/mesh/connectivity.h"
#include "osdmra/remesh/charts.h"
#include "osdmra/remesh/simplify.h"

namespace osdmra::remeshing {

struct SmoothingOptions {
  /// Sweeps over the free vertices (Gauss-Seidel).
  int sweeps = 5;
  /// Largest anisotropy (distortion.h) a move may leave around the vertex; a vertex
  /// already above it may move only if that lowers its worst.
  double anisotropy = 4;
};

struct SmoothingReport {
  int moves = 0;    ///< accepted moves over all sweeps
  int refused = 0;  ///< moves refused (a fold or too much distortion)
};

/// Smooths the places of `s.params` of the input vertices that are free: removed, not
/// on a feature line or the boundary (`pinned`), with a closed one-ring.
SmoothingReport smoothParameters(const TriMesh& input, const Connectivity& inputConn,
                                 const BaseCharts& charts, const std::vector<char>& pinned,
                                 Simplification& s, const SmoothingOptions& options = {});

}  // namespace osdmra::remeshing
