// Base edge flips after the simplification, where the grid sampled over a pair of base
// faces folds and over the flipped pair would fold less: a base face with one wide angle
// (a cap) holds its chart's points along one long side, and the grid over it can fold
// there (the bunny over 300 base faces at J = 5: its one crossing pair, in a cap of 145
// degrees along a hole's rim). Each flip is one more step of the parameterisation,
// recorded in the history as a removal is, so traceToInput undoes it and the map stays a
// bijection by construction: the two faces are laid flat about their shared edge, and a
// flip is made only where that quad is strictly convex.
// And base edge splits, where the grid sampled over a face still folds (remesh.cpp
// samples first, then splits): the face's longest edge split at an input vertex made a
// base vertex again, inside the pair laid flat (or on the edge, where it is a boundary
// or feature line), recorded as a flip is; a smaller base face's grid straddles fewer of
// the input's creases.
#pragma once

#include <vector>

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
  /// splitFoldingFaces(): at most this many splits (each adds a base vertex and two base
  /// faces, one on the boundary).
  int maxSplits = 0;
  /// As `stretch`, for the faces a split makes.
  double splitStretch = 2;
  /// splitFoldingFaces(): a split only where the grid of `levels` splits sampled over the
  /// new faces through the exact map folds no more than over the old (that grid is
  /// remesh()'s other one); false: the other checks alone.
  bool splitFoldCheck = true;
  /// splitFoldingFaces(): where the pair about an interior edge that is no feature line
  /// holds no input vertex that makes the new faces within the bounds, a point of the
  /// input under a lattice of 8 steps over each face of the pair laid flat, the one
  /// making the new faces' widest angle smallest within the same bounds, made a base
  /// vertex (Simplification::added).
  bool splitAtPoints = false;
};

struct BaseFlipReport {
  int flips = 0;          ///< flips made
  int refused = 0;        ///< candidates refused, over all sweeps (not convex, a pinch, a crossing,
                          ///< no fewer folds)
  int splits = 0;         ///< caps split
  int splitsRefused = 0;  ///< caps left whole
  int splitsFoldingMore = 0;  ///< of those, refused by splitFoldCheck alone
};

/// Flips candidates of `s.base` (never a boundary or feature edge, never making an edge
/// that exists, never leaving a vertex with fewer than three faces, never making a base
/// face cross another that the pair did not cross), moving every parameterised point of
/// the pair by the piecewise-linear map of the flattened quad and recording the flip in
/// `s.history`.
BaseFlipReport flipCaps(Simplification& s, const BaseFlipOptions& options = {});

/// Flips edges of `s.base` (with the same guards as flipCaps, and options.stretch) where
/// the input points the pair holds (options.input) lie nearer the planes of the flipped
/// faces than of the faces as they are, and no face meets the new ones or their
/// neighbours at a fold past a right angle unless one was there before: a base that fits
/// the input better for the same vertices, for levels of detail whose coarse levels are
/// the base (lodForBudget). Every point keeps its place in the flattened pair, so the map
/// stays a bijection, recorded in `s.history` as flipCaps' flips are.
BaseFlipReport flipTowardsInput(Simplification& s, const BaseFlipOptions& options);

/// Splits the longest edge of base faces whose grid folds (`folds`: per base face, how many
/// of the triangles sampled over it fold), most folds first, at most options.maxSplits
/// times: an input vertex held by the faces about that edge (on the edge itself where it
/// is a boundary or feature line) is made a base vertex again and those faces fanned
/// about it, where that leaves the new faces' widest angle in space under 120 degrees or
/// the old faces' widest, each new face within options.splitStretch of its flat shape,
/// no new crossing of the base, and (options.splitFoldCheck) the grid of options.levels
/// splits over the new faces (through the exact map, options.input) folding no more than
/// over the old. Each split
/// is recorded in `s.history` as a flip is, so the map stays a bijection; genus,
/// boundary loops and components are kept.
BaseFlipReport splitFoldingFaces(Simplification& s, const std::vector<int>& folds,
                                 const BaseFlipOptions& options);

}  // namespace osdmra::remeshing
