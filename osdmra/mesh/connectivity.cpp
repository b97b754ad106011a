#include "osdmra/mesh/connectivity.h"

#include <algorithm>
#include <memory>
#include <numeric>
#include <utility>

#include "osdmra/base/detail/parallel.h"

namespace osdmra {

namespace {

// One corner of a face as seen from its vertex a: the face is (a, next, prev)
// counter-clockwise.
struct Corner {
  int next, prev;
};

// Orders a vertex's corners counter-clockwise in place (each corner's prev is the
// next of the one after it). Returns 0 for a closed fan, 1 for an open one (it then
// starts at the corner whose next has no corner ending there), -1 when the corners
// do not form a single fan: a repeated neighbour on the same side means a
// non-manifold edge or a face of opposite winding, two starts or a chain that stops
// early mean several fans meeting at the vertex.
int orderFan(Corner* c, int d) {
  // Few corners (the usual case): pairwise scans. Many: sort and search, so a
  // hostile vertex shared by a million faces costs d log d, not d^2.
  constexpr int kSmall = 16;
  if (d <= kSmall) {
    // Each corner's successor (the corner whose next is its prev) and repeats, by
    // full pairwise scans without early exits: d is about 6, and branch-free
    // comparisons beat searches that mispredict.
    int succ[kSmall];
    bool repeated = false;
    for (int i = 0; i < d; ++i) {
      int s = -1;
      for (int j = 0; j < d; ++j) {
        s = c[j].next == c[i].prev ? j : s;
        repeated |= (j > i) & ((c[i].next == c[j].next) | (c[i].prev == c[j].prev));
      }
      succ[i] = s;
    }
    if (repeated) return -1;
    // Without repeats each corner has at most one predecessor; an open fan starts at
    // the one corner without.
    bool hasPred[kSmall] = {};
    for (int i = 0; i < d; ++i)
      if (succ[i] >= 0) hasPred[succ[i]] = true;
    int start = 0, starts = 0;
    for (int i = 0; i < d; ++i)
      if (!hasPred[i]) {
        start = i;
        ++starts;
      }
    if (starts > 1) return -1;
    Corner ordered[kSmall];
    int k = 0;
    for (int i = start; k < d && i >= 0 && (k == 0 || i != start); i = succ[i]) ordered[k++] = c[i];
    if (k != d) return -1;  // the chain misses corners: several fans
    std::copy(ordered, ordered + d, c);
    return starts;
  }
  const Corner first = c[0];
  std::vector<Corner> byNext(c, c + d);
  std::sort(byNext.begin(), byNext.end(),
            [](const Corner& x, const Corner& y) { return x.next < y.next; });
  std::vector<int> prevs(d);
  for (int i = 0; i < d; ++i) prevs[i] = c[i].prev;
  std::sort(prevs.begin(), prevs.end());
  for (int i = 0; i + 1 < d; ++i)
    if (byNext[i].next == byNext[i + 1].next || prevs[i] == prevs[i + 1]) return -1;
  int start = 0, starts = 0;
  for (int i = 0; i < d; ++i)
    if (!std::binary_search(prevs.begin(), prevs.end(), byNext[i].next)) {
      start = i;
      ++starts;
    }
  if (starts > 1) return -1;
  c[0] = starts == 1 ? byNext[start] : first;
  for (int k = 0; k + 1 < d; ++k) {
    const auto it = std::lower_bound(byNext.begin(), byNext.end(), c[k].prev,
                                     [](const Corner& x, int value) { return x.next < value; });
    if (it == byNext.end() || it->next != c[k].prev) return -1;
    c[k + 1] = *it;
  }
  // With no repeats, a chain of d corners from the single start (or from any corner
  // when there is none) uses every corner once and closes by itself.
  return starts;
}

}  // namespace

VertexRings::VertexRings(const Faces& F, int numVertices) : state_(numVertices, kNonManifold) {
  const int numFaces = static_cast<int>(F.rows());
  const int* corner = F.data();  // row-major: corner 3 f + i is F(f, i)
  offset_.assign(numVertices + 1, 0);
  for (int k = 0; k < 3 * numFaces; ++k) ++offset_[corner[k] + 1];
  std::partial_sum(offset_.begin(), offset_.end(), offset_.begin());

  // Corners to their vertices in two cache-friendly passes instead of one scattered
  // write each (the input order may be random): first into blocks of kBlock
  // consecutive vertices, a few hundred write streams at a time, then within each
  // block through a small buffer that stays in cache. Chunks of faces fill each
  // block in face order, so a vertex's corners keep the order of its faces (which
  // fixes where a closed ring starts) whatever the number of threads.
  constexpr int kBlockBits = 12, kBlock = 1 << kBlockBits;
  const int numBlocks = (numVertices + kBlock - 1) / kBlock;
  auto blockBegin = [&](int b) { return offset_[std::min(b * kBlock, numVertices)]; };
  const int faceChunks = numChunks(numFaces);
  std::vector<std::vector<int>> fill(faceChunks, std::vector<int>(numBlocks, 0));
  forChunks(numFaces, faceChunks, [&](int c, int begin, int end) {
    for (int k = 3 * begin; k < 3 * end; ++k) ++fill[c][corner[k] >> kBlockBits];
  });
  for (int b = 0; b < numBlocks; ++b)
    for (int c = 0, at = blockBegin(b); c < faceChunks; ++c) at += std::exchange(fill[c][b], at);
  // Not value-initialised: the first touch of these large arrays (page faults) then
  // happens in the parallel pass that fills them.
  const std::unique_ptr<Corner[]> corners(new Corner[offset_.back()]);
  const std::unique_ptr<std::uint16_t[]> within(new std::uint16_t[offset_.back()]);
  forChunks(numFaces, faceChunks, [&](int c, int begin, int end) {
    std::vector<int>& at = fill[c];
    auto put = [&](int a, Corner value) {
      const int k = at[a >> kBlockBits]++;
      corners[k] = value;
      within[k] = static_cast<std::uint16_t>(a & (kBlock - 1));
    };
    for (int h = 3 * begin; h < 3 * end; h += 3) {
      const int a = corner[h], b = corner[h + 1], cc = corner[h + 2];
      put(a, {b, cc});
      put(b, {cc, a});
      put(cc, {a, b});
    }
  });

  ring_.reset(new int[static_cast<std::size_t>(offset_.back()) + numVertices]);
  const int blockChunks = std::max(1, std::min(numBlocks, numChunks(numVertices)));
  std::vector<int> firstBad(blockChunks, -1), firstIsolated(blockChunks, -1);
  forChunks(numBlocks, blockChunks, [&](int chunk, int blocksBegin, int blocksEnd) {
    std::vector<Corner> block;
    std::vector<int> at(kBlock);
    for (int b = blocksBegin; b < blocksEnd; ++b) {
      const int first = b * kBlock, last = std::min(first + kBlock, numVertices);
      const int base = blockBegin(b);
      block.resize(blockBegin(b + 1) - base);
      for (int v = first; v < last; ++v) at[v - first] = offset_[v] - base;
      for (int k = base, end = blockBegin(b + 1); k < end; ++k) block[at[within[k]]++] = corners[k];
      for (int v = first; v < last; ++v) {
        const int begin = offset_[v], d = offset_[v + 1] - begin;
        if (d == 0) {
          if (firstIsolated[chunk] < 0) firstIsolated[chunk] = v;
          continue;
        }
        Corner* c = block.data() + (begin - base);
        const int kind = orderFan(c, d);
        if (kind < 0) {
          if (firstBad[chunk] < 0) firstBad[chunk] = v;
          continue;
        }
        state_[v] = kind == 1 ? kBoundary : kClosed;
        int* ring = ring_.get() + begin + v;
        for (int k = 0; k < d; ++k) ring[k] = c[k].next;
        if (kind == 1) ring[d] = c[d - 1].prev;
      }
    }
  });
  for (int c = blockChunks - 1; c >= 0; --c) {
    if (firstBad[c] >= 0) firstNonManifoldVertex = firstBad[c];
    if (firstIsolated[c] >= 0) firstIsolatedVertex = firstIsolated[c];
  }
}

IndexSpan VertexRings::ring(int v) const {
  if (state_[v] == kNonManifold) return {};
  const int* first = ring_.get() + offset_[v] + v;
  return {first, first + (offset_[v + 1] - offset_[v]) + (state_[v] == kBoundary ? 1 : 0)};
}

long long VertexRings::numEdgesIfManifold() const {
  long long ends = 0;
  for (int v = 0; v < numVertices(); ++v) ends += valence(v);
  return ends / 2;
}

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
  startRings(numVertices, nh);
  for (int v = 0; v < numVertices; ++v) {
    const int begin = outOffset[v], end = outOffset[v + 1];
    // Start at an outgoing boundary halfedge when there is one: clockwise from it
    // there is nothing, so the counter-clockwise walk covers the whole fan.
    int start = begin < end ? out[begin] : -1, starts = 0;
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
    walkFan(v, start, end - begin, starts);
  }
}

