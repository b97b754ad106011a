#include "osdmra/remesh/removal.h"

#include <cmath>

namespace osdmra::remeshing {

namespace {

// Ear clipping of one simple counter-clockwise polygon (local indices).
std::vector<std::array<int, 3>> earClip(const std::vector<Vec2>& p) {
  std::vector<int> poly(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) poly[i] = static_cast<int>(i);
  std::vector<std::array<int, 3>> out;
  while (poly.size() > 3) {
    const int n = static_cast<int>(poly.size());
    int best = -1;
    double bestQuality = -1;
    for (int i = 0; i < n; ++i) {
      const int a = poly[(i + n - 1) % n], b = poly[i], c = poly[(i + 1) % n];
      if (cross2(p[b] - p[a], p[c] - p[b]) <= 1e-14) continue;  // reflex or flat
      bool empty = true;
      for (int k = 0; k < n && empty; ++k) {
        const int q = poly[k];
        if (q == a || q == b || q == c) continue;
        empty = minOf(barycentric(p[q], p[a], p[b], p[c])) < -1e-12;
      }
      if (!empty) continue;
      const double quality = smallestAngle(p[a], p[b], p[c]);
      if (quality > bestQuality) {
        bestQuality = quality;
        best = i;
      }
    }
    if (best < 0) return {};
    out.push_back({poly[(best + n - 1) % n], poly[best], poly[(best + 1) % n]});
    poly.erase(poly.begin() + best);
  }
  if (poly.size() == 3) {
    if (cross2(p[poly[1]] - p[poly[0]], p[poly[2]] - p[poly[0]]) <= 1e-14) return {};
    out.push_back({poly[0], poly[1], poly[2]});
  }
  return out;
}

// Sets the polar angles of points from..to: the 3D angles `theta` scaled to `span`.
void spread(const std::vector<double>& theta, int from, int to, double startAngle, double span,
            std::vector<double>& phi) {
  double sum = 0;
  for (int k = from; k < to; ++k) sum += theta[k];
  double acc = startAngle;
  for (int k = from; k < to; ++k) {
    phi[k] = acc;
    acc += theta[k] * span / std::max(sum, 1e-300);
  }
  phi[to] = acc;
}

// Sine of the angle at a in triangle (a, b, c), signed by orientation.
double orientedSine(const Vec2& a, const Vec2& b, const Vec2& c) {
  const double scale = (b - a).norm() * (c - a).norm();
  return scale > 0 ? cross2(b - a, c - a) / scale : 0.0;
}

// Whether positive triangles on the polygon's vertices form a disk with the polygon as
// its boundary: each polygon edge used once, in its direction, and every other edge
// once each way. Positive faces of such a disk with a simple boundary tile it once.
bool tilesOnce(const std::vector<std::array<int, 3>>& triangles, int m, bool boundary) {
  const int n = boundary ? m + 1 : m;  // distinct polygon vertices
  auto index = [&](int k) { return k % n; };
  std::vector<int> uses(static_cast<std::size_t>(n) * n, 0);  // directed edge counts
  for (const auto& t : triangles)
    for (int i = 0; i < 3; ++i) ++uses[index(t[i]) * n + index(t[(i + 1) % 3])];
  for (int a = 0; a < n; ++a)
    for (int b = 0; b < n; ++b) {
      if (a == b) continue;
      const bool rim = b == (a + 1) % n, rimReversed = a == (b + 1) % n;
      const int here = uses[a * n + b], back = uses[b * n + a];
      if (rim && here != 1) return false;
      if (!rim && !rimReversed && here != back) return false;
      if (here > 1 || (rimReversed && here != 0)) return false;
    }
  return static_cast<int>(triangles.size()) == n - 2;
}

}  // namespace

Flattening flattenRing(const Vec3& center, const std::vector<Vec3>& ring, bool boundary,
                       int featureAt) {
  const int m = static_cast<int>(ring.size()) - 1;
  Flattening out;
  std::vector<double> theta(m);
  double total = 0;
  for (int k = 0; k < m; ++k) {
    const Vec3 a = ring[k] - center, b = ring[k + 1] - center;
    theta[k] = angleBetween(a, b);
    total += theta[k];
  }
  out.exponent = total > 1e-12 ? (boundary ? kPi : 2 * kPi) / total : 0.0;
  std::vector<double> phi(m + 1, 0.0);
  if (featureAt >= 0) {
    spread(theta, 0, featureAt, 0.0, kPi, phi);
    spread(theta, featureAt, m, kPi, kPi, phi);
  } else {
    spread(theta, 0, m, 0.0, boundary ? kPi : 2 * kPi, phi);
  }
  out.angles.resize(m);
  for (int k = 0; k < m; ++k) out.angles[k] = phi[k + 1] - phi[k];
  out.points.resize(m + 1);
  for (int k = 0; k <= m; ++k) {
    const double rho = std::pow((ring[k] - center).norm(), out.exponent);
    out.points[k] = rho * Vec2(std::cos(phi[k]), std::sin(phi[k]));
  }
  if (!boundary) out.points[m] = out.points[0];
  return out;
}

std::vector<std::array<int, 3>> triangulateRing(const std::vector<Vec2>& points, bool boundary,
                                                int featureAt) {
  const int m = static_cast<int>(points.size()) - 1;
  std::vector<std::array<int, 3>> tris;
  auto clip = [&](int from, int to) {  // the polygon points[from..to]
    std::vector<Vec2> poly(points.begin() + from, points.begin() + to + 1);
    const std::vector<std::array<int, 3>> t = earClip(poly);
    for (const auto& x : t) tris.push_back({x[0] + from, x[1] + from, x[2] + from});
    return !t.empty();
  };
  const bool ok =
      featureAt >= 0 ? clip(0, featureAt) && clip(featureAt, m) : clip(0, boundary ? m : m - 1);
  if (!ok) tris.clear();
  return tris;
}

std::vector<std::array<int, 3>> fanOfRing(int from, int numPoints, bool boundary) {
  const int corners = boundary ? numPoints : numPoints - 1;
  std::vector<std::array<int, 3>> tris;
  for (int i = 1; i + 1 < corners; ++i)
    tris.push_back({from, (from + i) % corners, (from + i + 1) % corners});
  return tris;
}

bool isBijective(const Flattening& flat, const std::vector<std::array<int, 3>>& triangles,
                 bool boundary, double margin) {
  const int m = static_cast<int>(flat.points.size()) - 1;
  if (triangles.empty() || !(flat.exponent > 0)) return false;
  // The fan: each flat angle strictly between 0 and pi.
  for (int k = 0; k < m; ++k)
    if (!(flat.angles[k] > margin && flat.angles[k] < kPi - margin) || !(flat.points[k].norm() > 0))
      return false;
  // The new faces: positive at every corner (a positive triangle has all three).
  for (const auto& t : triangles)
    for (int i = 0; i < 3; ++i)
      if (!(orientedSine(flat.points[t[i]], flat.points[t[(i + 1) % 3]],
                         flat.points[t[(i + 2) % 3]]) > margin))
        return false;
  return tilesOnce(triangles, m, boundary);
}

int locateInTriangles(const Vec2& p, const std::vector<Vec2>& points,
                      const std::vector<std::array<int, 3>>& triangles,
                      std::array<double, 3>& bary) {
  int best = -1;
  std::array<double, 3> bestBary{-1e300, 0, 0};
  for (std::size_t q = 0; q < triangles.size(); ++q) {
    const auto b =
        barycentric(p, points[triangles[q][0]], points[triangles[q][1]], points[triangles[q][2]]);
    if (minOf(b) > minOf(bestBary)) {
      bestBary = b;
      best = static_cast<int>(q);
    }
  }
  // Rounding only: a point of the fan is inside the polygon the new faces tile.
  if (best < 0 || minOf(bestBary) < -1e-9) return -1;
  for (double& x : bestBary) x = std::max(x, 0.0);
  const double sum = bestBary[0] + bestBary[1] + bestBary[2];
  for (double& x : bestBary) x /= sum;
  bary = bestBary;
  return best;
}

}  // namespace osdmra::remeshing
