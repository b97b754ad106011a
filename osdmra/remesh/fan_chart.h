// A base vertex's faces laid about it one after the other (step 2 of remesh.h): the one
// chart in which an input triangle whose corners lie around a base vertex has the same
// image, whichever of the vertex's faces asks for it.
//
// BaseCharts lays the faces around a face's corners breadth first, so around a corner
// whose angles do not sum to a whole turn (a cone, a saddle) they come out cut apart
// somewhere, and where depends on the face the chart is laid from. An input triangle
// with corners in faces on either side of that cut has one image per chart: on small
// base faces, two neighbouring faces' grids placed the points of their shared edge
// through different images of one input triangle, and the grid folded there (the lion
// over 150 base faces, stages mesh-wide: 18 of its 19 sampled folds). Laid about the
// vertex instead, each corner at its angle about it and its distance from it, on the arc
// of the turn the corners span (a triangle not holding the vertex spans less than a half
// turn of it in any flat image), the triangle has one shape: the chart of each face
// differs from another's only by a rigid motion.
#pragma once

#include <array>

#include "osdmra/mesh/connectivity.h"
#include "osdmra/remesh/distortion.h"
#include "osdmra/remesh/simplify.h"

namespace osdmra::remeshing {

/// A point of the base mesh: base vertex `vertex` if it is not -1, else `param`.
struct BasePoint {
  int vertex = -1;
  Param param;
};

/// The triangle with corners `corners` laid about corner `iv` of base face f (vertex v)
/// in f's chart, where f lies as `own` (BaseCharts::own): v's faces turned about v one
/// after the other from f, each by its angle at v, and each corner placed at its angle
/// about v and its distance from v. The angles are taken on the arc the corners span:
/// counter-clockwise from the corner after v to the one before where v is a corner,
/// else the turn less the widest gap between them; that arc is taken the way round v
/// that keeps it nearest f (on the base's boundary, v's faces from the boundary on).
/// False where a corner is neither v, a neighbour of v, nor a point of v's faces.
bool layAboutCorner(const TriMesh& base, const Connectivity& baseConn, int f, int iv,
                    const Laid& own, const std::array<BasePoint, 3>& corners,
                    std::array<Vec2, 3>& image);

}  // namespace osdmra::remeshing
