// TriMesh: plain triangle-mesh data, and the checks that every mesh passes before
// it reaches OpenSubdiv.
#pragma once

#include <Eigen/Core>
#include <string>

namespace osdmra {

/// n x 3 vertex positions, one row per vertex (row-major so a row is one xyz).
using Points = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
/// m x 3 vertex indices, one row per triangle, counter-clockwise seen from outside.
using Faces = Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>;

struct TriMesh {
  Points V;
  Faces F;
  /// Optional per-vertex normals (empty, or one row per vertex); written by the
  /// writers when present.
  Points N;
};

/// Throws osdmra::Error, prefixed with `source` (a file name or a description),
/// when the mesh cannot be a domain for subdivision: an index out of range, a
/// repeated vertex in a face, a non-finite coordinate, an unreferenced vertex, a
/// non-manifold edge or vertex, or inconsistent orientation. The message names the
/// offending face or vertex (0-based) and what is wrong with it.
void validate(const TriMesh& mesh, const std::string& source);

/// Drops vertices that no face uses (scans often carry some), renumbering the rest
/// in their order; returns how many were dropped.
int removeUnreferencedVertices(TriMesh& mesh);

/// Diagonal of the axis-aligned bounding box (0 for an empty mesh).
double boundingBoxDiagonal(const Points& V);

}  // namespace osdmra
