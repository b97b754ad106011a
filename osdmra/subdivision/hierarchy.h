// Hierarchy: the base mesh M^0 and its J uniform 1-to-4 refinements M^1..M^J.
//
// This is the only module that talks to OpenSubdiv's Far::TopologyRefiner. It owns
// the index conventions every other module relies on, which are OpenSubdiv's uniform
// refinement's: a manifold base is split by osdmra itself in OpenSubdiv's numbering
// (tests hold faces, edges and Loop matrices to the refiner's), a non-manifold one by
// the refiner (the conventions checked when it is built):
//   - old vertices of M^{j+1} come first: vertex v of M^j is vertex v of M^{j+1};
//   - new vertex n_j + e of M^{j+1} is the midpoint of edge e of M^j, whose
//     endpoints parentEdge() gives;
//   - the children of face f of M^j are faces 4f..4f+3 of M^{j+1}: for face
//     (v0,v1,v2) with edge midpoints m_i on (v_i, v_i+1), they are (v0,m0,m2),
//     (m0,v1,m1), (m2,m1,v2) and the centre (m1,m2,m0).
// That is also osdmra's canonical vertex and face order for a level-J surface.
//
// Boundaries use Loop's crease rule (Sdc VTX_BOUNDARY_EDGE_ONLY): boundary vertices
// 1/8, 3/4, 1/8 along the boundary, boundary edge midpoints 1/2, 1/2, so each
// boundary curve is a uniform cubic B-spline and corners are not pinned.
#pragma once

#include <Eigen/SparseCore>
#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "osdmra/mesh/connectivity.h"
#include "osdmra/mesh/mesh.h"

namespace osdmra {

/// The two subdivision schemes of the paper on the same triangle split.
enum class Scheme {
  Loop,    ///< Loop's scheme (C^2 box splines away from extraordinary vertices)
  Linear,  ///< polyhedral: piecewise linear (old vertices kept, midpoints 1/2, 1/2)
};
const char* schemeName(Scheme s);
/// Parses "loop" or "linear" (also "polyhedral"); throws Error otherwise.
Scheme parseScheme(const std::string& name);

/// Row-major sparse matrix: rows are the finer level's vertices.
using SparseMatrix = Eigen::SparseMatrix<double, Eigen::RowMajor>;

class Hierarchy {
 public:
  /// Refines the connectivity of a validated base mesh `levels` times (0..15). With
  /// `only`, the refinement matrices of that scheme alone are extracted (a decoder
  /// knows its scheme; each scheme's matrices cost time and memory of the order of
  /// the finest level), and refinement() of the other throws.
  Hierarchy(const Faces& baseFaces, int numBaseVertices, int levels,
            std::optional<Scheme> only = std::nullopt);
  ~Hierarchy();
  Hierarchy(Hierarchy&&) noexcept;
  Hierarchy& operator=(Hierarchy&&) noexcept;

  int levels() const;  ///< J
  int numVertices(int j) const;
  int numFaces(int j) const;
  const Faces& faces(int j) const;
  /// Adjacency of M^j, built on first use (thread-safe).
  const Connectivity& connectivity(int j) const;

  /// Endpoints (in M^j) of the edge whose midpoint is vertex n_j + e of M^{j+1}.
  std::array<int, 2> parentEdge(int j, int e) const;
  /// Vertex of M^{j+1} at the midpoint of the M^j edge {a, b}; -1 if not an edge.
  int midpoint(int j, int a, int b) const;
  /// For j < J, per face of M^j the edge e (midpoint n_j + e) of each of its edges i
  /// (from corner i to corner i + 1), as osdmra's split of a manifold base knows them;
  /// null for a hierarchy refined by OpenSubdiv (a non-manifold base).
  const Connectivity::FaceEdgeList* faceEdges(int j) const;

  /// P^{j+1} (n_{j+1} x n_j) for 0 <= j < J, taken from OpenSubdiv: Loop's vertex
  /// interpolation, or the varying (linear) interpolation on the same refiner, on first
  /// use (then the refiner is freed). Every row sums to 1.
  const SparseMatrix& refinement(Scheme scheme, int j) const;
  /// Extracts the refinement matrices now rather than at the first refinement() (they
  /// are extracted once, on first use, thread-safe): for a caller with a thread to spare
  /// while another starts on the faces and edges.
  void prepareRefinement() const;

  /// Loop limit positions and unit normals, at the vertices of M^level, of the surface
  /// with control points `c` on M^level (OpenSubdiv's PrimvarRefiner::Limit with the
  /// same boundary rules). Every vertex of a coarser level is also a vertex of M^J with
  /// the same index and limit point, so one call serves a level-of-detail mesh mixing
  /// levels.
  void loopLimit(int level, const Points& c, Points& positions, Points& normals) const;

  /// The linear maps behind loopLimit: limit position and the two tangents of every
  /// vertex of M^level as sparse rows over its control points (n x n each). Build once
  /// to evaluate many surfaces, or only some vertices.
  struct LimitStencils {
    SparseMatrix position, tangent1, tangent2;
  };
  LimitStencils limitStencils(int level) const;

  /// The base faces of a mesh given in canonical order at level `levels` (see the
  /// file comment). Throws Error when the faces cannot be in that order.
  static Faces baseFacesFromCanonical(const Faces& finest, int levels);

  /// The hierarchy whose level `levels` is exactly `finest` (canonical order, with
  /// `numVertices` vertices). Throws Error naming the first face or count that
  /// disagrees, so a mesh in any other order is refused rather than misread.
  static Hierarchy fromCanonical(const Faces& finest, int numVertices, int levels);

  /// The largest J for which fromCanonical(finest, numVertices, J) succeeds; 0 when
  /// the mesh is not in canonical order at any level.
  static int detectCanonicalLevels(const Faces& finest, int numVertices);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Unit normals du x dv row by row (zero where the tangents are parallel).
Points unitNormals(const Points& du, const Points& dv);

}  // namespace osdmra
