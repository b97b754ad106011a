// TriMesh: plain triangle-mesh data, and the checks that every mesh passes before
// it reaches OpenSubdiv.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

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

/// Every face's indices in range and its three corners distinct: what the repairs below
/// and Connectivity need (validate() names a face that is not).
bool hasWellFormedFaces(const TriMesh& mesh);

/// Drops vertices that no face uses (scans often carry some), renumbering the rest
/// in their order; returns how many were dropped.
int removeUnreferencedVertices(TriMesh& mesh);

/// What weldBoundaryVertices() did.
struct Welding {
  int vertices = 0;  ///< vertices merged into another at the same position
  int faces = 0;     ///< faces dropped because two of their corners merged
  /// Why nothing was welded although coincident boundary vertices exist (the welded
  /// mesh would not pass validate()); empty otherwise.
  std::string refused;
};

/// Merges boundary vertices that lie at exactly the same position, the way a triangle
/// soup (an STL file written as OBJ, say) or a mesh split along its texture seams has
/// every seam vertex twice: faces are renumbered to the first vertex of each group,
/// faces left with a repeated corner are dropped, and the vertices no face uses any
/// more (those merged, and any other) removed.
/// Interior vertices are never merged (a surface may touch itself). Nothing changes,
/// and `refused` says why, when the welded mesh would not pass validate() once its
/// pinched vertices are split (splitNonManifoldVertices); nothing
/// changes either when the mesh has an index out of range or a repeated corner, which
/// validate() reports.
Welding weldBoundaryVertices(TriMesh& mesh);

/// Drops every face that names one vertex twice (a segment or a point, not a triangle:
/// exporters write them for collapsed geometry); returns how many were dropped. Faces
/// with an index out of range are kept, for validate() to report.
int removeFacesWithRepeatedCorners(TriMesh& mesh);

/// Drops every face whose three corners are those of an earlier face, in either
/// orientation (simplifiers and exporters leave such copies; the copy makes each of
/// its edges non-manifold, and one of two back-to-back faces adds nothing to the
/// surface); returns how many were dropped. Nothing changes when the mesh has an index
/// out of range or a repeated corner, which validate() reports.
int removeDuplicateFaces(TriMesh& mesh);

/// Splits every vertex whose faces form separate fans that touch only there (a
/// "bowtie", common in scans), one copy per fan after the first, at the same position
/// (and normal); returns how many copies were added. The surface is the same, its
/// topology now a manifold's (two sheets touching at a point). Nothing changes when the
/// mesh has an index out of range, a repeated corner, a non-manifold edge or
/// inconsistent orientation, which validate() reports.
int splitNonManifoldVertices(TriMesh& mesh);

/// Cuts open every edge shared by three faces or more (simplifiers leave them:
/// meshoptimizer's decimation of armadillo to 3,000 faces has one): each end of such an
/// edge gets one copy per fan of its faces joined through its other edges. Two faces
/// of the edge that a sheet joins elsewhere (a disc through the edge) share the copies
/// again, and a face joined to them by no other path (a fin) is cut off, the edge its
/// boundary; sheets that meet only along the edge come apart there. The surface is the
/// same point set. Returns how many edges were cut;
/// validate() still refuses an edge whose faces all remain joined (three sheets
/// through one edge that meet elsewhere). Nothing changes when the mesh has an index
/// out of range or a repeated corner, which validate() reports.
int cutNonManifoldEdges(TriMesh& mesh);

/// Reverses the faces whose winding disagrees with their neighbours' (meshes assembled
/// from parts, or exported by tools that do not keep a winding, have some), so that
/// every edge of two faces is run both ways; in each connected component the winding
/// most of its faces have is kept. Returns how many faces were reversed. Nothing changes
/// when a component cannot be oriented (a Moebius strip), when an edge has three faces
/// (cutNonManifoldEdges first), or when the mesh has an index out of range or a
/// repeated corner: validate() reports those.
int orientConsistently(TriMesh& mesh);

/// The connected component of every face (faces sharing a vertex are connected),
/// numbered 0.. in the order of each component's first face. Indices must be in range.
std::vector<int> componentOfFaces(const Faces& F, int numVertices);

/// Drops every connected component of fewer than `minFaces` faces (a scan's debris:
/// single triangles floating off the surface) and the vertices left unused; returns
/// how many components were dropped. Nothing changes for minFaces <= 1, or when the
/// mesh has an index out of range or a repeated corner.
int removeSmallComponents(TriMesh& mesh, int minFaces);

/// Diagonal of the axis-aligned bounding box (0 for an empty mesh).
double boundingBoxDiagonal(const Points& V);

}  // namespace osdmra
