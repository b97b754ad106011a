// Orders that follow the surface through space: consecutive rows lie near each other,
// so that work walking a neighbourhood touches memory that is already in cache.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "osdmra/mesh/mesh.h"

namespace osdmra {

/// The rows of `points` in Morton (Z-curve) order of their positions in their bounding
/// box (21 bits per axis); ties (one cell of that grid) by the coordinates, then by row.
std::vector<Eigen::Index> mortonOrder(const Points& points);

/// `mesh` renumbered for locality: vertices in mortonOrder(), faces sorted by their
/// corners' new numbers, each face's corners rotated (orientation kept) to start at its
/// smallest. The same surface, and a function of positions and connectivity alone: two
/// numberings of a mesh give the same result, but for the order among vertices at one
/// position (a split pinch), which is theirs. Normals, if any, follow their vertices.
TriMesh inSpatialOrder(const TriMesh& mesh);

}  // namespace osdmra
