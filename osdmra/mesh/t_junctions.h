// T-junctions of an input mesh, zipped.
//
// Meshes tessellated piece by piece (CAD exports, where each face of a model is
// triangulated on its own; meshes merged from parts) can have a vertex in the middle
// of a neighbour's edge: the neighbour's edge (a, b) and the chain a, v1, ..., vk, b
// of the other side are boundaries along the same line, and the surface has a crack
// of zero width there. Each such edge is split at the vertices lying on it, its face
// fanned from its third corner, so that both sides share the same edges: the surface
// is the same set of points, and the crack is gone (tests/mesh/test_t_junctions.cpp).
#pragma once

#include "osdmra/mesh/mesh.h"

namespace osdmra {

/// A boundary vertex lies on a boundary edge when its distance to the edge's segment
/// is at most this fraction of the edge's length, strictly between its ends.
constexpr double kTJunctionTolerance = 1e-6;

/// Splits every boundary edge at the boundary vertices (not its own ends) that lie on
/// it (kTJunctionTolerance), fanning its face from the opposite corner; returns how
/// many edges were split. The work is bounded in proportion to the boundary's size
/// (edges beyond that budget are left as they are). Nothing changes when the mesh has an index out
/// of range or a repeated corner, which validate() reports.
int zipTJunctions(TriMesh& mesh);

}  // namespace osdmra
