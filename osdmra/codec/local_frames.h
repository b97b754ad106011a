// Local frames of the wavelet coefficients: a coefficient d^j_e (a 3-vector at the
// new vertex on edge e of M^j) is coded as its components along the normal of the
// coarser surface and two tangents, the along-edge direction and the one across it.
//
// For a smooth surface sampled evenly the tangential components are small: the
// coarser level already places the new vertex almost where it belongs along the
// surface, and what is left is mostly height above it (Khodakovsky, Schroder and
// Sweldens 2000, section 4.1; MPEG's dynamic-mesh coding quantises its normal
// displacement more finely for the same reason). Tangential errors also move the
// surface less than normal ones of the same size, which the codec's tangential weight
// exploits.
//
// The frame of level j is computed from c^j, the control points of level j, which
// the decoder has rebuilt before it needs the frame: the normal of edge (a, b) is
// the sum of the area-weighted vertex normals of a and b over M^j; the along-edge
// tangent is b - a made orthogonal to it. Degenerate neighbourhoods fall back to the
// coordinate axes, the same way on both sides.
//
// Each frame also says how much the coarser surface bends at its edge: sliding a new
// vertex by t along a flat surface moves it by nothing, along a bent one by about t
// times the angle its faces make with its normal, so the codec weights tangential
// components by it (codec.h, CodecOptions::bendGain).
#pragma once

#include "osdmra/mesh/mesh.h"
#include "osdmra/subdivision/hierarchy.h"

namespace osdmra {

/// One orthonormal frame per edge of M^j: rows of `normal`, `along`, `across`.
struct LocalFrames {
  Points normal, along, across;
  /// Per edge (a, b): the largest |n_f - n_v| over the faces f of M^j around a or b,
  /// between the unit normal of f and the unit vertex normal of that end, 2 sin(theta / 2)
  /// for the angle theta between them: 0 where the surface is flat around the edge.
  Eigen::VectorXd bend;
};

/// The frames of the edges of M^j (0 <= j < J) over control points `c` (n_j x 3).
LocalFrames edgeFrames(const Hierarchy& h, int j, const Points& c);

/// World vectors to (normal, along, across) components, row by row.
Points toLocal(const LocalFrames& f, const Points& world);
/// The inverse of toLocal.
Points toWorld(const LocalFrames& f, const Points& local);

}  // namespace osdmra
