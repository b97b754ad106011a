// Halfedges grouped by undirected edge, for the repairs that must see edges of any
// number of faces (mesh.cpp, t_junctions.cpp), which Connectivity does not build.
// Internal: not installed.
#pragma once

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "osdmra/mesh/mesh.h"

namespace osdmra::detail {

/// Every halfedge h = 3 f + k (face f's edge from corner k to k + 1) keyed by its ends,
/// lower first, sorted by key (then by h): the halfedges of one undirected edge are
/// consecutive. Indices must be in range.
std::vector<std::pair<std::uint64_t, int>> halfedgesByEdge(const Faces& F);

/// The end of the run of halfedges on the same edge as sorted[i].
std::size_t runEnd(const std::vector<std::pair<std::uint64_t, int>>& sorted, std::size_t i);

}  // namespace osdmra::detail
