#include "osdmra/connectivity.h"

#include <algorithm>
#include <numeric>

namespace osdmra {

Connectivity::Connectivity(const Faces& F, int numVertices) : F_(F) {
  const int nh = 3 * static_cast<int>(F.rows());
  // Outgoing halfedges per vertex (CSR), so twins are found by a scan of one
  // vertex's few halfedges: linear time without hashing.
  std::vector<int> outOffset(numVertices + 1, 0);
  for (int h = 0; h < nh; ++h) ++outOffset[from(h) + 1];
  std::partial_sum(outOffset.begin(), outOffset.end(), outOffset.begin());
  std::vector<int> out(nh), fill(outOffset.begin(), outOffset.end() - 1);
  for (int h = 0; h < nh; ++h) out[fill[from(h)]++] = h;

  // Targets beside the halfedge ids: the scans below read one contiguous array
  // instead of chasing each halfedge into the face list.
  std::vector<int> outTo(nh);
  for (int k = 0; k < nh; ++k) outTo[k] = to(out[k]);

  twin_.assign(nh, -1);
  halfedgeEdge_.assign(nh, -1);
  edgeHalfedge_.reserve(nh / 2 + 1);
  for (int h = 0; h < nh; ++h) {
    if (halfedgeEdge_[h] >= 0) continue;
    const int a = from(h), b = to(h);
    // Halfedges a->b and b->a; a manifold, consistently oriented edge has one each.
    int same[2], opp[2], sameDir = 0, numOpposite = 0;
    for (int k = outOffset[a]; k < outOffset[a + 1]; ++k)
      if (outTo[k] == b && sameDir++ < 2) same[sameDir - 1] = out[k];
    for (int k = outOffset[b]; k < outOffset[b + 1]; ++k)
      if (outTo[k] == a && numOpposite++ < 2) opp[numOpposite - 1] = out[k];
    const int e = static_cast<int>(edgeHalfedge_.size());
    edgeHalfedge_.push_back(h);
    if (sameDir + numOpposite > 2) {
      if (firstNonManifoldEdgeFace < 0) firstNonManifoldEdgeFace = h / 3;
      // Tag every halfedge on {a,b} with this edge; pair none of them.
      for (int k = outOffset[a]; k < outOffset[a + 1]; ++k)
        if (outTo[k] == b) halfedgeEdge_[out[k]] = e;
      for (int k = outOffset[b]; k < outOffset[b + 1]; ++k)
        if (outTo[k] == a) halfedgeEdge_[out[k]] = e;
      continue;
    }
    if (sameDir == 2 && firstFlippedFace < 0) firstFlippedFace = h / 3;
    for (int i = 0; i < sameDir; ++i) halfedgeEdge_[same[i]] = e;
    for (int i = 0; i < numOpposite; ++i) halfedgeEdge_[opp[i]] = e;
    if (sameDir == 1 && numOpposite == 1) {
      twin_[h] = opp[0];
      twin_[opp[0]] = h;
    }
  }

  // Rings: walk each vertex's fan counter-clockwise, h -> twin(prev(h)).
  boundaryVertex_.assign(numVertices, 0);
  manifoldVertex_.assign(numVertices, 1);
  ringOffset_.assign(numVertices + 1, 0);
  fanOffset_.assign(numVertices + 1, 0);
  ringVerts_.reserve(nh + nh / 8);
  fanHalfedges_.reserve(nh);
  for (int v = 0; v < numVertices; ++v) {
    const int begin = outOffset[v], end = outOffset[v + 1];
    if (begin == end) {
      if (firstIsolatedVertex < 0) firstIsolatedVertex = v;
      manifoldVertex_[v] = 0;
    } else {
      // Start at an outgoing boundary halfedge when there is one: clockwise from it
      // there is nothing, so the counter-clockwise walk covers the whole fan.
      int start = out[begin], starts = 0;
      for (int k = begin; k < end; ++k)
        if (twin_[out[k]] < 0 && halfedgeEdge_[out[k]] >= 0) {
          // A boundary edge only if no halfedge of the same edge runs the other way.
          const int hh = out[k];
          bool paired = false;
          for (int q = outOffset[outTo[k]]; q < outOffset[outTo[k] + 1]; ++q)
            if (outTo[q] == v) paired = true;
          if (!paired) {
            start = hh;
            ++starts;
          }
        }
      const std::size_t ringBegin = ringVerts_.size(), fanBegin = fanHalfedges_.size();
      int h = start, steps = 0;
      bool closed = false;
      while (steps <= end - begin) {
        fanHalfedges_.push_back(h);
        ringVerts_.push_back(to(h));
        ++steps;
        const int p = twin_[prev(h)];
        if (p < 0) {
          ringVerts_.push_back(from(prev(h)));
          break;
        }
        if (p == start) {
          closed = true;
          break;
        }
        h = p;
      }
      const bool manifold = steps == end - begin && starts <= 1 && (closed == (starts == 0));
      if (!manifold) {
        manifoldVertex_[v] = 0;
        if (firstNonManifoldVertex < 0) firstNonManifoldVertex = v;
        ringVerts_.resize(ringBegin);
        fanHalfedges_.resize(fanBegin);
      } else {
        boundaryVertex_[v] = closed ? 0 : 1;
      }
    }
    ringOffset_[v + 1] = static_cast<int>(ringVerts_.size());
    fanOffset_[v + 1] = static_cast<int>(fanHalfedges_.size());
  }
}

std::array<int, 2> Connectivity::edgeVertices(int e) const {
  const int h = edgeHalfedge_[e];
  return {from(h), to(h)};
}

int Connectivity::findEdge(int a, int b) const {
  for (int h : fan(a))
    if (to(h) == b) return halfedgeEdge_[h];
  for (int h : fan(b))
    if (to(h) == a) return halfedgeEdge_[h];
  return -1;
}

IndexSpan Connectivity::ring(int v) const {
  return {ringVerts_.data() + ringOffset_[v], ringVerts_.data() + ringOffset_[v + 1]};
}

IndexSpan Connectivity::fan(int v) const {
  return {fanHalfedges_.data() + fanOffset_[v], fanHalfedges_.data() + fanOffset_[v + 1]};
}

int Connectivity::numBoundaryLoops() const {
  // Follow boundary halfedges: the next boundary halfedge after h (face on the
  // left) leaves to(h); it is the first outgoing halfedge of that vertex's fan.
  std::vector<std::uint8_t> seen(twin_.size(), 0);
  int loops = 0;
  for (std::size_t h0 = 0; h0 < twin_.size(); ++h0) {
    if (twin_[h0] >= 0 || seen[h0] || halfedgeEdge_[h0] < 0) continue;
    ++loops;
    int h = static_cast<int>(h0);
    while (!seen[h]) {
      seen[h] = 1;
      const int v = to(h);
      if (!isManifoldVertex(v) || fan(v).size() == 0) break;
      h = fan(v)[0];
      if (twin_[h] >= 0) break;
    }
  }
  return loops;
}

int Connectivity::numComponents() const {
  std::vector<int> parent(numVertices());
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (int f = 0; f < numFaces(); ++f)
    for (int i = 1; i < 3; ++i) parent[find(F_(f, i))] = find(F_(f, 0));
  int count = 0;
  for (int v = 0; v < numVertices(); ++v)
    if (find(v) == v && ringOffset_[v + 1] > ringOffset_[v]) ++count;
  return count;
}

int Connectivity::eulerCharacteristic() const {
  int used = 0;
  for (int v = 0; v < numVertices(); ++v)
    if (fanOffset_[v + 1] > fanOffset_[v]) ++used;
  return used - numEdges() + numFaces();
}

}  // namespace osdmra
