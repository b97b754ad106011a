#include "osdmra/mesh/mesh.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <string>
#include <utility>
#include <vector>

#include "osdmra/base/error.h"
#include "osdmra/mesh/connectivity.h"
#include "osdmra/mesh/detail/edges.h"

namespace osdmra {
namespace {

std::string str(long long i) {
  return std::to_string(i);
}

/// Shortest round-trip decimal: "nan", "inf", "0.1" (not "0.100000").
std::string real(double x) {
  char digits[32];
  const auto r = std::to_chars(digits, digits + sizeof digits, x);
  return std::string(digits, r.ptr);
}

/// "face 7 (0, 1, 4)": naming the vertices lets a user find the face in a viewer.
std::string faceText(const Faces& F, int f) {
  return "face " + str(f) + " (" + str(F(f, 0)) + ", " + str(F(f, 1)) + ", " + str(F(f, 2)) + ")";
}

/// Halfedges grouped by undirected edge; built only on the error paths, where
/// messages need every face on an edge.
class EdgeHalfedges {
 public:
  explicit EdgeHalfedges(const Connectivity& conn)
      : offset_(static_cast<std::size_t>(conn.numEdges()) + 1, 0) {
    const int nh = 3 * conn.numFaces();
    for (int h = 0; h < nh; ++h) ++offset_[conn.edge(h) + 1];
    std::partial_sum(offset_.begin(), offset_.end(), offset_.begin());
    halfedges_.resize(static_cast<std::size_t>(nh));
    std::vector<int> fill(offset_.begin(), offset_.end() - 1);
    for (int h = 0; h < nh; ++h) halfedges_[fill[conn.edge(h)]++] = h;
  }
  std::vector<int> of(int e) const {
    return {halfedges_.begin() + offset_[e], halfedges_.begin() + offset_[e + 1]};
  }

