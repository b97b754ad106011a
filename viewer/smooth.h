// LoopPatches: the Loop limit surface of a triangle control mesh as OpenSubdiv patches.
//
// The smooth mode draws the truncated surface itself rather than a mesh through its
// limit points: OpenSubdiv's feature-adaptive patch table (regular Loop box-spline
// patches, Gregory triangles around extraordinary vertices) over the control mesh,
// with the control points given per surface. The topology work (refiner, patch
// table, stencils) is done once per control mesh; new control points then only
// cost one stencil evaluation, so the smooth view follows the LOD sliders.
#pragma once

#include <opensubdiv/far/patchTable.h>
#include <opensubdiv/far/stencilTable.h>

#include <memory>
#include <vector>

namespace viewer {

class LoopPatches {
 public:
  /// `triangles`: 3 vertex indices per face of a valid (manifold, oriented) mesh
  /// with `numVertices` vertices. Boundaries follow Loop's crease rule, as in
  /// osdmra's hierarchy. `isolation`: adaptive refinement levels around
  /// extraordinary vertices (the Gregory end caps approximate the limit there).
  LoopPatches(const std::vector<int>& triangles, int numVertices, int isolation = 2);
  ~LoopPatches();

  const OpenSubdiv::Far::PatchTable& table() const { return *patches_; }
  int numControlPoints() const { return numControl_; }
  int numPatches() const { return patches_->GetNumPatchesTotal(); }

  /// Positions of every point the patches index (control points, refined points,
  /// end-cap points), 3 floats each, from `controls` (3 doubles per control point).
  std::vector<float> points(const std::vector<double>& controls) const;

 private:
  int numControl_ = 0;
  std::unique_ptr<OpenSubdiv::Far::PatchTable> patches_;
  std::unique_ptr<const OpenSubdiv::Far::StencilTableReal<double>> stencils_;
};

}  // namespace viewer
