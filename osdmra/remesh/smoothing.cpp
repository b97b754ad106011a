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

// The constants of the ring's stretch: for triangle k (centre, neighbour k, neighbour
// k + 1) its surface area and the Gram matrix of its two edges from the centre on the
// surface. They do not depend on where the centre is placed, so every evaluation of the
// stretch while the centre moves is a few multiplications per triangle.
struct StretchTerm {
  double area, aa, bb, ab;  // |Pa|^2, |Pb|^2, Pa . Pb
};
void stretchTerms(const OneRing& r, std::vector<StretchTerm>& terms) {
  const std::size_t n = r.at.size();
  terms.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    const Vec3 a = r.position[k] - r.centre, b = r.position[(k + 1) % n] - r.centre;
    terms[k] = {0.5 * a.cross(b).norm(), a.squaredNorm(), b.squaredNorm(), a.dot(b)};
  }
}

// The ring's stretch with its centre at `u`: over its triangles, the surface area times
// the squared Frobenius norm of the map J from the chart to the surface (Sander et al.
// 2001's L2 stretch, summed as their L2 norm is), and its gradient in u. A grid of the
// chart samples the surface at spacings |J| times its own, so this is low where the
// surface is spread evenly over the chart; it is a barrier at a fold (J grows without
// bound as a triangle of the chart flattens), +infinity past one. With the chart's edges
// e0 = a - u, e1 = b - u and the surface's Pa, Pb: J = [Pa Pb] [e0 e1]^-1, so
// |J|^2 = (|Pa|^2 |e1|^2 + |Pb|^2 |e0|^2 - 2 Pa.Pb e0.e1) / det(e0, e1)^2.
double stretch(const OneRing& r, const std::vector<StretchTerm>& terms, const Vec2& u,
               Vec2* gradient = nullptr) {
  const std::size_t n = r.at.size();
  double e = 0;
  if (gradient) gradient->setZero();
  for (std::size_t k = 0; k < n; ++k) {
    const Vec2 e0 = r.at[k] - u, e1 = r.at[(k + 1) % n] - u;
    const double det = e0.x() * e1.y() - e0.y() * e1.x();
    if (!(det > 0)) return std::numeric_limits<double>::infinity();
    const StretchTerm& t = terms[k];
    const double num = t.aa * e1.squaredNorm() + t.bb * e0.squaredNorm() - 2 * t.ab * e0.dot(e1);
    const double inv2 = 1 / (det * det);
    e += t.area * num * inv2;
    if (!gradient) continue;
    // Both edges move with -u.
    const Vec2 dNum = -2 * t.aa * e1 - 2 * t.bb * e0 + 2 * t.ab * (e0 + e1);
    const Vec2 dDet(e0.y() - e1.y(), e1.x() - e0.x());
    *gradient += t.area * inv2 * (dNum - (2 * num / det) * dDet);
  }
  return e;
}

// The centre moved down the stretch's gradient by the longest of a quarter, an eighth,
// ... of its distance to the nearest neighbour that lowers the stretch (a backtracking
// line search); the centre itself where none does. One step per visit: four (each
// vertex brought near its ring's minimum before the next) left the corpus's scans over
// 150 faces further from the input (the lion at J = 5 0.54% -> 0.61% Hausdorff).
Vec2 lowerStretchPlace(const OneRing& r, const std::vector<StretchTerm>& terms, const Vec2& u) {
  Vec2 g;
  const double e = stretch(r, terms, u, &g);
  if (!std::isfinite(e) || !(g.norm() > 0)) return u;
  double nearest = std::numeric_limits<double>::infinity();
  for (const Vec2& a : r.at) nearest = std::min(nearest, (a - u).norm());
  const Vec2 down = -g / g.norm();
  for (double t = 0.25 * nearest; t > 1e-3 * nearest; t *= 0.5)
    if (stretch(r, terms, u + t * down) < e) return u + t * down;
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
// (infinite if one folds); `flat`: layRingFlat's. Compared by anisotropySum, converted
// once.
double worstAround(const OneRing& r, const FlatRing& flat, const Vec2& centre) {
  const std::size_t n = r.at.size();
  double worst = 2;
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t l = (k + 1) % n;
    worst = std::max(worst, anisotropySum(flat[k], {centre, r.at[k], r.at[l]}));
  }
  return anisotropyFromSum(worst);
}

// The base faces whose charts will see the triangles around x: those holding x and its
// neighbours (the resampling maps each grid point in its own face's chart).
void chartsSeeing(const Connectivity& conn, const Simplification& s, int x,
                  std::vector<int>& faces) {
  faces.assign(1, s.params[x].face);
  for (int y : conn.ring(x))
    if (s.baseOf[y] < 0 && std::find(faces.begin(), faces.end(), s.params[y].face) == faces.end())
      faces.push_back(s.params[y].face);
}

// What acceptable() reads and reuses from vertex to vertex.
struct Check {
  const OneRing* own = nullptr;  // x's ring in the chart of the face x was in: x's own
                                 // place does not change where its neighbours lie there
  OneRing other;
  std::vector<int> faces;
};

// Whether x may go to `to` (a place in face `from`'s chart, there `p`): in every chart
// that sees its triangles, none folds and their anisotropy stays within `bound`.
bool acceptable(const TriMesh& input, const Connectivity& conn, const BaseCharts& charts,
                Simplification& s, int x, const Param& p, double bound, const FlatRing& flat,
                Check& c) {
  const Param old = s.params[x];
  s.params[x] = p;
  chartsSeeing(conn, s, x, c.faces);
  bool ok = true;
  for (int f : c.faces) {
    const bool own = f == c.own->face;
    Vec2 at;
    ok = (own || oneRingIn(input, conn, charts, s, x, f, c.other)) && charts.place(f, p, at) &&
         worstAround(own ? *c.own : c.other, flat, at) <= bound;
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
  OneRing r;  // reused: a ring's lists are allocated once, not per vertex
  Check check;
  check.own = &r;
  std::vector<StretchTerm> terms;
  std::vector<FlatRing> flats(n);  // per vertex, laid on its first move
  for (int sweep = 0; sweep < options.sweeps; ++sweep)
    for (int x = 0; x < n; ++x) {
      if (s.baseOf[x] >= 0 || pinned[x] || inputConn.isBoundaryVertex(x)) continue;
      const int face = s.params[x].face;
      if (!oneRingIn(input, inputConn, charts, s, x, face, r)) continue;
      Vec2 now;
      if (!charts.place(face, s.params[x], now)) continue;
      stretchTerms(r, terms);
      const Vec2 target = lowerStretchPlace(r, terms, now);
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
            !acceptable(input, inputConn, charts, s, x, p, bound, flat, check))
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
