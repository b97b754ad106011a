// Normals of a triangle mesh, for the surfaces that have no analytic ones (the
// polyhedral scheme, remeshing input): each face's normal weighted by its area.
#pragma once

#include <Eigen/Core>

#include "osdmra/mesh/mesh.h"

namespace osdmra {

/// (b - a) x (c - a) for face f = (a, b, c): twice its area times its unit normal.
Eigen::Vector3d faceNormal(const TriMesh& mesh, Eigen::Index f);

/// Face f's angle at its corner i (0, 1 or 2), in [0, pi]: atan2 of |u x w| and u . w
/// for its two edges u, w out of that corner, exact near 0 and pi where acos is not.
/// Summed over a vertex's faces, the cone angle whose defect is the vertex's curvature.
double faceAngle(const TriMesh& mesh, Eigen::Index f, int i);

/// Per vertex, the sum of faceNormal() over its faces: area-weighted, not normalised
/// (for sign tests and blending, where the length says how much surface stands behind
/// a direction).
Points vertexNormalSums(const TriMesh& mesh);

/// vertexNormalSums() scaled to unit length (zero rows stay zero).
Points vertexNormals(const TriMesh& mesh);

}  // namespace osdmra
