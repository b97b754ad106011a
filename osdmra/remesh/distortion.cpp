#include "osdmra/remesh/distortion.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace osdmra::remeshing {

std::array<Vec2, 3> layFlat(const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 e1 = b - a, e2 = c - a;
  const double len = e1.norm();
  if (!(len > 0)) return {Vec2::Zero(), Vec2::Zero(), Vec2::Zero()};
  const double x = e2.dot(e1) / len, y = e1.cross(e2).norm() / len;
  return {Vec2::Zero(), Vec2(len, 0), Vec2(x, y)};
}

double anisotropy(const std::array<Vec3, 3>& from, const std::array<Vec2, 3>& to) {
  return anisotropyFromFlat(layFlat(from[0], from[1], from[2]), to);
}

double anisotropyFromFlat(const std::array<Vec2, 3>& src, const std::array<Vec2, 3>& to) {
  return anisotropyFromSum(anisotropySum(src, to));
}

// With S and T the edges from corner 0 of `src` and `to`, the map is J = T S^-1, whose
// squared singular values s1^2, s2^2 have the sum |J|^2 and the product det(J)^2; so
// s1 / s2 + s2 / s1 = |J|^2 / det(J) = |T adj(S)|^2 / (det(S) det(T)).
double anisotropySum(const std::array<Vec2, 3>& src, const std::array<Vec2, 3>& to) {
  const Vec2 s0 = src[1] - src[0], s1 = src[2] - src[0];
  const Vec2 t0 = to[1] - to[0], t1 = to[2] - to[0];
  const double detS = s0.x() * s1.y() - s0.y() * s1.x(), detT = t0.x() * t1.y() - t0.y() * t1.x();
  if (!(detS > 0) || !(detT > 0)) return std::numeric_limits<double>::infinity();
  const Vec2 c0 = s1.y() * t0 - s0.y() * t1, c1 = s0.x() * t1 - s1.x() * t0;  // T adj(S)
  const double sum = (c0.squaredNorm() + c1.squaredNorm()) / (detS * detT);
  return sum > 0 ? sum : std::numeric_limits<double>::infinity();
}

double anisotropyFromSum(double sum) {
  // The larger root of k^2 - sum k + 1 = 0; no cancellation, as both terms are positive.
  return 0.5 * (sum + std::sqrt(std::max(0.0, sum * sum - 4)));
}

bool hinge(const Points& V, const Laid& from, const std::array<int, 3>& f, Laid& out) {
  int apart = -1, shared = 0;
  std::array<int, 3> at{};  // f's corners in `from`, -1 for the one apart
  const std::array<int, 3>& g = from.face;
  for (int i = 0; i < 3; ++i) {
    at[i] = f[i] == g[0] ? 0 : f[i] == g[1] ? 1 : f[i] == g[2] ? 2 : 3;
    if (at[i] < 3)
      ++shared;
    else
      apart = i;
  }
  if (shared != 2) return false;
  const int iu = (apart + 1) % 3, iw = (apart + 2) % 3;
  const Vec2 pu = from.pos[at[iu]], pw = from.pos[at[iw]];
  const Vec3 u = V.row(f[iu]).transpose(), w = V.row(f[iw]).transpose(),
             o = V.row(f[apart]).transpose();
  const double len = (pw - pu).norm();
  if (!(len > 0)) return false;
  const double du = (o - u).norm(), dw = (o - w).norm();
  const double x = (du * du - dw * dw + len * len) / (2 * len);
  const double y = std::sqrt(std::max(0.0, du * du - x * x));
  const Vec2 ex = (pw - pu) / len;
  out.face = f;
  out.pos[iu] = pu;
  out.pos[iw] = pw;
  out.pos[apart] = pu + x * ex + y * Vec2(-ex.y(), ex.x());  // left of u -> w
  return true;
}

