// Remeshing: any manifold triangle mesh to a mesh with subdivision connectivity, in
// the spirit of MAPS (Lee, Sweldens, Schroder, Cowsar and Dobkin 1998).
//
// 1. Simplification with a parameterisation. Vertices are removed in rounds of
//    independent sets, least important first (small one-ring area and curvature).
//    Each removal flattens the vertex's one-ring conformally (the z^a map: angles
//    scaled to sum to 2 pi, or pi on each side of a boundary or a feature line),
//    retriangulates the flat polygon, and moves every input vertex that lived in the
//    removed faces (and the removed vertex itself) to its barycentric place in the
//    new faces. A removal that would create an edge the mesh already has is skipped,
//    so genus, boundary loops and components are kept. Feature edges (dihedral angle
//    above a threshold) are kept as edges: a vertex on a feature line is removed as
//    two half-disks whose retriangulations share the edge between its two feature
//    neighbours; corners of features (where lines meet or turn sharply) and sharp
//    turns of boundaries are never removed, and a scan's folds (triangles facing
//    against their corners' normals) go first. The result is a base mesh M^0 of
//    about the requested size, every input vertex at a point of it.
// 2. Resampling. Each base face is split J times (a regular grid of 2^J segments per
//    edge); every grid point is located in the parameterised input (an input
//    triangle whose parameter image contains it) and placed at the corresponding
//    point of the input surface. Input triangles are laid out in the chart of their
//    base face when their corners all lie in it, else in the chart of the base edge
//    they straddle (its two faces unfolded, isometric to both face charts, so there
//    is no crack along base edges), else in the chart of a base vertex they surround.
//    Grid points on feature and boundary base edges are sampled along the input's
//    line itself (the chain of input feature or boundary edges the base edge stands
//    for), at their parameter along the edge.
// 3. Clean-up. Where the parameterisation folds (composed flattenings bend a large
//    input triangle; a base vertex's neighbours end up on one side of it), output
//    triangles come out flipped (facing against the input's normals where their
//    corners were sampled), of zero area, or crossing others. Three stages repair
//    them: free grid points around them go to the input point nearest their
//    neighbours' centroid; disks around what is left are resampled from their tangent
//    plane (Tutte's embedding, lifted back onto the input); then points go one at a
//    time to where the worst of their triangles is best (Freitag and Plassmann's
//    untangling, on the surface), points on feature lines and boundaries sliding
//    along them. The last two keep a move only if it makes nothing worse nearby. As a
//    last resort, base faces still defective relax as a whole (each free point walks
//    along the surface towards its neighbours' centroid) and the repairs run again,
//    kept if fewer defects remain and the relaxed faces come no farther from the
//    input. remesh() reports what remains (none on the scans of docs/REMESH.md at
//    the defaults, nor at most other sizes; listed there).
//
// The output has subdivision connectivity in its own vertex and face order: the
// rest of osdmra recovers its structure (recovery.h).
#pragma once

#include <string>

#include "osdmra/mesh/mesh.h"
#include "osdmra/base/progress.h"

namespace osdmra {

struct RemeshOptions {
  /// Target number of base faces: simplification stops at or just below it, or
  /// earlier when no vertex can be removed without changing the topology or
  /// flattening the tip of a protrusion (a one-ring whose angles sum to under 192
  /// degrees, such as the bunny's ear tips below about 180 faces).
  int baseFaces = 300;
  /// Rounds of 1-to-4 splitting of the base mesh.
  int levels = 5;
  /// Edges whose dihedral angle (between face normals) exceeds this, in degrees,
  /// are features that stay edges of the base mesh, if they form chains of at least
  /// 4 edges (shorter ones on scans are noise). 180 turns features off. 70 was best
  /// over the four scans of docs/REMESH.md (60 pins noisy creases of the bunny).
  double featureAngle = 70.0;
};

struct Remeshing {
  TriMesh mesh;  ///< the remeshed surface: M^levels over `base`, positions on the input
  /// The base mesh M^0, the first vertices of `mesh`: input vertices, but for those the
  /// clean-up moved (to another point of the input).
  TriMesh base;
  int featureEdges = 0;  ///< input edges taken as features
  /// Grid points whose parameter fell outside every input triangle image and were
  /// snapped to the nearest one (a measure of parameterisation trouble; 0 is ideal).
  int snappedSamples = 0;
  /// Triangles of `mesh` left flipped (facing against the input where they lie) or
  /// of zero area after the clean-up pass; 0 is the goal (see remesh()).
  int flippedTriangles = 0, degenerateTriangles = 0;
  /// Pairs of triangles of `mesh` that cross without being neighbours
  /// (findSelfIntersections); 0 is the goal.
  long long selfIntersections = 0;
};

/// Remeshes a valid mesh (validate(): manifold, oriented, no unreferenced vertex).
/// Throws Error when the mesh cannot be simplified to any base at all (fewer than
/// 4 faces, say) or when options are out of range.
Remeshing remesh(const TriMesh& input, const RemeshOptions& options = {},
                 const Progress& progress = {});

}  // namespace osdmra
