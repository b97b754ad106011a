// Step 3 of remesh.h: smoothing of the parameterisation (MAPS, Lee et al. 1998,
// section 4.3, with Sander et al. 2001's L2 stretch as the measure). The simplification
// places each input vertex where the removals happened to put it: a bijection with
// bounded distortion, but one that may squeeze much of the surface into a small part of
// a base face (the bunny over 150 faces had grid triangles of 2.3% of its diagonal
// there), and a uniform grid then samples that part coarsely. Each free input vertex
// moves down the gradient of its one-ring's stretch (surface area times the squared
// norm of the map from the base face's chart to the surface: lowest where the surface
// is spread evenly over the chart, and exactly the affine map on a flat one-ring); a
// move is kept only if every triangle around the vertex stays positively oriented with
// anisotropy within the bound, in every chart that sees it, so the map stays a
// bijection with bounded distortion at every step. (Floater's mean value map, the
// first measure tried, left more runs of the corpus with defects and was dropped.)
#pragma once

#include <vector>

#include "osdmra/mesh/connectivity.h"
#include "osdmra/remesh/charts.h"
#include "osdmra/remesh/simplify.h"

namespace osdmra::remeshing {

struct SmoothingOptions {
  /// Sweeps over the free vertices (Gauss-Seidel), one descent step per vertex each.
  int sweeps = 10;
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
