// What the simplification must keep of the input (step 1 of remesh.h): feature
// lines, the corners of lines and boundaries, the tips of protrusions, and a scan's
// folds (which it removes first).
#pragma once

#include <array>
#include <cstdint>
#include <unordered_set>
#include <vector>

#include "osdmra/mesh/connectivity.h"
#include "osdmra/mesh/mesh.h"

namespace osdmra::remeshing {

struct Features {
  /// Feature edges (edgeKey of their vertices): dihedral angle above the threshold,
  /// in chains of at least kMinChain edges or closed loops, folds excluded (and lines on
  /// their own shorter than detectFeatures' minLineLength).
  std::unordered_set<std::uint64_t> edges;
  std::vector<std::array<int, 2>> list;  ///< the same edges as vertex pairs
  /// Vertices where a feature line or a boundary turns by more than kMaxTurn (a
  /// boundary: at the scale of detectFeatures' span, one per bend): they stay in the
  /// base mesh, else a base edge would cut the corner. Tips (below) are corners too.
  std::vector<char> corner;
  /// Corners of fold triangles (facing against their own corners' area-weighted
  /// normals: a sliver turned over onto its neighbour). Noise: removed first.
  std::vector<char> fold;
  /// Tips of protrusions (an ear, a horn, a finger): interior vertices whose face
  /// angles sum to under kMaxTipAngle, the sharpest cones no removal could flatten.
  /// They are corners too, so they stay base vertices, sampled exactly at every level.
  std::vector<char> tip;
};

/// Scans carry sharp-looking noise: single edges and short chains of feature edges.
constexpr int kMinChain = 4;
/// Largest turn of a feature line or a boundary at a removable vertex, in degrees.
constexpr double kMaxTurn = 40.0;
/// Largest sum of face angles at a tip, in degrees: 2 pi over the largest exponent of
/// the z^a flattening the simplification uses (1.875, simplify.h's kStages).
constexpr double kMaxTipAngle = 192.0;

/// The features of a valid mesh at `featureAngle` degrees (180: none). A feature line
/// on its own (both ends free, or closed) shorter than `minLineLength` is none. A boundary's
/// turn at a vertex is measured between the points `boundarySpan` away along it on
/// either side (two edges at least), and only the vertex turning most within that reach
/// is a corner: bends finer than that are not (remesh() passes half the edge of a base
/// face of the size asked for, which could not follow them anyway).
Features detectFeatures(const TriMesh& mesh, double featureAngle, double boundarySpan = 0,
                        double minLineLength = 0);

/// Whether a face of normal `faceNormal` is a fold: facing against `cornerNormals`, the
/// sum of its corners' area-weighted normals (vertexNormalSums).
bool facesAgainst(const Eigen::Vector3d& faceNormal, const Eigen::Vector3d& cornerNormals);

/// Features::fold of detectFeatures(), alone (`c`: the mesh's connectivity).
std::vector<char> foldCorners(const TriMesh& mesh, const Connectivity& c);

/// Every input vertex's neighbours along the input's lines: its boundary (the edges of
/// one face, from `c`) and its feature lines (`featureEdges`, Features::list). The chains
/// a base edge on a line stands for are walked through these (followLine).
struct LineNeighbours {
  std::vector<std::vector<int>> boundary, feature;
};
LineNeighbours lineNeighbours(const Connectivity& c,
                              const std::vector<std::array<int, 2>>& featureEdges);

/// The vertices of a line (`along[v]`: v's neighbours on it) from `from` through
/// `next`, on through vertices with exactly two neighbours, up to one that `stops`,
/// has another number of neighbours, or is `from` again (a closed loop). It cannot
/// run in circles: a loop of two-neighbour vertices has no way in but from one of
/// them.
template <class Stops>
std::vector<int> followLine(const std::vector<std::vector<int>>& along, int from, int next,
                            const Stops& stops) {
  std::vector<int> chain{from, next};
  while (chain.back() != from && along[chain.back()].size() == 2 && !stops(chain.back())) {
    const std::vector<int>& two = along[chain.back()];
    chain.push_back(two[0] == chain[chain.size() - 2] ? two[1] : two[0]);
  }
  return chain;
}

}  // namespace osdmra::remeshing
