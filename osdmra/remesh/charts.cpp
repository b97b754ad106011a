#include "osdmra/remesh/charts.h"

#include <algorithm>

#include "osdmra/geometry/surface_walk.h"

namespace osdmra::remeshing {

namespace {

std::array<int, 3> faceOf(const TriMesh& base, int g) {
  return {base.F(g, 0), base.F(g, 1), base.F(g, 2)};
}

// Face f and the faces within `rings` rings of it (sharing a vertex with the ring
// before), nearest first.
std::vector<int> facesAround(const TriMesh& base, const Connectivity& conn, int f, int rings) {
  std::vector<int> around = {f};
  for (int ring = 0; ring < rings; ++ring) {
    const std::size_t known = around.size();
    for (std::size_t i = 0; i < known; ++i)
      for (int k = 0; k < 3; ++k)
        for (int h : conn.fan(base.F(around[i], k)))
          if (std::find(around.begin(), around.end(), h / 3) == around.end())
            around.push_back(h / 3);
  }
  return around;
}

}  // namespace

BaseCharts::BaseCharts(const TriMesh& base, int rings) {
  const Connectivity conn(base.F, static_cast<int>(base.V.rows()));
  const int nb = static_cast<int>(base.F.rows());
  charts_.resize(nb);
  ids_.resize(nb);
  for (int f = 0; f < nb; ++f) {
    const std::vector<int> around = facesAround(base, conn, f, rings);
    std::vector<std::array<int, 3>> faces;
    for (int g : around) faces.push_back(faceOf(base, g));
    std::vector<std::size_t> index;
    charts_[f] = layBreadthFirst(base.V, faces, faces.size(), index);
    for (std::size_t q : index) ids_[f].push_back(around[q]);
  }
}

bool BaseCharts::place(int f, const Param& p, Vec2& at) const {
  const auto i = std::find(ids_[f].begin(), ids_[f].end(), p.face) - ids_[f].begin();
  if (i == static_cast<long>(ids_[f].size())) return false;
  at = pointIn(charts_[f][i], p.bary);
  return true;
}

bool BaseCharts::placeVertex(int f, int v, Vec2& at) const {
  return vertexIn(charts_[f], v, at);
}

bool BaseCharts::locate(int f, const Vec2& at, Param& p) const {
  for (std::size_t q = 0; q < charts_[f].size(); ++q) {
    const Laid& l = charts_[f][q];
    const std::array<double, 3> b = barycentric(at, l.pos[0], l.pos[1], l.pos[2]);
    if (!(minOf(b) >= -1e-12)) continue;
    p = {ids_[f][q], clampedBarycentric(b)};
    return true;
  }
  return false;
}

bool placeInputVertex(const BaseCharts& charts, const Simplification& s, int f, int x, Vec2& at) {
  return s.baseOf[x] >= 0 ? charts.placeVertex(f, s.baseOf[x], at)
                          : charts.place(f, s.params[x], at);
}

}  // namespace osdmra::remeshing
