// How much the parameterisation stretches the input (step 1 of remesh.h): the
// distortion bound of the simplification, in the spirit of Khodakovsky, Litke and
// Schroder 2003 (a parameterisation sampled uniformly folds where it is strongly
// anisotropic, not where it is merely scaled).
#pragma once

#include <array>

#include "osdmra/mesh/mesh.h"
#include "osdmra/remesh/planar.h"

namespace osdmra::remeshing {

/// Anisotropy of the affine map taking the 3D triangle `from` onto the planar
/// triangle `to` (corner i to corner i): the ratio of its singular values, >= 1;
/// +infinity when either triangle is degenerate or the map reverses orientation (the
/// planar image is then clockwise).
double anisotropy(const std::array<Vec3, 3>& from, const std::array<Vec2, 3>& to);

/// A 3D triangle laid isometrically in the plane: a at the origin, b on the x axis,
/// c above it.
std::array<Vec2, 3> layFlat(const Vec3& a, const Vec3& b, const Vec3& c);

/// A triangle of a mesh laid in a chart: its vertices (ids) and their places.
struct Laid {
  std::array<int, 3> face;
  std::array<Vec2, 3> pos;
};

/// Triangle `f` (vertex ids into `V`, counter-clockwise) laid isometrically next to
/// `from` across the edge they share, on the other side of it: `out`. False if they do
/// not share exactly one edge.
bool hinge(const Points& V, const Laid& from, const std::array<int, 3>& f, Laid& out);

}  // namespace osdmra::remeshing