 private:
  std::vector<int> offset_, halfedges_;
};

/// The halfedge other than h on h's edge that runs the same way, or -1.
int sameWay(const Connectivity& conn, const EdgeHalfedges& byEdge, int h) {
  for (int g : byEdge.of(conn.edge(h)))
    if (g != h && conn.from(g) == conn.from(h)) return g;
  return -1;
}

/// How many of face f's edges run the same way as a neighbour's edge.
int disagreements(const Connectivity& conn, const EdgeHalfedges& byEdge, int f) {
  int n = 0;
  for (int i = 0; i < 3; ++i) n += sameWay(conn, byEdge, 3 * f + i) >= 0 ? 1 : 0;
  return n;
}

bool sameVertices(const Faces& F, int f, int g) {
  std::array<int, 3> a{F(f, 0), F(f, 1), F(f, 2)}, b{F(g, 0), F(g, 1), F(g, 2)};
  std::sort(a.begin(), a.end());
  std::sort(b.begin(), b.end());
  return a == b;
}

std::string duplicateMessage(const Faces& F, int f, int g) {
  return faceText(F, g) + " duplicates " + faceText(F, f) + "; remove the duplicate face";
}

std::string nonManifoldEdgeMessage(const Connectivity& conn, int f) {
  const EdgeHalfedges byEdge(conn);
  for (int i = 0; i < 3; ++i) {
    const std::vector<int> hs = byEdge.of(conn.edge(3 * f + i));
    if (hs.size() <= 2) continue;
    // A duplicated face is the usual cause of a third face on an edge: say so.
    for (std::size_t p = 0; p < hs.size(); ++p)
      for (std::size_t q = p + 1; q < hs.size(); ++q)
        if (sameVertices(conn.faces(), hs[p] / 3, hs[q] / 3))
          return duplicateMessage(conn.faces(), hs[p] / 3, hs[q] / 3);
    const int a = conn.from(3 * f + i), b = conn.to(3 * f + i);
    std::string faces;
    for (int h : hs)
      faces += (faces.empty() ? "" : ", ") + str(h / 3) + " (" + str(conn.from(h)) + "->" +
               str(conn.to(h)) + ")";
    return faceText(conn.faces(), f) + ": edge (" + str(a) + ", " + str(b) + ") is shared by " +
           str(static_cast<long long>(hs.size())) + " faces [" + faces +
           "]; a non-manifold edge (osdmra needs at most two faces per edge)";
  }
  return faceText(conn.faces(), f) + " has a non-manifold edge";  // not reached
}

std::string flippedFaceMessage(const Connectivity& conn, int f) {
  const Faces& F = conn.faces();
  const EdgeHalfedges byEdge(conn);
  for (int i = 0; i < 3; ++i) {
    const int h = 3 * f + i, other = sameWay(conn, byEdge, h);
    if (other < 0) continue;
    const int g = other / 3;
    const std::string edge = str(conn.from(h)) + "->" + str(conn.to(h));
    if (sameVertices(F, f, g)) return duplicateMessage(F, f, g);
    // A single flipped face in an otherwise consistent mesh disagrees with all of
    // its neighbours, the neighbour only on the shared edge: name the likely one.
    const int df = disagreements(conn, byEdge, f), dg = disagreements(conn, byEdge, g);
    const int culprit = df > dg ? f : g, neighbour = culprit == f ? g : f;
    const int dc = std::max(df, dg);
    std::string message = faceText(F, culprit) + " is oriented inconsistently with " +
                          faceText(F, neighbour) + ": both run edge " + edge +
                          " the same way, so the faces cannot share a consistent outside";
    if (df != dg)
      message += "; " + str(dc) + " of face " + str(culprit) +
                 "'s 3 edges disagree with neighbours, so reverse its winding";
    else
      message += "; reverse one of them (or the surface is not orientable, like a Moebius strip)";
    return message;
  }
  return faceText(F, f) + " is oriented inconsistently";  // not reached
}

// `faces` (all of v's) grouped into fans: two faces are in one fan if they share an
// edge at v (with `cutCrowded`, an edge of two faces only). A manifold vertex has
// exactly one fan. Fans in the order of their first face
// in `faces`, each in that order too.
std::vector<std::vector<int>> fansAround(const Faces& F, const std::vector<int>& faces, int v,
                                         bool cutCrowded = false) {
  std::vector<int> parent(faces.size());
  std::iota(parent.begin(), parent.end(), 0);
  const auto find = [&](int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  // (neighbour, face) pairs sorted by neighbour: faces listing the same neighbour
  // w share the edge {v, w}. Sorting keeps this O(k log k) for a k-face vertex.
  std::vector<std::pair<int, int>> byNeighbour;
  for (std::size_t i = 0; i < faces.size(); ++i)
    for (int a = 0; a < 3; ++a)
      if (F(faces[i], a) != v) byNeighbour.emplace_back(F(faces[i], a), static_cast<int>(i));
  std::sort(byNeighbour.begin(), byNeighbour.end());
  for (std::size_t k = 0; k < byNeighbour.size();) {
    std::size_t end = k + 1;
    while (end < byNeighbour.size() && byNeighbour[end].first == byNeighbour[k].first) ++end;
    for (std::size_t i = k + 1; i < end && !(cutCrowded && end - k > 2); ++i) {
      // The earlier face stays the root, so fans come out in the order of `faces`.
      const int a = find(byNeighbour[i].second), b = find(byNeighbour[i - 1].second);
      parent[std::max(a, b)] = std::min(a, b);
    }
    k = end;
  }
  std::vector<std::vector<int>> fans;
  std::vector<int> fanOf(faces.size(), -1);
  for (std::size_t i = 0; i < faces.size(); ++i) {
    const int root = find(static_cast<int>(i));
    if (fanOf[root] < 0) {
      fanOf[root] = static_cast<int>(fans.size());
      fans.emplace_back();
    }
    fans[fanOf[root]].push_back(faces[i]);
  }
  return fans;
}

// Every fan of each listed vertex but its first gets a copy of the vertex (at the same
// position, with the same normal). Returns how many copies were made.
int detachFans(TriMesh& mesh, const std::vector<int>& vertices, bool cutCrowded) {
  const int nv = static_cast<int>(mesh.V.rows());
  // The faces of each listed vertex, in one pass over the faces.
  std::vector<int> slot(static_cast<std::size_t>(nv), -1);
  for (std::size_t i = 0; i < vertices.size(); ++i) slot[vertices[i]] = static_cast<int>(i);
  std::vector<std::vector<int>> faces(vertices.size());
  for (int f = 0; f < static_cast<int>(mesh.F.rows()); ++f)
    for (int k = 0; k < 3; ++k)
      if (slot[mesh.F(f, k)] >= 0) faces[slot[mesh.F(f, k)]].push_back(f);
  std::vector<std::pair<int, std::vector<int>>> copies;  // (vertex, faces of the copy)
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    std::vector<std::vector<int>> fans = fansAround(mesh.F, faces[i], vertices[i], cutCrowded);
    for (std::size_t k = 1; k < fans.size(); ++k)
      copies.emplace_back(vertices[i], std::move(fans[k]));
  }
  const bool normals = mesh.N.rows() == nv;
  mesh.V.conservativeResize(nv + static_cast<Eigen::Index>(copies.size()), 3);
  if (normals) mesh.N.conservativeResize(mesh.V.rows(), 3);
  for (std::size_t c = 0; c < copies.size(); ++c) {
    const int v = copies[c].first, copy = nv + static_cast<int>(c);
    mesh.V.row(copy) = mesh.V.row(v);
    if (normals) mesh.N.row(copy) = mesh.N.row(v);
    for (int f : copies[c].second)
      for (int k = 0; k < 3; ++k)
        if (mesh.F(f, k) == v) mesh.F(f, k) = copy;
  }
  return static_cast<int>(copies.size());
}

std::string nonManifoldVertexMessage(const Faces& F, int v) {
  std::vector<int> faces;
  for (int f = 0; f < F.rows(); ++f)
    if (F(f, 0) == v || F(f, 1) == v || F(f, 2) == v) faces.push_back(f);
  const std::vector<std::vector<int>> fans = fansAround(F, faces, v);
  std::vector<int> fanFace;  // one face per fan
  for (const std::vector<int>& fan : fans) fanFace.push_back(fan.front());
  std::string message = "vertex " + str(v) + " is non-manifold: ";
  if (fanFace.size() >= 2) {
    message += "its " + str(static_cast<long long>(faces.size())) + " faces form " +
               str(static_cast<long long>(fanFace.size())) +
               " separate fans that touch only at this vertex (a 'bowtie'; e.g. face " +
               str(fanFace[0]) + " and face " + str(fanFace[1]) + ")";
  } else {
    message += "its faces do not form a single disc or half-disc around it";
  }
  return message + "; split the vertex, one copy per fan";
}

}  // namespace

double boundingBoxDiagonal(const Points& V) {
  if (V.rows() == 0) return 0.0;
  return (V.colwise().maxCoeff() - V.colwise().minCoeff()).norm();
}

void validate(const TriMesh& mesh, const std::string& source) {
  const auto fail = [&](const std::string& what) { throw Error(source + ": " + what); };
  const Faces& F = mesh.F;
  const Eigen::Index nv = mesh.V.rows(), nf = F.rows();
  if (nf == 0)
    fail(nv == 0 ? std::string("mesh is empty (no vertices, no faces)")
                 : "mesh has no faces (" + str(static_cast<long long>(nv)) + " vertices)");
  constexpr Eigen::Index kMax = std::numeric_limits<int>::max();
  if (nv > kMax || nf > kMax / 3)
    fail("mesh too large (" + str(static_cast<long long>(nv)) + " vertices, " +
         str(static_cast<long long>(nf)) + " faces) for 32-bit indices");

  // Cheap per-element checks first: Connectivity assumes indices in range.
  for (int f = 0; f < nf; ++f)
    for (int i = 0; i < 3; ++i)
      if (F(f, i) < 0 || F(f, i) >= nv)
        fail("face " + str(f) + ", corner " + str(i) + ": vertex index " + str(F(f, i)) +
             " is out of range (the mesh has " + str(static_cast<long long>(nv)) + " vertices)");
  for (int f = 0; f < nf; ++f) {
    const int a = F(f, 0), b = F(f, 1), c = F(f, 2);
    if (a == b || b == c || a == c)
      fail(faceText(F, f) + " uses vertex " + str(a == b || a == c ? a : b) +
           " twice (a degenerate triangle)");
  }
  for (int v = 0; v < nv; ++v)
    if (!mesh.V.row(v).allFinite())
      fail("vertex " + str(v) + " has a non-finite coordinate (" + real(mesh.V(v, 0)) + ", " +
           real(mesh.V(v, 1)) + ", " + real(mesh.V(v, 2)) + ")");
  if (mesh.N.rows() != 0 && mesh.N.rows() != nv)
    fail("mesh has " + str(static_cast<long long>(mesh.N.rows())) + " normals for " +
         str(static_cast<long long>(nv)) + " vertices (expected one per vertex, or none)");

  // Topology. Order matters: a non-manifold edge or a flipped face also breaks the
  // fans of its vertices, so report the edge or face, the actual cause, first.
  const Connectivity conn(F, static_cast<int>(nv));
  if (conn.firstIsolatedVertex >= 0)
    fail("vertex " + str(conn.firstIsolatedVertex) +
         " is not used by any face (an isolated vertex); remove unreferenced vertices");
  if (conn.firstNonManifoldEdgeFace >= 0)
    fail(nonManifoldEdgeMessage(conn, conn.firstNonManifoldEdgeFace));
  if (conn.firstFlippedFace >= 0) fail(flippedFaceMessage(conn, conn.firstFlippedFace));
  if (conn.firstNonManifoldVertex >= 0)
    fail(nonManifoldVertexMessage(F, conn.firstNonManifoldVertex));
}

int removeUnreferencedVertices(TriMesh& mesh) {
  const Eigen::Index n = mesh.V.rows();
  std::vector<int> newIndex(static_cast<std::size_t>(n), -1);
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int v = mesh.F(f, k);
      if (v < 0 || v >= n)
        throw Error("face " + std::to_string(f) + " has vertex index " + std::to_string(v) +
                    ", out of range");
      newIndex[v] = 0;
    }
  int kept = 0;
  for (Eigen::Index v = 0; v < n; ++v)
    if (newIndex[v] == 0) newIndex[v] = kept++;
  if (kept == n) return 0;
  Points V(kept, 3), N(mesh.N.rows() == n ? kept : 0, 3);
  for (Eigen::Index v = 0; v < n; ++v)
    if (newIndex[v] >= 0) {
      V.row(newIndex[v]) = mesh.V.row(v);
      if (N.rows()) N.row(newIndex[v]) = mesh.N.row(v);
    }
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f)
    for (int k = 0; k < 3; ++k) mesh.F(f, k) = newIndex[mesh.F(f, k)];
  mesh.V = std::move(V);
  mesh.N = std::move(N);
  return static_cast<int>(n - kept);
}

