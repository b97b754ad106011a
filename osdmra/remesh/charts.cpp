#include "osdmra/remesh/charts.h"

#include <algorithm>

namespace osdmra::remeshing {

namespace {

std::array<int, 3> faceOf(const TriMesh& base, int g) {
  return {base.F(g, 0), base.F(g, 1), base.F(g, 2)};
}

// The faces within `rings` rings of face f (sharing a vertex with the ring before),
// nearest first, f excluded.
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
  around.erase(around.begin());
  return around;
}

}  // namespace

BaseCharts::BaseCharts(const TriMesh& base, int rings) {
  const Connectivity conn(base.F, static_cast<int>(base.V.rows()));
  const int nb = static_cast<int>(base.F.rows());
  charts_.resize(nb);
  ids_.resize(nb);
  for (int f = 0; f < nb; ++f) {
    const std::array<int, 3> own = faceOf(base, f);
    charts_[f].push_back(
        {own, layFlat(base.V.row(own[0]).transpose(), base.V.row(own[1]).transpose(),
                      base.V.row(own[2]).transpose())});
    ids_[f].push_back(f);
    // Breadth first: each face hinged to the first laid face it shares an edge with.
    const std::vector<int> around = facesAround(base, conn, f, rings);
    std::vector<char> done(around.size(), 0);
    for (std::size_t head = 0; head < charts_[f].size(); ++head)
      for (std::size_t q = 0; q < around.size(); ++q) {
        Laid next;
        if (done[q] || !hinge(base.V, charts_[f][head], faceOf(base, around[q]), next)) continue;
        done[q] = 1;
        charts_[f].push_back(next);
        ids_[f].push_back(around[q]);
      }
  }
}

bool BaseCharts::place(int f, const Param& p, Vec2& at) const {
  const auto i = std::find(ids_[f].begin(), ids_[f].end(), p.face) - ids_[f].begin();
  if (i == static_cast<long>(ids_[f].size())) return false;
  const Laid& l = charts_[f][i];
  at = p.bary[0] * l.pos[0] + p.bary[1] * l.pos[1] + p.bary[2] * l.pos[2];
  return true;
}

bool BaseCharts::placeVertex(int f, int v, Vec2& at) const {
  for (const Laid& l : charts_[f]) {
    const auto i = std::find(l.face.begin(), l.face.end(), v) - l.face.begin();
    if (i == 3) continue;
    at = l.pos[i];
    return true;
  }
  return false;
}

bool BaseCharts::locate(int f, const Vec2& at, Param& p) const {
  for (std::size_t q = 0; q < charts_[f].size(); ++q) {
    const Laid& l = charts_[f][q];
    std::array<double, 3> b = barycentric(at, l.pos[0], l.pos[1], l.pos[2]);
    if (!(minOf(b) >= -1e-12)) continue;
    for (double& x : b) x = std::max(x, 0.0);
    const double sum = b[0] + b[1] + b[2];
    p = {ids_[f][q], {b[0] / sum, b[1] / sum, b[2] / sum}};
    return true;
  }
  return false;
}

bool placeInputVertex(const BaseCharts& charts, const Simplification& s, int f, int x, Vec2& at) {
  return s.baseOf[x] >= 0 ? charts.placeVertex(f, s.baseOf[x], at)
                          : charts.place(f, s.params[x], at);
}

}  // namespace osdmra::remeshing
