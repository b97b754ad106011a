#include "osdmra/remesh/smoothing.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "osdmra/remesh/distortion.h"

namespace osdmra::remeshing {

namespace {

// Free vertex x's one-ring: its neighbours' places in the chart of base face `face` and
// their positions, counter-clockwise.
struct OneRing {
  int face = -1;
  Vec3 centre;
  std::vector<Vec2> at;
  std::vector<Vec3> position;
};

bool oneRingIn(const TriMesh& input, const Connectivity& conn, const BaseCharts& charts,
               const Simplification& s, int x, int face, OneRing& r) {
  r.face = face;
  r.centre = input.V.row(x).transpose();
  r.at.clear();
  r.position.clear();
  for (int y : conn.ring(x)) {
    Vec2 at;
    if (!placeInputVertex(charts, s, r.face, y, at)) return false;
    r.at.push_back(at);
    r.position.push_back(input.V.row(y).transpose());
  }
  return r.at.size() >= 3;
}

// Floater's mean value coordinates of the centre over its one-ring, from the input's
// angles and lengths: positive, and reproducing a flat ring's centre exactly.
Vec2 meanValuePlace(const OneRing& r) {
  const std::size_t n = r.at.size();
  std::vector<double> halfTan(n);
  for (std::size_t k = 0; k < n; ++k) {
    const Vec3 a = r.position[k] - r.centre, b = r.position[(k + 1) % n] - r.centre;
    halfTan[k] = std::tan(0.5 * angleBetween(a, b));
  }
  Vec2 sum = Vec2::Zero();
  double total = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const double w = (halfTan[(k + n - 1) % n] + halfTan[k]) / (r.position[k] - r.centre).norm();
    sum += w * r.at[k];
    total += w;
  }
  return sum / total;
}

// The largest anisotropy of the triangles around the centre placed at `centre`
// (infinite if one folds).
double worstAround(const OneRing& r, const Vec2& centre) {
  const std::size_t n = r.at.size();
  double worst = 1;
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t l = (k + 1) % n;
    worst = std::max(
        worst, anisotropy({r.centre, r.position[k], r.position[l]}, {centre, r.at[k], r.at[l]}));
  }
  return worst;
}

// The base faces whose charts will see the triangles around x: those holding x and its
// neighbours (the resampling maps each grid point in its own face's chart).
std::vector<int> chartsSeeing(const Connectivity& conn, const Simplification& s, int x) {
  std::vector<int> faces = {s.params[x].face};
  for (int y : conn.ring(x))
    if (s.baseOf[y] < 0 && std::find(faces.begin(), faces.end(), s.params[y].face) == faces.end())
      faces.push_back(s.params[y].face);
  return faces;
}

// Whether x may go to `to` (a place in face `from`'s chart, there `p`): in every chart
// that sees its triangles, none folds and their anisotropy stays within `bound`.
bool acceptable(const TriMesh& input, const Connectivity& conn, const BaseCharts& charts,
                Simplification& s, int x, const Param& p, double bound) {
  const Param old = s.params[x];
  s.params[x] = p;
  bool ok = true;
  OneRing r;
  for (int f : chartsSeeing(conn, s, x)) {
    Vec2 at;
    ok = oneRingIn(input, conn, charts, s, x, f, r) && charts.place(f, p, at) &&
         worstAround(r, at) <= bound;
    if (!ok) break;
  }
  s.params[x] = old;
  return ok;
}

}  // namespace

SmoothingReport smoothParameters(const TriMesh& input, const Connectivity& inputConn,
                                 const BaseCharts& charts, const std::vector<char>& pinned,
                                 Simplification& s, const SmoothingOptions& options) {
  SmoothingReport report;
  const int n = static_cast<int>(input.V.rows());
  OneRing r;
  for (int sweep = 0; sweep < options.sweeps; ++sweep)
    for (int x = 0; x < n; ++x) {
      if (s.baseOf[x] >= 0 || pinned[x] || inputConn.isBoundaryVertex(x)) continue;
      const int face = s.params[x].face;
      if (!oneRingIn(input, inputConn, charts, s, x, face, r)) continue;
      Vec2 now;
      if (!charts.place(face, s.params[x], now)) continue;
      const double bound = std::max(options.anisotropy, worstAround(r, now));
      const Vec2 target = meanValuePlace(r);
      // The whole way, else half of it: kept if nothing folds and the distortion stays
      // within the bound (or, where it was over already, does not rise), in every chart
      // that sees the triangles around.
      bool moved = false;
      for (const double step : {1.0, 0.5}) {
        Param p;
        if (!charts.locate(face, now + step * (target - now), p) ||
            !acceptable(input, inputConn, charts, s, x, p, bound))
          continue;
        s.params[x] = p;
        moved = true;
        break;
      }
      ++(moved ? report.moves : report.refused);
    }
  return report;
}

}  // namespace osdmra::remeshing
