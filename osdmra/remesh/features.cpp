#include "osdmra/remesh/features.h"

#include <array>
#include <cmath>

#include "osdmra/geometry/normals.h"
#include "osdmra/mesh/connectivity.h"
#include "osdmra/remesh/planar.h"

namespace osdmra::remeshing {

namespace {

// Folds of a scan: triangles facing against their own corners' area-weighted normals.
// Their edges look like the sharpest creases and their corners like the sharpest
// points of the surface; they are noise: no feature, and removed first at any
// distortion (else a fold survives as a base face, and every grid triangle in it
// comes out flipped).
std::vector<char> findFoldFaces(const TriMesh& m, const std::vector<Vec3>& faceNormals) {
  const Points vertexNormals = vertexNormalSums(m);
  std::vector<char> foldFace(m.F.rows(), 0);
  for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
    Vec3 r = Vec3::Zero();
    for (int k = 0; k < 3; ++k) r += vertexNormals.row(m.F(f, k)).transpose();
    foldFace[f] = facesAgainst(faceNormals[f], r);
  }
  return foldFace;
}

// The surface on one side of an edge (halfedge e): the unit normal of e's face and its
// neighbours across its other two edges, weighted by area. A sliver (decimated scans
// have many) turns its normal by tens of degrees when a corner moves by a small
// fraction of an edge: next to its neighbours it weighs little, and an edge is a
// feature only where the two sides meet at the angle too. (The camel head decimated to
// 3,000 faces and moved by noise of a twentieth of an edge had 39 feature edges, nearly
// all such, and kept 200 base faces of the 150 asked; now 4, and 150.)
Vec3 sideNormal(const Connectivity& c, const std::vector<Vec3>& faceNormals,
                const std::vector<char>& foldFace, int e, double cosLimit) {
  const Vec3 own = faceNormals[e / 3].normalized();
  const Vec3 other = faceNormals[c.twin(e) / 3].normalized();
  Vec3 sum = faceNormals[e / 3];
  for (int g : {Connectivity::next(e), Connectivity::prev(e)}) {
    const int t = c.twin(g);
    if (t < 0 || foldFace[t / 3]) continue;
    // A neighbour at the angle from both sides is a third side: across a cube's edge
    // from a triangle in its corner, which would otherwise tilt both sides towards it.
    // (A sliver's neighbours, at the angle from the sliver only, are its side's.)
    const Vec3 across = faceNormals[t / 3].normalized();
    if (own.dot(across) < cosLimit && other.dot(across) < cosLimit) continue;
    sum += faceNormals[t / 3];
  }
  return sum.normalized();
}

std::vector<std::vector<int>> adjacency(const std::unordered_set<std::uint64_t>& edges, int n) {
  std::vector<std::vector<int>> adj(n);
  for (std::uint64_t k : edges) {
    const int a = static_cast<int>(k >> 32), b = static_cast<int>(k & 0xffffffffu);
    adj[a].push_back(b);
    adj[b].push_back(a);
  }
  return adj;
}

double lineLength(const Points& V, const std::vector<int>& line) {
  double length = 0;
  for (std::size_t i = 0; i + 1 < line.size(); ++i)
    length += (V.row(line[i + 1]) - V.row(line[i])).norm();
  return length;
}

// A feature must be a chain of at least kMinChain edges between its ends (vertices
// with other than two feature edges), or a closed loop; the rest are dropped, so that
// they neither pin vertices in the base mesh nor bend the parameterisation. A line on
// its own (both ends free, or closed) shorter than `minLength` is dropped too: a base of
// the size asked could follow it only with base vertices closer together than its own
// edges (two at its ends, three around a loop).
std::unordered_set<std::uint64_t> pruneShortChains(const Points& V,
                                                   const std::unordered_set<std::uint64_t>& edges,
                                                   double minLength) {
  const int n = static_cast<int>(V.rows());
  const std::vector<std::vector<int>> adj = adjacency(edges, n);
  std::unordered_set<std::uint64_t> seen, keep;
  auto take = [&](const std::vector<int>& line, bool kept) {
    for (std::size_t i = 0; i + 1 < line.size(); ++i) {
      seen.insert(edgeKey(line[i], line[i + 1]));
      if (kept) keep.insert(edgeKey(line[i], line[i + 1]));
    }
  };
  for (int v = 0; v < n; ++v) {
    if (adj[v].empty() || adj[v].size() == 2) continue;  // chains start at their ends
    for (int w : adj[v]) {
      if (seen.count(edgeKey(v, w))) continue;
      const std::vector<int> chain = followLine(adj, v, w, [](int) { return false; });
      const bool alone = adj[v].size() == 1 && adj[chain.back()].size() == 1;
      take(chain, static_cast<int>(chain.size()) - 1 >= kMinChain &&
                      !(alone && lineLength(V, chain) < minLength));
    }
  }
  for (int v = 0; v < n; ++v)  // closed loops: every vertex has two
    for (int w : adj[v])
      if (!seen.count(edgeKey(v, w))) {
        const std::vector<int> loop = followLine(adj, v, w, [](int) { return false; });
        take(loop, lineLength(V, loop) >= minLength);
      }
  return keep;
}

// The vertices from v along the line (`along`) through `next`: at least two edges and at
// least `span` long, or up to where the line ends or comes back to v.
std::vector<int> walkAlong(const Points& V, const std::vector<std::vector<int>>& along, int v,
                           int next, double span) {
  std::vector<int> path{v, next};
  double length = (V.row(next) - V.row(v)).norm();
  while ((path.size() < 3 || length < span) && next != v && along[next].size() == 2) {
    const int from = path[path.size() - 2];
    const int after = along[next][0] == from ? along[next][1] : along[next][0];
    length += (V.row(after) - V.row(next)).norm();
    path.push_back(next = after);
  }
  return path;
}

// Edges along the line from v through `next`, up to 2 kMinChain.
int lineEdges(const std::vector<std::vector<int>>& along, int v, int next) {
  int count = 1, from = v;
  while (count < 2 * kMinChain && along[next].size() == 2 && next != v) {
    const int after = along[next][0] == from ? along[next][1] : along[next][0];
    from = next;
    next = after;
    ++count;
  }
  return count;
}

// Marks as corners the vertices where a line (its edges: `along`, two per vertex on
// the line) turns by more than kMaxTurn, measured between the points `span` away along
// the line on either side (two edges at least, so that the zig-zag of a scanned crease
// or rim is not a corner). With `onePerBend`, only the vertex that turns most within
// that reach: one bend makes one corner. A kink on a short line is noise.
void markCorners(const Points& V, const std::vector<std::vector<int>>& along, double span,
                 bool onePerBend, std::vector<char>& corner) {
  const int n = static_cast<int>(along.size());
  std::vector<double> turn(n, -1);
  std::vector<std::array<std::vector<int>, 2>> reach(n);
  for (int v = 0; v < n; ++v) {
    if (along[v].size() != 2) continue;
    auto& [left, right] = reach[v];
    left = walkAlong(V, along, v, along[v][0], span);
    right = walkAlong(V, along, v, along[v][1], span);
    if (left.back() == v) {  // a closed line shorter than two spans: a third each way
      const std::size_t third = (left.size() - 1) / 3;
      if (third < 2) continue;
      left.resize(third + 1);
      right.resize(third + 1);
    }
    if (lineEdges(along, v, along[v][0]) + lineEdges(along, v, along[v][1]) < 2 * kMinChain)
      continue;
    const Vec3 a = (V.row(v) - V.row(left.back())).transpose().normalized(),
               b = (V.row(right.back()) - V.row(v)).transpose().normalized();
    turn[v] = angleBetween(a, b) * 180.0 / kPi;
  }
  for (int v = 0; v < n; ++v) {
    if (!(turn[v] > kMaxTurn)) continue;
    bool most = true;
    if (onePerBend)
      for (const std::vector<int>& side : reach[v])
        for (int w : side)
          most = most && (w == v || turn[w] < turn[v] || (turn[w] == turn[v] && w > v));
    if (most) corner[v] = 1;
  }
}

// Interior vertices whose face angles sum to under kMaxTipAngle (a vertex of no face is
// none).
std::vector<char> findTips(const TriMesh& m, const Connectivity& c) {
  const int n = static_cast<int>(m.V.rows());
  std::vector<double> angle(n, 0.0);
  std::vector<char> rim(n, 0), used(n, 0);
  for (int h = 0; h < 3 * c.numFaces(); ++h) {
    const int v = c.from(h);
    used[v] = 1;
    if (c.twin(h) < 0) rim[v] = rim[c.to(h)] = 1;
    angle[v] += faceAngle(m, h / 3, h % 3);
  }
  std::vector<char> tip(n, 0);
  for (int v = 0; v < n; ++v) tip[v] = used[v] && !rim[v] && angle[v] < kMaxTipAngle * kPi / 180.0;
  return tip;
}

// The corners of fold faces, but for a tip of which fewer than half the faces are
// folds: a spike's faces face sideways of the surface around it, so one of them can
// look turned over (the decimated knight's ears, whose tips went first as noise and
// were cut off: 1.49% of the diagonal from the input over 150 faces at J = 5). A
// crumple of a scan, whose vertices have small angle sums too, folds most of their faces.
std::vector<char> foldVertices(const TriMesh& m, const std::vector<char>& foldFace,
                               const std::vector<char>& tip) {
  const int n = static_cast<int>(m.V.rows());
  std::vector<int> faces(n, 0), folded(n, 0);
  for (Eigen::Index f = 0; f < m.F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      ++faces[m.F(f, k)];
      folded[m.F(f, k)] += foldFace[f];
    }
  std::vector<char> fold(n, 0);
  for (int v = 0; v < n; ++v) fold[v] = folded[v] > 0 && (!tip[v] || 2 * folded[v] >= faces[v]);
  return fold;
}

}  // namespace