namespace {

// Boundary vertices with a finite position, grouped by exact position (-0 and +0 the
// same): each group's vertices in increasing order. Empty when the faces are not
// well-formed (an index out of range or a repeated corner).
std::vector<std::vector<int>> coincidentBoundaryVertices(const TriMesh& mesh) {
  if (!hasWellFormedFaces(mesh)) return {};
  const int nv = static_cast<int>(mesh.V.rows());
  const Connectivity conn(mesh.F, nv);
  std::vector<int> open;
  std::vector<char> isOpen(static_cast<std::size_t>(nv), 0);
  for (int h = 0; h < 3 * conn.numFaces(); ++h)
    if (conn.twin(h) < 0)
      for (int v : {conn.from(h), conn.to(h)})
        if (!isOpen[v] && mesh.V.row(v).allFinite()) {
          isOpen[v] = 1;
          open.push_back(v);
        }
  auto key = [&](int v) {
    // + 0.0 turns -0 into +0, so that the two compare equal in the tuple.
    return std::array<double, 3>{mesh.V(v, 0) + 0.0, mesh.V(v, 1) + 0.0, mesh.V(v, 2) + 0.0};
  };
  std::sort(open.begin(), open.end(),
            [&](int a, int b) { return key(a) != key(b) ? key(a) < key(b) : a < b; });
  std::vector<std::vector<int>> groups;
  for (std::size_t i = 0; i < open.size(); ++i) {
    if (i == 0 || key(open[i]) != key(open[i - 1])) groups.emplace_back();
    groups.back().push_back(open[i]);
  }
  groups.erase(std::remove_if(groups.begin(), groups.end(),
                              [](const std::vector<int>& g) { return g.size() < 2; }),
               groups.end());
  return groups;
}

}  // namespace

