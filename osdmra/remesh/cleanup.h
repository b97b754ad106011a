// Step 3 of remesh.h, a safety net: where sampling the parameterisation still folds,
// output triangles come out flipped (facing against the input's normals where their
// corners were sampled), of zero area, or crossing others. Free grid points around
// them go to the input point nearest their neighbours' centroid; disks around what is
// left are resampled from their tangent plane (Tutte's embedding, untangled in the plane
// where its boundary is not convex and it folds: untangle.h; lifted back onto the
// input); then points go one at a time to where the worst of their triangles is best
// (Freitag and Plassmann's untangling, on the surface), points on feature lines and
// boundaries sliding along them. As a last resort, base faces still defective relax
// as a whole (each free point walks along the surface towards its neighbours'
// centroid), kept if fewer defects remain and the relaxed faces come no farther from
// the input. Remeshing reports how much of it ran.
#pragma once

#include <array>
#include <functional>
#include <vector>

#include "osdmra/base/progress.h"
#include "osdmra/geometry/self_intersection.h"
#include "osdmra/geometry/surface_walk.h"
#include "osdmra/remesh/remesh.h"

namespace osdmra::remeshing {

/// The triangles of `mesh` (M^J sampled from `input`, `where` its vertices' places on
/// it) that cleanUp() repairs as flipped or of zero area: facing against the input
/// triangles under each of their corners, or of no area. 0 where sampling folded nothing.
long long foldedTriangles(const TriMesh& mesh, const std::vector<SurfacePoint>& where,
                          const TriMesh& input, const Connectivity& inputConn);

/// The same, triangle by triangle: 1 where folded.
std::vector<char> foldedTriangleFlags(const TriMesh& mesh, const std::vector<SurfacePoint>& where,
                                      const TriMesh& input, const Connectivity& inputConn);

/// Repairs out.mesh (M^J over out.base, sampled from `input`; `where` its vertices'
/// places on the input, kept up to date; `free` and `line` as in resample.h) and sets
/// the defect counts and the clean-up's own of `out`. `lastResort`, if set, is called
/// once if the repairs leave defects, before the last resort (relaxing whole base faces,
/// which may take seconds). `progress` reports as the repairs go, and an exception
/// thrown from it abandons them. `inputCrossings`: the input's crossing pairs
/// (findSelfIntersections) if the caller has them; found here, if needed, otherwise.
void cleanUp(Remeshing& out, const TriMesh& input, const std::vector<char>& free,
             const std::vector<long long>& line, std::vector<SurfacePoint>& where,
             const SurfaceWalker& walker, const Progress& progress = {},
             const std::function<void()>& lastResort = {},
             const CrossingPairs* inputCrossings = nullptr);

}  // namespace osdmra::remeshing
