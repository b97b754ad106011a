#include "osdmra/remesh/smoothing.h"

#include <Eigen/LU>
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

// The ring's stretch with its centre at `u`: over its triangles, the surface area times
// the squared Frobenius norm of the map J from the chart to the surface (Sander et al.
// 2001's L2 stretch, summed as their L2 norm is), and its gradient in u. A grid of the
// chart samples the surface at spacings |J| times its own, so this is low where the
// surface is spread evenly over the chart; it is a barrier at a fold (J grows without
// bound as a triangle of the chart flattens), +infinity past one.
double stretch(const OneRing& r, const Vec2& u, Vec2* gradient = nullptr) {
  const std::size_t n = r.at.size();
  double e = 0;
  if (gradient) gradient->setZero();
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t l = (k + 1) % n;
    Eigen::Matrix2d q;
    q.col(0) = r.at[k] - u;
    q.col(1) = r.at[l] - u;
    if (!(q.determinant() > 0)) return std::numeric_limits<double>::infinity();
    Eigen::Matrix<double, 3, 2> p;
    p.col(0) = r.position[k] - r.centre;
    p.col(1) = r.position[l] - r.centre;
    const Eigen::Matrix2d qInverse = q.inverse();
    const Eigen::Matrix<double, 3, 2> j = p * qInverse;
    const double area = 0.5 * p.col(0).cross(p.col(1)).norm();
    e += area * j.squaredNorm();
    if (!gradient) continue;
    // Both columns of q move with -u: dJ = J [d d] q^-1 for a step d of u.
    for (int axis = 0; axis < 2; ++axis) {
      Eigen::Matrix2d dq = Eigen::Matrix2d::Zero();
      dq.row(axis).setOnes();
      (*gradient)[axis] += 2 * area * (j.cwiseProduct(j * dq * qInverse)).sum();
    }
  }
  return e;
}

// The centre moved down the stretch's gradient by the longest of a quarter, an eighth,
// ... of its distance to the nearest neighbour that lowers the stretch (a backtracking
// line search); the centre itself where none does.
Vec2 lowerStretchPlace(const OneRing& r, const Vec2& u) {
  Vec2 g;
  const double e = stretch(r, u, &g);
  if (!std::isfinite(e) || !(g.norm() > 0)) return u;
  double nearest = std::numeric_limits<double>::infinity();
  for (const Vec2& a : r.at) nearest = std::min(nearest, (a - u).norm());
  const Vec2 down = -g / g.norm();
  for (double t = 0.25 * nearest; t > 1e-3 * nearest; t *= 0.5)
    if (stretch(r, u + t * down) < e) return u + t * down;
  return u;
}

// The triangles around the centre of `r` (centre, neighbour k, neighbour k + 1) laid
// flat: they never move, and every check of the vertex measures them again.
using FlatRing = std::vector<std::array<Vec2, 3>>;
void layRingFlat(const OneRing& r, FlatRing& flat) {
  const std::size_t n = r.at.size();
  flat.resize(n);
  for (std::size_t k = 0; k < n; ++k)
    flat[k] = layFlat(r.centre, r.position[k], r.position[(k + 1) % n]);
}

// The largest anisotropy of the triangles around the centre placed at `centre`
// (infinite if one folds); `flat`: layRingFlat's.
double worstAround(const OneRing& r, const FlatRing& flat, const Vec2& centre) {
  const std::size_t n = r.at.size();
  double worst = 1;
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t l = (k + 1) % n;
    worst = std::max(worst, anisotropyFromFlat(flat[k], {centre, r.at[k], r.at[l]}));
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
                Simplification& s, int x, const Param& p, double bound, const FlatRing& flat,
                OneRing& r) {
  const Param old = s.params[x];
  s.params[x] = p;
  bool ok = true;
  for (int f : chartsSeeing(conn, s, x)) {
    Vec2 at;
    ok = oneRingIn(input, conn, charts, s, x, f, r) && charts.place(f, p, at) &&
         worstAround(r, flat, at) <= bound;
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
  OneRing r, other;                // reused: a ring's lists are allocated once, not per vertex
  std::vector<FlatRing> flats(n);  // per vertex, laid on its first move
  for (int sweep = 0; sweep < options.sweeps; ++sweep)
    for (int x = 0; x < n; ++x) {
      if (s.baseOf[x] >= 0 || pinned[x] || inputConn.isBoundaryVertex(x)) continue;
      const int face = s.params[x].face;
      if (!oneRingIn(input, inputConn, charts, s, x, face, r)) continue;
      Vec2 now;
      if (!charts.place(face, s.params[x], now)) continue;
      const Vec2 target = lowerStretchPlace(r, now);
      if (target == now) continue;  // at a minimum of its ring's stretch already
      FlatRing& flat = flats[x];
      if (flat.empty()) layRingFlat(r, flat);
      const double bound = std::max(options.anisotropy, worstAround(r, flat, now));
      // The whole way, else half of it: kept if nothing folds and the distortion stays
      // within the bound (or, where it was over already, does not rise), in every chart
      // that sees the triangles around.
      bool moved = false;
      for (const double step : {1.0, 0.5}) {
        Param p;
        if (!charts.locate(face, now + step * (target - now), p) ||
            !acceptable(input, inputConn, charts, s, x, p, bound, flat, other))
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
