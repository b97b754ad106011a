#include "osdmra/mra/lod.h"

#include <algorithm>
#include <array>
#include <string>
#include <utility>

#include "osdmra/base/error.h"
#include "osdmra/mra/detail/lod_closure.h"

namespace osdmra {

namespace {

using Closure = detail::LodClosure;

void checkMask(const Hierarchy& h, const KeepMask& keep) {
  const int J = h.levels();
  if (static_cast<int>(keep.size()) != J)
    throw Error("extractLod: keep mask has " + std::to_string(keep.size()) +
                " levels, the hierarchy " + std::to_string(J));
  for (int j = 0; j < J; ++j) {
    const std::size_t n = static_cast<std::size_t>(h.numVertices(j + 1) - h.numVertices(j));
    if (keep[j].size() != n)
      throw Error("extractLod: keep mask level " + std::to_string(j) + " has " +
                  std::to_string(keep[j].size()) + " flags, expected " + std::to_string(n));
  }
}

void seedCoefficient(const Hierarchy& h, Closure& closure, int j, int e) {
  const auto ab = h.parentEdge(j, e);
  closure.seed(j, ab[0], ab[1]);
}

// The closure of every coefficient `keep` holds.
void closeMask(const Hierarchy& h, const KeepMask& keep, Closure& closure) {
  checkMask(h, keep);
  for (int j = 0; j < h.levels(); ++j)
    for (std::size_t e = 0; e < keep[j].size(); ++e)
      if (keep[j][e]) seedCoefficient(h, closure, j, static_cast<int>(e));
  closure.close();
}

// The mesh of a closed closure.
LodMesh walkClosure(const Hierarchy& h, Closure& closure) {
  // Walk down from the base faces through red faces only, children in order, so the
  // output is in canonical order (everything kept gives faces(J) row for row) and
  // only existing faces are visited.
  LodMesh out;
  std::vector<std::array<int, 3>> tris;
  std::vector<std::pair<int, int>> stack;
  for (int f0 = h.numFaces(0) - 1; f0 >= 0; --f0) stack.emplace_back(0, f0);
  while (!stack.empty()) {
    const auto [j, f] = stack.back();
    stack.pop_back();
    if (closure.isRed(j, f)) {
      for (int k = 3; k >= 0; --k) stack.emplace_back(j + 1, 4 * f + k);
      continue;
    }
    const auto v = h.faces(j).row(f);
    const int i = closure.redEdge(j, f);
    if (i < 0) {
      tris.push_back({v(0), v(1), v(2)});
      out.faceLevel.push_back(j);
      out.faceOrigin.push_back(f);
      ++out.redTriangles;
      continue;
    }
    // Green split of edge i = (v_i, v_{i+1}) at its midpoint, read off the child
    // layout of hierarchy.h: m0 = child 0 corner 1, m1 = child 1 corner 2,
    // m2 = child 0 corner 2. Both halves keep the face's winding.
    const Faces& fine = h.faces(j + 1);
    const int m = i == 0 ? fine(4 * f, 1) : i == 1 ? fine(4 * f + 1, 2) : fine(4 * f, 2);
    const int a = v(i), b = v((i + 1) % 3), o = v((i + 2) % 3);
    tris.push_back({a, m, o});
    tris.push_back({m, b, o});
    out.faceLevel.push_back(j);
    out.faceLevel.push_back(j);
    out.faceOrigin.push_back(f);
    out.faceOrigin.push_back(f);
    out.greenTriangles += 2;
  }

  const int nf = static_cast<int>(tris.size());
  out.faces.resize(nf, 3);
  for (int r = 0; r < nf; ++r)
    for (int k = 0; k < 3; ++k) out.faces(r, k) = tris[r][k];

  // Vertices by marking, not sorting: the marks span the indices used (at most n_J,
  // which the mask already spans), and reading them in order gives them ascending.
  int maxVertex = -1;
  for (const auto& t : tris) maxVertex = std::max({maxVertex, t[0], t[1], t[2]});
  constexpr int kUsed = -2;
  std::vector<int> compact(static_cast<std::size_t>(maxVertex + 1), -1);
  for (const auto& t : tris)
    for (int v : t) compact[v] = kUsed;
  for (int v = 0; v <= maxVertex; ++v)
    if (compact[v] == kUsed) {
      compact[v] = static_cast<int>(out.vertices.size());
      out.vertices.push_back(v);
    }
  out.compactFaces.resize(nf, 3);
  for (int r = 0; r < nf; ++r)
    for (int k = 0; k < 3; ++k) out.compactFaces(r, k) = compact[tris[r][k]];
  return out;
}

// `keep` and the coefficients its closure makes free.
KeepMask withFreeCoefficients(const Hierarchy& h, const KeepMask& keep, const Closure& closure) {
  const int J = h.levels();
  // A coefficient whose edge has every face split already is free: seeding it marks
  // nothing new, so the closure, and with it the mesh, stay the same.
  KeepMask out = keep;
  for (int j = 0; j < J; ++j) {
    bool anyRed = false;
    for (int f = 0; f < h.numFaces(j) && !anyRed; ++f) anyRed = closure.isRed(j, f);
    if (!anyRed) continue;  // no split face at this level: nothing is free
    const Connectivity& c = h.connectivity(j);
    for (std::size_t e = 0; e < out[j].size(); ++e) {
      if (out[j][e]) continue;
      const auto ab = h.parentEdge(j, static_cast<int>(e));
      const int edge = c.findEdge(ab[0], ab[1]);
      const int he = c.edgeHalfedge(edge), tw = c.twin(he);
      out[j][e] = closure.isRed(j, he / 3) && (tw < 0 || closure.isRed(j, tw / 3));
    }
  }
  return out;
}

}  // namespace

LodMesh extractLod(const Hierarchy& h, const KeepMask& keep) {
  Closure closure(h);
  closeMask(h, keep, closure);
  return walkClosure(h, closure);
}

KeepMask saturate(const Hierarchy& h, const KeepMask& keep) {
  Closure closure(h);
  closeMask(h, keep, closure);
  return withFreeCoefficients(h, keep, closure);
}

LodMesh extractSaturated(const Hierarchy& h, const KeepMask& keep, KeepMask& saturated) {
  Closure closure(h);
  closeMask(h, keep, closure);
  saturated = withFreeCoefficients(h, keep, closure);
  return walkClosure(h, closure);
}

std::vector<long long> lodTriangleCounts(const Hierarchy& h,
                                         const std::vector<std::pair<int, int>>& order) {
  const int J = h.levels();
  const int K = static_cast<int>(order.size());
  for (const auto& [j, e] : order)
    if (j < 0 || j >= J || e < 0 || e >= h.numVertices(j + 1) - h.numVertices(j))
      throw Error("lodTriangleCounts: coefficient (" + std::to_string(j) + ", " +
                  std::to_string(e) + ") is not in the hierarchy");
  // When each face turns red as the mask grows: the closure of a larger mask contains
  // that of a smaller one, so growing it one seed at a time and closing after each
  // gives every face the first count at which extractLod would split it.
  Closure closure(h);
  for (int k = 0; k < K; ++k) {
    closure.setTime(k + 1);
    seedCoefficient(h, closure, order[k].first, order[k].second);
    closure.close();
  }
  // Each face then adds to the output over a range of counts: nothing before it
  // exists (its parent turns red), one triangle until a neighbour turns red, two
  // (a green split) from then until it turns red itself, nothing after (its children
  // take over). Rule (iii) makes it red by the time a second neighbour is, so the
  // first red neighbour is all that matters. Steps go into a difference array.
  std::vector<long long> steps(static_cast<std::size_t>(K) + 2, 0);
  auto add = [&](int from, int to, int triangles) {
    if (from >= to || from > K) return;
    steps[from] += triangles;
    steps[std::min(to, K + 1)] -= triangles;
  };
  constexpr int kNever = Closure::kNever;
  for (int j = 0; j <= J; ++j) {
    const Connectivity* c = j < J ? &h.connectivity(j) : nullptr;
    for (int f = 0; f < h.numFaces(j); ++f) {
      const int born = j == 0 ? 0 : closure.redTime(j - 1, f >> 2);
      if (born == kNever) continue;
      const int red = closure.redTime(j, f);
      int green = kNever;
      if (c)
        for (int i = 0; i < 3; ++i) {
          const int t = c->twin(3 * f + i);
          if (t >= 0) green = std::min(green, closure.redTime(j, t / 3));
        }
      const int split = std::max(born, green);
      add(born, std::min(split, red), 1);
      add(split, red, 2);
    }
  }
  std::vector<long long> counts(static_cast<std::size_t>(K) + 1);
  long long running = 0;
  for (int k = 0; k <= K; ++k) counts[k] = running += steps[k];
  return counts;
}

}  // namespace osdmra
