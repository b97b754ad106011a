#include "osdmra/remesh/features.h"

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
    foldFace[f] = faceNormals[f].dot(r) <= 0;
  }
  return foldFace;
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

// A feature must be a chain of at least kMinChain edges between its ends (vertices
// with other than two feature edges), or a closed loop; the rest are dropped, so that
// they neither pin vertices in the base mesh nor bend the parameterisation.
std::unordered_set<std::uint64_t> pruneShortChains(const std::unordered_set<std::uint64_t>& edges,
                                                   int n) {
  const std::vector<std::vector<int>> adj = adjacency(edges, n);
  std::unordered_set<std::uint64_t> seen, keep;
  for (int v = 0; v < n; ++v) {
    if (adj[v].empty() || adj[v].size() == 2) continue;  // chains start at their ends
    for (int w : adj[v]) {
      if (seen.count(edgeKey(v, w))) continue;
      const std::vector<int> chain = followLine(adj, v, w, [](int) { return false; });
      const bool kept = static_cast<int>(chain.size()) - 1 >= kMinChain;
      for (std::size_t i = 0; i + 1 < chain.size(); ++i) {
        seen.insert(edgeKey(chain[i], chain[i + 1]));
        if (kept) keep.insert(edgeKey(chain[i], chain[i + 1]));
      }
    }
  }
  for (std::uint64_t k : edges)  // closed loops: every vertex has two
    if (!seen.count(k)) keep.insert(k);
  return keep;
}

// Marks as corners the vertices where a line (its edges: `along`, two per vertex on
// the line) turns by more than kMaxTurn. The turn is measured between points two edges
// away along the line, so that the zig-zag of a scanned crease or rim is not a corner;
// and a kink on a short line is noise.
void markCorners(const Points& V, const std::vector<std::vector<int>>& along,
                 std::vector<char>& corner) {
  auto ahead = [&](int from, int next) {
    if (along[next].size() == 2) {
      const int after = along[next][0] == from ? along[next][1] : along[next][0];
      if (after != from) return after;
    }
    return next;
  };
  // Edges along the line from v through `next`, up to `cap`.
  auto length = [&](int v, int next, int cap) {
    int count = 1, from = v;
    while (count < cap && along[next].size() == 2 && next != v) {
      const int after = along[next][0] == from ? along[next][1] : along[next][0];
      from = next;
      next = after;
      ++count;
    }
    return count;
  };
  const double cosTurn = std::cos(kMaxTurn * kPi / 180.0);
  for (int v = 0; v < static_cast<int>(along.size()); ++v) {
    if (along[v].size() != 2 ||
        length(v, along[v][0], 2 * kMinChain) + length(v, along[v][1], 2 * kMinChain) <
            2 * kMinChain)
      continue;
    const int p = ahead(v, along[v][0]), q = ahead(v, along[v][1]);
    const Vec3 a = (V.row(v) - V.row(p)).transpose().normalized(),
               b = (V.row(q) - V.row(v)).transpose().normalized();
    if (a.dot(b) < cosTurn) corner[v] = 1;
  }
}

}  // namespace

Features detectFeatures(const TriMesh& m, double featureAngle) {
  const int n = static_cast<int>(m.V.rows());
  Features out;
  std::vector<Vec3> faceNormals(m.F.rows());
  for (Eigen::Index f = 0; f < m.F.rows(); ++f) faceNormals[f] = faceNormal(m, f);
  const std::vector<char> foldFace = findFoldFaces(m, faceNormals);
  out.fold.assign(n, 0);
  for (Eigen::Index f = 0; f < m.F.rows(); ++f)
    if (foldFace[f])
      for (int k = 0; k < 3; ++k) out.fold[m.F(f, k)] = 1;
  // Feature edges: the angle between the normals of their two faces.
  const Connectivity c(m.F, n);
  const double cosLimit = std::cos(featureAngle * kPi / 180.0);
  std::unordered_set<std::uint64_t> sharp;
  for (int h = 0; h < 3 * c.numFaces(); ++h) {
    const int t = c.twin(h);
    if (t < h || foldFace[h / 3] || foldFace[t / 3]) continue;
    if (faceNormals[h / 3].normalized().dot(faceNormals[t / 3].normalized()) < cosLimit)
      sharp.insert(edgeKey(c.from(h), c.to(h)));
  }
  out.edges = pruneShortChains(sharp, n);
  for (std::uint64_t k : out.edges)
    out.list.push_back({static_cast<int>(k >> 32), static_cast<int>(k & 0xffffffffu)});
  // Corners of feature lines: where a line turns sharply (the fandisk's creases meet at
  // such kinks), the vertex stays, like a vertex where lines meet; likewise where a
  // boundary turns sharply (a base edge cutting that corner would leave slivers of base
  // faces fanned into it).
  out.corner.assign(n, 0);
  markCorners(m.V, adjacency(out.edges, n), out.corner);
  std::vector<std::vector<int>> rim(n);
  for (int h = 0; h < 3 * c.numFaces(); ++h)
    if (c.twin(h) < 0) {
      rim[c.from(h)].push_back(c.to(h));
      rim[c.to(h)].push_back(c.from(h));
    }
  markCorners(m.V, rim, out.corner);
  return out;
}

}  // namespace osdmra::remeshing