bool hasWellFormedFaces(const TriMesh& mesh) {
  const Eigen::Index nv = mesh.V.rows();
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int v = mesh.F(f, k), w = mesh.F(f, (k + 1) % 3);
      if (v < 0 || v >= nv || v == w) return false;
    }
  return true;
}

Welding weldBoundaryVertices(TriMesh& mesh) {
  Welding out;
  const std::vector<std::vector<int>> groups = coincidentBoundaryVertices(mesh);
  if (groups.empty()) return out;
  std::vector<int> target(static_cast<std::size_t>(mesh.V.rows()));
  std::iota(target.begin(), target.end(), 0);
  for (const std::vector<int>& g : groups)
    for (int v : g) target[v] = g.front();
  TriMesh welded;
  welded.V = mesh.V;
  welded.N = mesh.N;
  welded.F.resize(mesh.F.rows(), 3);
  Eigen::Index kept = 0;
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) {
    const std::array<int, 3> t = {target[mesh.F(f, 0)], target[mesh.F(f, 1)], target[mesh.F(f, 2)]};
    if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0]) continue;
    welded.F.row(kept++) << t[0], t[1], t[2];
  }
  welded.F.conservativeResize(kept, 3);
  removeUnreferencedVertices(welded);
  try {
    // Pinched vertices that welding makes are split again afterwards, and edges of
    // three faces that the input had are cut; an edge of three faces that welding would
    // make is refused (cutting it would undo the weld).
    TriMesh split = welded, unwelded = mesh;
    if (cutNonManifoldEdges(split) > cutNonManifoldEdges(unwelded)) split = welded;
    orientConsistently(split);
    splitNonManifoldVertices(split);
    validate(split, "the welded mesh");
  } catch (const Error& e) {
    out.refused = e.what();
    return out;
  }
  for (const std::vector<int>& g : groups) out.vertices += static_cast<int>(g.size()) - 1;
  out.faces = static_cast<int>(mesh.F.rows() - kept);
  mesh = std::move(welded);
  return out;
}

