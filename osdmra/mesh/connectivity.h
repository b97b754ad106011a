// Connectivity: the one mesh traversal utility of osdmra.
//
// Built once from a face list, it answers every adjacency question the other
// modules ask: halfedges and their twins, undirected edges, boundary flags, and
// each vertex's neighbours in counter-clockwise order. Nothing else in osdmra
// walks a face list by itself.
//
// Storage (all plain arrays, sized by the mesh):
//   halfedge h = 3 f + i runs from corner i of face f to corner i+1;
//   twin(h) is the opposite halfedge, or -1 on a boundary;
//   edge(h) numbers undirected edges in order of first appearance over the faces;
//   ring(v) lists v's neighbours counter-clockwise. For a boundary vertex it is the
//   path that starts at the neighbour across v's outgoing boundary edge and ends at
//   the neighbour across its incoming one (valence = faces + 1 there).
//
// Defects (non-manifold edges and vertices, flipped faces) are recorded, not thrown:
// validate() turns them into named errors, and hierarchy-internal local meshes may
// legitimately have non-manifold vertices on their cut.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "osdmra/mesh/mesh.h"

namespace osdmra {

/// A read-only view of a contiguous run of indices.
struct IndexSpan {
  const int* first = nullptr;
  const int* last = nullptr;
  const int* begin() const { return first; }
  const int* end() const { return last; }
  int size() const { return static_cast<int>(last - first); }
  int operator[](int i) const { return first[i]; }
};

/// Each vertex's neighbours in counter-clockwise order, and nothing else: the cheap
/// core of Connectivity (no halfedges, no twins, no edge numbering), built from one
/// cache-friendly sort of the corners so that every later read is local to one
/// vertex. For passes over large meshes that only walk rings, such as the recovery
/// of subdivision connectivity. ring() follows Connectivity::ring exactly.
///
/// A vertex whose corners do not chain into one fan (a non-manifold vertex, or one
/// on a non-manifold edge or a face of opposite winding) has an empty ring.
class VertexRings {
 public:
  VertexRings() = default;
  VertexRings(const Faces& F, int numVertices);

  int numVertices() const { return static_cast<int>(state_.size()); }
  IndexSpan ring(int v) const;
  int valence(int v) const { return ring(v).size(); }
  bool isBoundaryVertex(int v) const { return state_[v] == kBoundary; }
  bool isManifoldVertex(int v) const { return state_[v] <= kBoundary; }
  /// Number of undirected edges, when every vertex is manifold.
  long long numEdgesIfManifold() const;

  int firstNonManifoldVertex = -1;  ///< -1 when there is none
  int firstIsolatedVertex = -1;     ///< a vertex in no face, or -1

 private:
  enum : std::uint8_t { kClosed = 0, kBoundary = 1, kNonManifold = 2 };
  // ring(v) starts at ring_[offset_[v] + v]: v's corner count, plus room for the one
  // extra neighbour of a boundary vertex.
  std::vector<int> offset_;
  std::unique_ptr<int[]> ring_;
  std::vector<std::uint8_t> state_;
};

class Connectivity {
 public:
  Connectivity() = default;
  Connectivity(const Faces& F, int numVertices);
  /// Per face, the undirected edge index of each halfedge (edge i of face f joins its
  /// corners i and i + 1), in any numbering over numEdges edges.
  using FaceEdgeList = std::vector<std::array<int, 3>>;
  /// The same connectivity as Connectivity(F, numVertices), built faster where each
  /// halfedge's undirected edge is known already (a subdivision level's, as OpenSubdiv
  /// numbers them): twins are paired through them instead of searched for. A mesh
  /// they do not show manifold and consistently oriented gets the general construction.
  Connectivity(const Faces& F, int numVertices, const FaceEdgeList& faceEdges, int numEdges);

  int numVertices() const { return static_cast<int>(ringOffset_.size()) - 1; }
  int numFaces() const { return static_cast<int>(F_.rows()); }
  int numEdges() const { return static_cast<int>(edgeHalfedge_.size()); }
  const Faces& faces() const { return F_; }

  // Halfedges.
  int from(int h) const { return F_(h / 3, h % 3); }
  int to(int h) const { return F_(h / 3, (h + 1) % 3); }
  static int next(int h) { return h - h % 3 + (h % 3 + 1) % 3; }
  static int prev(int h) { return h - h % 3 + (h % 3 + 2) % 3; }
  int twin(int h) const { return twin_[h]; }
  int edge(int h) const { return halfedgeEdge_[h]; }

  // Undirected edges.
  int edgeHalfedge(int e) const { return edgeHalfedge_[e]; }
  std::array<int, 2> edgeVertices(int e) const;
  bool isBoundaryEdge(int e) const { return twin_[edgeHalfedge_[e]] < 0; }
  /// Index of the edge {a,b}, or -1.
  int findEdge(int a, int b) const;

  // Vertices.
  /// Neighbours counter-clockwise (see the file comment for boundary vertices).
  IndexSpan ring(int v) const;
  /// Outgoing halfedges in the same counter-clockwise order (one per incident face).
  IndexSpan fan(int v) const;
  int valence(int v) const { return ring(v).size(); }
  int numVertexFaces(int v) const { return fan(v).size(); }
  bool isBoundaryVertex(int v) const { return boundaryVertex_[v] != 0; }
  bool isManifoldVertex(int v) const { return manifoldVertex_[v] != 0; }

  // Defects found while building; -1 when there is none.
  int firstNonManifoldEdgeFace = -1;  ///< a face on an edge shared by 3+ faces
  int firstFlippedFace = -1;          ///< a face whose winding disagrees with a neighbour
  int firstNonManifoldVertex = -1;    ///< a vertex whose faces do not form one fan
  int firstIsolatedVertex = -1;       ///< a vertex in no face
  int numBoundaryLoops() const;
  int numComponents() const;
  /// Euler characteristic V - E + F (isolated vertices excluded).
  int eulerCharacteristic() const;

 private:
  void startRings(int numVertices, int numHalfedges);
  void walkFan(int v, int start, int numOut, int starts);

  Faces F_;
  std::vector<int> twin_, halfedgeEdge_, edgeHalfedge_;
  std::vector<int> ringOffset_, ringVerts_, fanOffset_, fanHalfedges_;
  std::vector<std::uint8_t> boundaryVertex_, manifoldVertex_;
};

}  // namespace osdmra