std::vector<Laid> layBreadthFirst(const Points& V, const std::vector<std::array<int, 3>>& faces,
                                  std::size_t needed, std::vector<std::size_t>& index) {
  std::vector<Laid> laid;
  layBreadthFirst(V, faces, needed, laid, index);
  return laid;
}

void layBreadthFirst(const Points& V, const std::vector<std::array<int, 3>>& faces,
                     std::size_t needed, std::vector<Laid>& laid, std::vector<std::size_t>& index) {
  const std::array<int, 3>& first = faces[0];
  laid.assign(1, {first, layFlat(V.row(first[0]).transpose(), V.row(first[1]).transpose(),
                                 V.row(first[2]).transpose())});
  index.assign(1, 0);
  thread_local std::vector<char> done;
  done.assign(faces.size(), 0);
  done[0] = 1;
  // Most pairs tried share no edge: a face's vertices as bits (id mod 64) rule those out
  // at one AND, where its three bits are distinct (else bits 0, and hinge() decides).
  thread_local std::vector<std::uint64_t> bits;
  bits.resize(faces.size());
  for (std::size_t q = 0; q < faces.size(); ++q) {
    std::uint64_t b = 0;
    for (int v : faces[q]) b |= std::uint64_t{1} << (static_cast<unsigned>(v) & 63u);
    const std::uint64_t rest = b & (b - 1), last = rest & (rest - 1);  // 3 bits: last != 0
    bits[q] = last != 0 ? b : 0;
  }
  auto mayShareEdge = [&](std::size_t a, std::size_t b) {
    const std::uint64_t common = bits[a] & bits[b];
    return bits[a] == 0 || bits[b] == 0 || (common & (common - 1)) != 0;  // two bits or more
  };
  std::size_t found = 1;
  for (std::size_t head = 0; head < laid.size() && found < needed; ++head)
    for (std::size_t q = 1; q < faces.size(); ++q) {
      Laid next;
      if (done[q] || !mayShareEdge(index[head], q) || !hinge(V, laid[head], faces[q], next))
        continue;
      done[q] = 1;
      laid.push_back(next);
      index.push_back(q);
      if (q < needed) ++found;
    }
}

bool vertexIn(const std::vector<Laid>& laid, int v, Vec2& at) {
  for (const Laid& l : laid) {
    const auto i = std::find(l.face.begin(), l.face.end(), v) - l.face.begin();
    if (i == 3) continue;
    at = l.pos[i];
    return true;
  }
  return false;
}

namespace {

bool sameFace(const std::array<int, 3>& f, const std::array<int, 3>& g) {
  return f[0] == g[0] && f[1] == g[1] && f[2] == g[2];
}

bool inFace(int v, const std::array<int, 3>& f) {
  return std::count(f.begin(), f.end(), v) == 1;
}

// Storage reused by chartImage() on each thread (the simplification's distortion checks
// call it about twenty times per input triangle).
struct ChartScratch {
  std::vector<std::array<int, 3>> faces, around;
  std::vector<Laid> laid;
  std::vector<std::size_t> index;
};
ChartScratch& scratch() {
  thread_local ChartScratch s;
  return s;
}

std::array<int, 3> firstFaceAround(const FacesAround& facesAround, int w) {
  std::vector<std::array<int, 3>>& around = scratch().around;
  around.clear();
  facesAround(w, around);
  return around.front();
}

// The chart of the general case below when the faces its corners bring (their own,
// and one around each vertex corner that none of those has) lay in one pass, as it
// would lay them, in fixed arrays instead of its lists: most triangles, once the faces
// hold many points. False when they do not lay so (the general case then brings more).
bool imageInCornerFaces(const Points& V, const std::array<Placed, 3>& at,
                        const FacesAround& facesAround, std::array<Vec2, 3>& image) {
  std::array<std::array<int, 3>, 6> faces;
  int n = 0;
  auto add = [&](const std::array<int, 3>& f) {
    if (std::none_of(faces.begin(), faces.begin() + n,
                     [&](const auto& g) { return sameFace(f, g); }))
      faces[n++] = f;
  };
  for (const Placed& c : at)
    if (!c.isVertex) add(c.face);
  for (const Placed& c : at)
    if (c.isVertex && std::none_of(faces.begin(), faces.begin() + n,
                                   [&](const auto& f) { return inFace(c.vertex, f); }))
      add(firstFaceAround(facesAround, c.vertex));
  // Breadth first from the first face, as layBreadthFirst.
  std::array<Laid, 6> laid;
  std::array<char, 6> done{};
  const std::array<int, 3>& first = faces[0];
  laid[0] = {first, layFlat(V.row(first[0]).transpose(), V.row(first[1]).transpose(),
                            V.row(first[2]).transpose())};
  done[0] = 1;
  int count = 1;
  for (int head = 0; head < count && count < n; ++head)
    for (int q = 1; q < n; ++q) {
      if (done[q] || !hinge(V, laid[head], faces[q], laid[count])) continue;
      done[q] = 1;
      ++count;
    }
  if (count < n) return false;
  for (int k = 0; k < 3; ++k) {
    const Placed& c = at[k];
    const auto holds = [&](const Laid& l) {
      return c.isVertex ? inFace(c.vertex, l.face) : sameFace(l.face, c.face);
    };
    const Laid* l = std::find_if(laid.begin(), laid.begin() + count, holds);
    if (l == laid.begin() + count) return false;
    image[k] = c.isVertex
                   ? l->pos[std::find(l->face.begin(), l->face.end(), c.vertex) - l->face.begin()]
                   : pointIn(*l, c.bary);
  }
  return true;
}

}  // namespace