int removeFacesWithRepeatedCorners(TriMesh& mesh) {
  const Eigen::Index nv = mesh.V.rows();
  Eigen::Index kept = 0;
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) {
    const int a = mesh.F(f, 0), b = mesh.F(f, 1), c = mesh.F(f, 2);
    const bool inRange = a >= 0 && a < nv && b >= 0 && b < nv && c >= 0 && c < nv;
    if (inRange && (a == b || b == c || c == a)) continue;
    mesh.F.row(kept++) = mesh.F.row(f);
  }
  const int dropped = static_cast<int>(mesh.F.rows() - kept);
  mesh.F.conservativeResize(kept, 3);
  return dropped;
}

int removeDuplicateFaces(TriMesh& mesh) {
  if (!hasWellFormedFaces(mesh)) return 0;
  // A face's key: its corners sorted, so that either orientation matches.
  std::vector<std::pair<std::array<int, 3>, Eigen::Index>> keys;
  keys.reserve(static_cast<std::size_t>(mesh.F.rows()));
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) {
    std::array<int, 3> k = {mesh.F(f, 0), mesh.F(f, 1), mesh.F(f, 2)};
    std::sort(k.begin(), k.end());
    keys.emplace_back(k, f);
  }
  std::sort(keys.begin(), keys.end());
  std::vector<char> drop(static_cast<std::size_t>(mesh.F.rows()), 0);
  int dropped = 0;
  for (std::size_t i = 1; i < keys.size(); ++i)
    if (keys[i].first == keys[i - 1].first) {  // sorted by face too: the first one stays
      drop[keys[i].second] = 1;
      ++dropped;
    }
  if (dropped == 0) return 0;
  Eigen::Index kept = 0;
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f)
    if (!drop[f]) mesh.F.row(kept++) = mesh.F.row(f);
  mesh.F.conservativeResize(kept, 3);
  return dropped;
}

int splitNonManifoldVertices(TriMesh& mesh) {
  if (!hasWellFormedFaces(mesh)) return 0;
  const int nv = static_cast<int>(mesh.V.rows());
  const Connectivity conn(mesh.F, nv);
  if (conn.firstNonManifoldVertex < 0 || conn.firstNonManifoldEdgeFace >= 0 ||
      conn.firstFlippedFace >= 0)
    return 0;
  std::vector<int> pinched;
  for (int v = 0; v < nv; ++v)
    if (!conn.isManifoldVertex(v)) pinched.push_back(v);
  return detachFans(mesh, pinched, false);
}

using detail::halfedgesByEdge;
using detail::runEnd;

int cutNonManifoldEdges(TriMesh& mesh) {
  if (!hasWellFormedFaces(mesh)) return 0;
  const std::vector<std::pair<std::uint64_t, int>> edges = halfedgesByEdge(mesh.F);
  std::vector<int> ends;
  int cut = 0;
  for (std::size_t i = 0, end; i < edges.size(); i = end) {
    end = runEnd(edges, i);
    if (end - i > 2) {
      ends.push_back(static_cast<int>(edges[i].first >> 32));
      ends.push_back(static_cast<int>(edges[i].first & 0xffffffffu));
      ++cut;
    }
  }
  if (cut == 0) return 0;
  std::sort(ends.begin(), ends.end());
  ends.erase(std::unique(ends.begin(), ends.end()), ends.end());
  // No face is joined to another across a cut edge: each end gets a copy per fan of
  // faces joined through its other edges.
  detachFans(mesh, ends, true);
  return cut;
}