bool facesAgainst(const Vec3& faceNormal, const Vec3& cornerNormals) {
  return faceNormal.dot(cornerNormals) <= 0;
}

std::vector<char> foldCorners(const TriMesh& m, const Connectivity& c) {
  std::vector<Vec3> faceNormals(m.F.rows());
  for (Eigen::Index f = 0; f < m.F.rows(); ++f) faceNormals[f] = faceNormal(m, f);
  return foldVertices(m, findFoldFaces(m, faceNormals), findTips(m, c));
}

LineNeighbours lineNeighbours(const Connectivity& c,
                              const std::vector<std::array<int, 2>>& featureEdges) {
  LineNeighbours out;
  out.boundary.resize(c.numVertices());
  out.feature.resize(c.numVertices());
  for (const auto& [a, b] : featureEdges) {
    out.feature[a].push_back(b);
    out.feature[b].push_back(a);
  }
  for (int e = 0; e < c.numEdges(); ++e)
    if (c.isBoundaryEdge(e)) {
      const auto [a, b] = c.edgeVertices(e);
      out.boundary[a].push_back(b);
      out.boundary[b].push_back(a);
    }
  return out;
}

Features detectFeatures(const TriMesh& m, double featureAngle, double boundarySpan,
                        double minLineLength) {
  const int n = static_cast<int>(m.V.rows());
  Features out;
  std::vector<Vec3> faceNormals(m.F.rows());
  for (Eigen::Index f = 0; f < m.F.rows(); ++f) faceNormals[f] = faceNormal(m, f);
  const std::vector<char> foldFace = findFoldFaces(m, faceNormals);
  const Connectivity c(m.F, n);
  out.tip = findTips(m, c);
  out.fold = foldVertices(m, foldFace, out.tip);
  for (int v = 0; v < n; ++v) out.tip[v] = out.tip[v] && !out.fold[v];
  // Feature edges: the angle between the normals of their two faces.
  const double cosLimit = std::cos(featureAngle * kPi / 180.0);
  std::unordered_set<std::uint64_t> sharp;
  for (int h = 0; h < 3 * c.numFaces(); ++h) {
    const int t = c.twin(h);
    if (t < h || foldFace[h / 3] || foldFace[t / 3]) continue;
    const double across = faceNormals[h / 3].normalized().dot(faceNormals[t / 3].normalized());
    if (!(across < cosLimit)) continue;  // a zero-area face makes no feature
    const double sides = sideNormal(c, faceNormals, foldFace, h, cosLimit)
                             .dot(sideNormal(c, faceNormals, foldFace, t, cosLimit));
    if (!(sides < cosLimit)) continue;
    sharp.insert(edgeKey(c.from(h), c.to(h)));
  }
  out.edges = pruneShortChains(m.V, sharp, minLineLength);
  for (std::uint64_t k : out.edges)
    out.list.push_back({static_cast<int>(k >> 32), static_cast<int>(k & 0xffffffffu)});
  // Corners of feature lines: where a line turns sharply (the fandisk's creases meet at
  // such kinks), the vertex stays, like a vertex where lines meet; likewise where a
  // boundary turns sharply (a base edge cutting that corner would leave slivers of base
  // faces fanned into it). A feature line is the model's own (sharp edges in chains),
  // and its kinks count at any scale; a boundary is where a scan's data ends, ragged at
  // every scale below the base's: its bends count from `boundarySpan` up, one corner each.
  // (Measured over docs/REMESH.md's corpus: the bunny's five holes made 58 corners, a
  // third of a 150-face base; spanning feature lines too took fandisk's 30 corners to 12
  // and raised its distance to the input.)
  out.corner.assign(n, 0);
  markCorners(m.V, adjacency(out.edges, n), 0.0, false, out.corner);
  std::vector<std::vector<int>> rim(n);
  for (int h = 0; h < 3 * c.numFaces(); ++h)
    if (c.twin(h) < 0) {
      rim[c.from(h)].push_back(c.to(h));
      rim[c.to(h)].push_back(c.from(h));
    }
  markCorners(m.V, rim, boundarySpan, true, out.corner);
  // Tips stay from the start. Left among the candidates, to be refused one by one as too
  // curved, their angle defects (the largest of the mesh) set the scale of every other
  // vertex's curvature in the order of removal, and the curvature counted for little
  // (the knight over 150 faces at J = 5: 0.72% of the diagonal from the input so, 0.44%
  // with its 23 tips kept as corners).
  for (int v = 0; v < n; ++v) out.corner[v] = out.corner[v] || out.tip[v];
  return out;
}

}  // namespace osdmra::remeshing
