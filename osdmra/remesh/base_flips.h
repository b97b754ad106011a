// Base edge flips after the simplification, where the grid sampled over a pair of base
// faces folds and over the flipped pair would fold less: a base face with one wide angle
// (a cap) holds its chart's points along one long side, and the grid over it can fold
// there (the bunny over 300 base faces at J = 5: its one crossing pair, in a cap of 145
// degrees along a hole's rim). Each flip is one more step of the parameterisation,
// recorded in the history as a removal is, so traceToInput undoes it and the map stays a
// bijection by construction: the two faces are laid flat about their shared edge, and a
// flip is made only where that quad is strictly convex.
#pragma once

#include "osdmra/mesh/mesh.h"
#include "osdmra/remesh/simplify.h"

namespace osdmra::remeshing {

struct BaseFlipOptions {
  /// A pair of base faces sharing an edge is a candidate where its widest angle is over
  /// this (degrees: by default any obtuse angle) and the flipped pair's widest angle is
  /// smaller.
  double capAngle = 90;
  /// Largest anisotropy (distortion.h) of the affine map from a flipped face in the
  /// flattened quad to the same face in space. The points keep their places in the quad,
  /// which the old pair is isometric to; across a bent edge the new faces are not, and
  /// every point of theirs moves on the surface by that stretch.
  double stretch = 1.2;
  /// Where over 0 (with `input`), a candidate is flipped only where the grid of this
  /// many splits sampled over the pair through the exact map (traceToInput) has fewer
  /// triangles facing against the input, or of no area, after the flip than before: a
  /// flip moves a base edge off the direction the simplification chose for it, and made
  /// wherever a cap is (without this check) it left more defects and larger distances
  /// over the never-seen meshes of docs/REMESH.md than it removed. 0: every candidate
  /// that passes the other checks (the flips' shape alone).
  int levels = 0;
  const TriMesh* input = nullptr;
  /// Sweeps over the base at most (a flip can make a neighbouring pair a candidate).
  int maxSweeps = 8;
};

struct BaseFlipReport {
  int flips = 0;    ///< flips made
  int refused = 0;  ///< candidates refused, over all sweeps (not convex, a pinch, a crossing,
                    ///< no fewer folds)
};

/// Flips candidates of `s.base` (never a boundary or feature edge, never making an edge
/// that exists, never leaving a vertex with fewer than three faces, never making a base
/// face cross another that the pair did not cross), moving every parameterised point of
/// the pair by the piecewise-linear map of the flattened quad and recording the flip in
/// `s.history`.
BaseFlipReport flipCaps(Simplification& s, const BaseFlipOptions& options = {});

}  // namespace osdmra::remeshing
