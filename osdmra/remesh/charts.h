// The base mesh laid flat around each of its faces (step 2 of remesh.h), and the
// parameterisation made straight on every input triangle in those charts.
//
// The simplification places every input vertex on the base (Simplification::params)
// and bounds the distortion of each input triangle between its corners' places, in
// faces hinged flat about the edges they share (simplify.cpp's distortion check). The
// map that is affine on every input triangle between those places is therefore the one
// whose distortion is known: the resampling samples it and the smoothing improves it.
// A base face's chart is the face laid flat and the faces around its corners hinged to
// it breadth first, each from the nearer side (a second ring of faces made no difference
// on the corpus of docs/REMESH.md).
#pragma once

#include <array>
#include <vector>

#include "osdmra/mesh/connectivity.h"
#include "osdmra/remesh/distortion.h"
#include "osdmra/remesh/simplify.h"

namespace osdmra::remeshing {

class BaseCharts {
 public:
  /// Charts of every face of `base` over `rings` rings of faces around it.
  explicit BaseCharts(const TriMesh& base, int rings = 1);

  /// Where point `p` of the base lies in face f's chart; false if its face is not laid
  /// there.
  bool place(int f, const Param& p, Vec2& at) const;
  /// Where base vertex v lies in face f's chart (its place in the nearest face laid
  /// that has it); false if none has.
  bool placeVertex(int f, int v, Vec2& at) const;
  /// The point at `at` of face f's chart as a point of the base: in the first laid face
  /// (nearest first) that holds it; false if none does.
  bool locate(int f, const Vec2& at, Param& p) const;
  /// Face f itself, laid flat.
  const Laid& own(int f) const { return charts_[f].front(); }

 private:
  std::vector<std::vector<Laid>> charts_;
  std::vector<std::vector<int>> ids_;  // the base face of each laid one
};

/// Where input vertex x lies in face f's chart, at its place on the base.
bool placeInputVertex(const BaseCharts& charts, const Simplification& s, int f, int x, Vec2& at);

}  // namespace osdmra::remeshing
