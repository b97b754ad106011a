#include "osdmra/codec/local_frames.h"

#include <Eigen/Geometry>
#include <algorithm>

#include "osdmra/base/error.h"

namespace osdmra {

namespace {

using Vec3 = Eigen::RowVector3d;

// Each face's cross product of two edges (twice its area along its normal).
Points faceCrossProducts(const Faces& F, const Points& c) {
  Points n(F.rows(), 3);
  for (int f = 0; f < F.rows(); ++f) {
    const Vec3 a = c.row(F(f, 0)), b = c.row(F(f, 1)), d = c.row(F(f, 2));
    n.row(f) = (b - a).cross(d - a);
  }
  return n;
}

// Area-weighted vertex normals: the sum of the cross products of the faces around
// each vertex.
Points vertexNormals(const Faces& F, const Points& crosses, Eigen::Index vertices) {
  Points N = Points::Zero(vertices, 3);
  for (int f = 0; f < F.rows(); ++f)
    for (int i = 0; i < 3; ++i) N.row(F(f, i)) += crosses.row(f);
  return N;
}

// Unit vector, or none when `v` is too short to have a direction.
bool normalise(Vec3& v) {
  const double len = v.norm();
  if (!(len > 1e-300)) return false;
  v /= len;
  return true;
}

// Per vertex, the largest distance between the unit normal of a face around it and
// its own unit normal (from the faces' cross products and their sums N); 0 for a
// vertex or face too degenerate to have a normal.
Eigen::VectorXd normalSpread(const Faces& F, const Points& crosses, const Points& N) {
  Points unit = N;
  for (Eigen::Index v = 0; v < unit.rows(); ++v) {
    Vec3 n = unit.row(v);
    unit.row(v) = normalise(n) ? n : Vec3::Zero();
  }
  Eigen::VectorXd spread = Eigen::VectorXd::Zero(N.rows());
  for (int f = 0; f < F.rows(); ++f) {
    Vec3 n = crosses.row(f);
    if (!normalise(n)) continue;
    for (int i = 0; i < 3; ++i) {
      const int v = F(f, i);
      if (unit.row(v).isZero()) continue;
      spread[v] = std::max(spread[v], (n - unit.row(v)).norm());
    }
  }
  return spread;
}

}  // namespace

LocalFrames edgeFrames(const Hierarchy& h, int j, const Points& c) {
  if (j < 0 || j >= h.levels() || c.rows() != h.numVertices(j))
    throw Error("edgeFrames: level " + std::to_string(j) + " needs " +
                (j >= 0 && j <= h.levels() ? std::to_string(h.numVertices(j)) : "valid") +
                " control points");
  const Points crosses = faceCrossProducts(h.faces(j), c);
  const Points N = vertexNormals(h.faces(j), crosses, c.rows());
  const Eigen::VectorXd spread = normalSpread(h.faces(j), crosses, N);
  const int E = h.numVertices(j + 1) - h.numVertices(j);
  LocalFrames f{Points(E, 3), Points(E, 3), Points(E, 3), Eigen::VectorXd(E)};
  for (int e = 0; e < E; ++e) {
    const auto [a, b] = h.parentEdge(j, e);
    Vec3 n = N.row(a) + N.row(b);
    if (!normalise(n)) n = Vec3(0, 0, 1);
    Vec3 t = c.row(b) - c.row(a);
    t -= t.dot(n) * n;
    if (!normalise(t)) {
      // Any direction orthogonal to n: the axis least aligned with it, projected.
      Vec3 axis = Vec3::Zero();
      int k = 0;
      n.cwiseAbs().minCoeff(&k);
      axis[k] = 1;
      t = axis - axis.dot(n) * n;
      normalise(t);
    }
    f.bend[e] = std::max(spread[a], spread[b]);
    f.normal.row(e) = n;
    f.along.row(e) = t;
    f.across.row(e) = n.cross(t);
  }
  return f;
}

Points toLocal(const LocalFrames& f, const Points& world) {
  Points out(world.rows(), 3);
  out.col(0) = (world.array() * f.normal.array()).rowwise().sum();
  out.col(1) = (world.array() * f.along.array()).rowwise().sum();
  out.col(2) = (world.array() * f.across.array()).rowwise().sum();
  return out;
}

Points toWorld(const LocalFrames& f, const Points& local) {
  Points out = f.normal.array().colwise() * local.col(0).array();
  out.array() += f.along.array().colwise() * local.col(1).array();
  out.array() += f.across.array().colwise() * local.col(2).array();
  return out;
}

}  // namespace osdmra