Connectivity::Connectivity(const Faces& F, int numVertices, const FaceEdgeList& faceEdges,
                           int numEdges)
    : F_(F) {
  const int nh = 3 * static_cast<int>(F.rows());
  // Twins paired through the known edges; anything but one halfedge each way (or one
  // alone, a boundary) is left to the general construction.
  twin_.assign(nh, -1);
  std::vector<int> firstOf(numEdges, -1);
  for (int h = 0; h < nh; ++h) {
    int& first = firstOf[faceEdges[h / 3][h % 3]];
    if (first < 0) {
      first = h;
    } else if (twin_[first] >= 0 || from(first) == from(h)) {
      *this = Connectivity(F, numVertices);
      return;
    } else {
      twin_[first] = h;
      twin_[h] = first;
    }
  }
  // Edges numbered in order of first appearance, as the general construction does.
  halfedgeEdge_.assign(nh, -1);
  edgeHalfedge_.reserve(numEdges);
  for (int h = 0; h < nh; ++h)
    if (halfedgeEdge_[h] < 0) {
      halfedgeEdge_[h] = static_cast<int>(edgeHalfedge_.size());
      if (twin_[h] >= 0) halfedgeEdge_[twin_[h]] = halfedgeEdge_[h];
      edgeHalfedge_.push_back(h);
    }
  // Each vertex's first outgoing halfedge, or its (last) outgoing boundary one.
  std::vector<int> start(numVertices, -1), numOut(numVertices, 0), starts(numVertices, 0);
  for (int h = 0; h < nh; ++h) {
    const int v = from(h);
    if (numOut[v]++ == 0 && starts[v] == 0) start[v] = h;
    if (twin_[h] < 0) {
      start[v] = h;
      ++starts[v];
    }
  }
  startRings(numVertices, nh);
  for (int v = 0; v < numVertices; ++v) walkFan(v, start[v], numOut[v], starts[v]);
}

void Connectivity::startRings(int numVertices, int nh) {
  boundaryVertex_.assign(numVertices, 0);
  manifoldVertex_.assign(numVertices, 1);
  ringOffset_.assign(numVertices + 1, 0);
  fanOffset_.assign(numVertices + 1, 0);
  ringVerts_.reserve(nh + nh / 8);
  fanHalfedges_.reserve(nh);
}

// Vertex v's fan walked counter-clockwise from `start` (h -> twin(prev(h))) over its
// `numOut` outgoing halfedges, `starts` of them on a boundary; the vertex is
// non-manifold (no ring) unless the walk covers them all as one fan. Vertices are
// walked in order: v's ring ends the rings so far.
void Connectivity::walkFan(int v, int start, int numOut, int starts) {
  if (numOut == 0) {
    if (firstIsolatedVertex < 0) firstIsolatedVertex = v;
    manifoldVertex_[v] = 0;
  } else {
    const std::size_t ringBegin = ringVerts_.size(), fanBegin = fanHalfedges_.size();
    int h = start, steps = 0;
    bool closed = false;
    while (steps <= numOut) {
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
    const bool manifold = steps == numOut && starts <= 1 && (closed == (starts == 0));
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
