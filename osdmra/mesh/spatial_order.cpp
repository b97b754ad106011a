#include "osdmra/mesh/spatial_order.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <tuple>

namespace osdmra {
namespace {

/// Spreads the low 21 bits of x so that bit i lands on bit 3 i.
std::uint64_t spreadBits(std::uint64_t x) {
  x &= 0x1fffff;
  x = (x | x << 32) & 0x1f00000000ffffull;
  x = (x | x << 16) & 0x1f0000ff0000ffull;
  x = (x | x << 8) & 0x100f00f00f00f00full;
  x = (x | x << 4) & 0x10c30c30c30c30c3ull;
  x = (x | x << 2) & 0x1249249249249249ull;
  return x;
}

}  // namespace

std::vector<Eigen::Index> mortonOrder(const Points& points) {
  const Eigen::Index n = points.rows();
  if (n == 0) return {};
  // Ties of the curve (positions in one cell of the grid) by the coordinates themselves,
  // then by row: the order depends on the positions alone wherever they differ.
  struct Keyed {
    std::uint64_t code;
    std::array<double, 3> at;
    Eigen::Index row;
    bool operator<(const Keyed& o) const {
      return std::tie(code, at, row) < std::tie(o.code, o.at, o.row);
    }
  };
  std::vector<Keyed> keyed(static_cast<std::size_t>(n));
  const Eigen::RowVector3d lo = points.colwise().minCoeff(), hi = points.colwise().maxCoeff();
  Eigen::RowVector3d scale = Eigen::RowVector3d::Zero();
  for (int k = 0; k < 3; ++k)
    if (hi[k] > lo[k]) scale[k] = double((1 << 21) - 1) / (hi[k] - lo[k]);
  for (Eigen::Index i = 0; i < n; ++i) {
    std::uint64_t code = 0;
    for (int k = 0; k < 3; ++k) {
      const double q = std::clamp((points(i, k) - lo[k]) * scale[k], 0.0, double((1 << 21) - 1));
      code |= spreadBits(static_cast<std::uint64_t>(q)) << k;
    }
    keyed[i] = {code, {points(i, 0), points(i, 1), points(i, 2)}, i};
  }
  std::sort(keyed.begin(), keyed.end());
  std::vector<Eigen::Index> order(static_cast<std::size_t>(n));
  for (Eigen::Index i = 0; i < n; ++i) order[i] = keyed[i].row;
  return order;
}

TriMesh inSpatialOrder(const TriMesh& mesh) {
  const std::vector<Eigen::Index> order = mortonOrder(mesh.V);
  std::vector<int> newOf(order.size());
  TriMesh out;
  out.V.resize(mesh.V.rows(), 3);
  const bool normals = mesh.N.rows() == mesh.V.rows() && mesh.N.rows() > 0;
  if (normals) out.N.resize(mesh.N.rows(), 3);
  for (std::size_t k = 0; k < order.size(); ++k) {
    newOf[order[k]] = static_cast<int>(k);
    out.V.row(k) = mesh.V.row(order[k]);
    if (normals) out.N.row(k) = mesh.N.row(order[k]);
  }
  std::vector<std::array<int, 3>> faces(static_cast<std::size_t>(mesh.F.rows()));
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) {
    std::array<int, 3> t = {newOf[mesh.F(f, 0)], newOf[mesh.F(f, 1)], newOf[mesh.F(f, 2)]};
    std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
    faces[f] = t;
  }
  std::sort(faces.begin(), faces.end());
  out.F.resize(mesh.F.rows(), 3);
  for (std::size_t f = 0; f < faces.size(); ++f)
    for (int i = 0; i < 3; ++i) out.F(f, i) = faces[f][i];
  return out;
}

}  // namespace osdmra
