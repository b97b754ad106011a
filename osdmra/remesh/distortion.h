// How much the parameterisation stretches the input (step 1 of remesh.h): the
// distortion bound of the simplification, in the spirit of Khodakovsky, Litke and
// Schroder 2003 (a parameterisation sampled uniformly folds where it is strongly
// anisotropic, not where it is merely scaled).
#pragma once

#include <array>
#include <functional>
#include <vector>

#include "osdmra/mesh/mesh.h"
#include "osdmra/remesh/planar.h"

namespace osdmra::remeshing {

/// Anisotropy of the affine map taking the 3D triangle `from` onto the planar
/// triangle `to` (corner i to corner i): the ratio of its singular values, >= 1;
/// +infinity when either triangle is degenerate or the map reverses orientation (the
/// planar image is then clockwise).
double anisotropy(const std::array<Vec3, 3>& from, const std::array<Vec2, 3>& to);

/// The same with `from` already laid flat (layFlat()'s triangle): for a triangle
/// checked many times, laid once.
double anisotropyFromFlat(const std::array<Vec2, 3>& fromFlat, const std::array<Vec2, 3>& to);

/// k + 1/k for that anisotropy k (the map's squared Frobenius norm over its
/// determinant): it grows with k and needs no square root, so the worst of many
/// triangles is found by comparing these and converted once (anisotropyFromSum).
/// +infinity where anisotropyFromFlat is.
double anisotropySum(const std::array<Vec2, 3>& fromFlat, const std::array<Vec2, 3>& to);

/// The anisotropy k >= 1 whose k + 1/k is `sum` (>= 2).
double anisotropyFromSum(double sum);

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

/// Faces (vertex ids into `V`, counter-clockwise) laid in one chart: faces[0] flat, then,
/// breadth first, each next one hinged to the first face laid before it that shares an
/// edge with it, until the first `needed` faces are laid or no more join. `index`
/// receives each laid face's position in `faces`.
std::vector<Laid> layBreadthFirst(const Points& V, const std::vector<std::array<int, 3>>& faces,
                                  std::size_t needed, std::vector<std::size_t>& index);

/// The same into `laid` (both outputs cleared first): called a million times by the
/// simplification's distortion checks, it reuses their storage.
void layBreadthFirst(const Points& V, const std::vector<std::array<int, 3>>& faces,
                     std::size_t needed, std::vector<Laid>& laid, std::vector<std::size_t>& index);

/// The point at barycentric coordinates `bary` of a laid face.
inline Vec2 pointIn(const Laid& l, const std::array<double, 3>& bary) {
  return bary[0] * l.pos[0] + bary[1] * l.pos[1] + bary[2] * l.pos[2];
}

/// Where vertex v lies in the first of `laid` that has it; false if none has.
bool vertexIn(const std::vector<Laid>& laid, int v, Vec2& at);

/// Where a corner of an input triangle lies on the mesh being simplified: one of its
/// vertices, or a face (its three vertices) and barycentric coordinates in it.
struct Placed {
  bool isVertex;
  int vertex;
  std::array<int, 3> face;
  std::array<double, 3> bary;
};

/// The faces around vertex `w`, each as its three vertex ids (counter-clockwise),
/// appended to `out` (a caller's buffer: no list is allocated per call).
using FacesAround = std::function<void(int w, std::vector<std::array<int, 3>>& out)>;

/// The corners' images in one chart: the faces holding them laid flat from the first,
/// each next one hinged to one already laid about the edge they share; where their own
/// faces do not chain so, through the faces around a vertex they all share, and failing
/// that, through the faces around every vertex of theirs (`facesAround(w, out)`: the
/// faces around vertex w). A corner that is a vertex of none of the other corners' faces
/// brings one of its own. A triangle straddling an edge or a vertex of the faces is bent
/// there in the parameterisation; unfolded, its image is what the grid samples. On a
/// coarse input a triangle can be wider than a base face, its corners' faces neither
/// sharing an edge nor a vertex: it needs a chart all the same, for left unchecked it
/// folds the grid (the decimated knight of docs/REMESH.md). False when the faces have
/// no chart even so.
bool chartImage(const Points& V, const std::array<Placed, 3>& at, const FacesAround& facesAround,
                std::array<Vec2, 3>& image);

}  // namespace osdmra::remeshing