int orientConsistently(TriMesh& mesh) {
  if (!hasWellFormedFaces(mesh)) return 0;
  const int nf = static_cast<int>(mesh.F.rows());
  // The halfedge across each one (-1 on the boundary), and whether the two agree (run
  // their edge opposite ways).
  const std::vector<std::pair<std::uint64_t, int>> edges = halfedgesByEdge(mesh.F);
  std::vector<int> twin(3 * static_cast<std::size_t>(nf), -1);
  std::vector<char> agrees(twin.size(), 1);
  bool disagreement = false;
  for (std::size_t i = 0, end; i < edges.size(); i = end) {
    end = runEnd(edges, i);
    if (end - i > 2) return 0;  // cutNonManifoldEdges first; validate() reports it
    if (end - i < 2) continue;
    const int h = edges[i].second, g = edges[i + 1].second;
    twin[h] = g;
    twin[g] = h;
    agrees[h] = agrees[g] = mesh.F(h / 3, h % 3) != mesh.F(g / 3, g % 3);
    disagreement = disagreement || !agrees[h];
  }
  if (!disagreement) return 0;
  // Each component from its first face: a neighbour that disagrees is reversed once.
  // A contradiction (a Moebius strip) leaves the mesh as it was.
  std::vector<signed char> reversed(static_cast<std::size_t>(nf), -1);
  std::vector<int> stack, component, flips;
  for (int start = 0; start < nf; ++start) {
    if (reversed[start] >= 0) continue;
    component.assign(1, start);
    reversed[start] = 0;
    stack.assign(1, start);
    while (!stack.empty()) {
      const int f = stack.back();
      stack.pop_back();
      for (int h = 3 * f; h < 3 * f + 3; ++h) {
        if (twin[h] < 0) continue;
        const int g = twin[h] / 3;
        const signed char want =
            static_cast<signed char>(agrees[h] ? reversed[f] : 1 - reversed[f]);
        if (reversed[g] < 0) {
          reversed[g] = want;
          component.push_back(g);
          stack.push_back(g);
        } else if (reversed[g] != want) {
          return 0;  // not orientable
        }
      }
    }
    // Keep the orientation most of the component's faces have.
    std::size_t count = 0;
    for (int f : component) count += reversed[f];
    const bool invert = 2 * count > component.size();
    for (int f : component)
      if ((reversed[f] != 0) != invert) flips.push_back(f);
  }
  for (int f : flips) std::swap(mesh.F(f, 1), mesh.F(f, 2));
  return static_cast<int>(flips.size());
}

std::vector<int> componentOfFaces(const Faces& F, int numVertices) {
  std::vector<int> parent(static_cast<std::size_t>(numVertices));
  std::iota(parent.begin(), parent.end(), 0);
  const auto find = [&](int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int k = 1; k < 3; ++k) {
      const int a = find(F(f, 0)), b = find(F(f, k));
      parent[std::max(a, b)] = std::min(a, b);
    }
  // Components numbered in the order of their first face.
  std::vector<int> number(static_cast<std::size_t>(numVertices), -1), out(F.rows());
  int next = 0;
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    int& n = number[find(F(f, 0))];
    if (n < 0) n = next++;
    out[f] = n;
  }
  return out;
}

int removeSmallComponents(TriMesh& mesh, int minFaces) {
  if (minFaces <= 1 || !hasWellFormedFaces(mesh)) return 0;
  const std::vector<int> component = componentOfFaces(mesh.F, static_cast<int>(mesh.V.rows()));
  std::vector<int> size;
  for (int c : component) {
    if (c >= static_cast<int>(size.size())) size.resize(c + 1, 0);
    ++size[c];
  }
  Eigen::Index kept = 0;
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f)
    if (size[component[f]] >= minFaces) mesh.F.row(kept++) = mesh.F.row(f);
  mesh.F.conservativeResize(kept, 3);
  removeUnreferencedVertices(mesh);
  return static_cast<int>(
      std::count_if(size.begin(), size.end(), [&](int n) { return n < minFaces; }));
}

}  // namespace osdmra