bool chartImage(const Points& V, const std::array<Placed, 3>& at, const FacesAround& facesAround,
                std::array<Vec2, 3>& image) {
  if (imageInCornerFaces(V, at, facesAround, image)) return true;
  ChartScratch& s = scratch();
  std::vector<std::array<int, 3>>& faces = s.faces;  // the corners' first, then the ones around
  faces.clear();
  auto add = [&](const std::array<int, 3>& f) {
    if (std::none_of(faces.begin(), faces.end(), [&](const auto& g) { return sameFace(f, g); }))
      faces.push_back(f);
  };
  auto addAround = [&](int w) {
    s.around.clear();
    facesAround(w, s.around);
    for (const auto& f : s.around) add(f);
  };
  for (const Placed& c : at)
    if (!c.isVertex) add(c.face);
  for (const Placed& c : at)
    if (c.isVertex && std::none_of(faces.begin(), faces.end(),
                                   [&](const auto& f) { return inFace(c.vertex, f); }))
      add(firstFaceAround(facesAround, c.vertex));
  const std::size_t required = faces.size();
  std::vector<Laid>& laid = s.laid;
  auto layFrom = [&] {
    layBreadthFirst(V, faces, required, laid, s.index);
    return static_cast<std::size_t>(std::count_if(s.index.begin(), s.index.end(),
                                                  [&](std::size_t q) { return q < required; })) ==
           required;
  };
  if (!layFrom()) {
    int common = -1;
    for (int w : faces[0])
      if (std::all_of(faces.begin(), faces.begin() + required,
                      [&](const auto& f) { return inFace(w, f); }))
        common = w;
    if (common >= 0) addAround(common);
    if (common < 0 || !layFrom()) {
      for (std::size_t q = 0; q < required; ++q)
        for (int w : std::array<int, 3>(faces[q]))  // a copy: addAround() grows `faces`
          addAround(w);
      if (!layFrom()) return false;
    }
  }
  for (int k = 0; k < 3; ++k) {
    const Placed& c = at[k];
    if (c.isVertex) {
      vertexIn(laid, c.vertex, image[k]);
      continue;
    }
    image[k] = pointIn(*std::find_if(laid.begin(), laid.end(),
                                     [&](const Laid& l) { return sameFace(l.face, c.face); }),
                       c.bary);
  }
  return true;
}

}  // namespace osdmra::remeshing
