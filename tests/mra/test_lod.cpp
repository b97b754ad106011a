// Level of detail (math.md 5): adaptive, crack-free meshes from kept coefficients.
//
// Every mesh is checked against the hierarchy it was cut from, independently of how
// extractLod builds it: each face is a whole triangle of M^faceLevel or one half of
// a green split of one, in the input's winding; the result is a valid manifold with
// the base's topology; it covers the base surface exactly (linear scheme, no
// displacement); and no output vertex lies inside an output edge.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <random>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "osdmra/base/error.h"
#include "osdmra/mra/filter_bank.h"
#include "osdmra/mra/lod.h"
#include "osdmra/mra/truncation.h"
#include "osdmra/subdivision/shapes.h"
#include "support.h"

using namespace osdmra;
using namespace osdmra::test;

namespace {

using Tri = std::array<int, 3>;

// The same triangle with its smallest index first (winding kept).
Tri rotated(int a, int b, int c) {
  if (b < a && b < c) return {b, c, a};
  if (c < a && c < b) return {c, a, b};
  return {a, b, c};
}

struct TriHash {
  std::size_t operator()(const Tri& t) const {
    std::uint64_t k = static_cast<std::uint32_t>(t[0]);
    k = k * 0x9E3779B97F4A7C15ull ^ static_cast<std::uint32_t>(t[1]);
    k = k * 0x9E3779B97F4A7C15ull ^ static_cast<std::uint32_t>(t[2]);
    return static_cast<std::size_t>(k ^ (k >> 29));
  }
};

Eigen::Vector3d point(const Points& V, int v) {
  return V.row(v).transpose();
}

double area(const Points& V, int a, int b, int c) {
  return 0.5 * (point(V, b) - point(V, a)).cross(point(V, c) - point(V, a)).norm();
}

// One base shape with its hierarchy and everything the checks compare against,
// built once for all tests.
struct Shape {
  std::string name;
  TriMesh base;
  int J;
  Hierarchy h;
  Points linear;  ///< M^J on the base mesh: linear scheme, no displacement
  std::vector<std::unordered_set<Tri, TriHash>> levelFaces;  ///< rotated faces of M^l
  std::vector<int> birth;  ///< first level at which each M^J vertex exists
  Topology baseTopology;   ///< which every level of detail keeps
  double totalArea = 0, minBaseArea = 1e300;
  double quantum = 0;  ///< position quantisation for the geometric T-junction check

  Shape(std::string n, TriMesh m, int levels)
      : name(std::move(n)),
        base(std::move(m)),
        J(levels),
        h(base.F, static_cast<int>(base.V.rows()), levels),
        linear(subdivide(base, levels, Scheme::Linear).V) {
    levelFaces.resize(J + 1);
    for (int l = 0; l <= J; ++l) {
      const Faces& F = h.faces(l);
      for (int f = 0; f < F.rows(); ++f) levelFaces[l].insert(rotated(F(f, 0), F(f, 1), F(f, 2)));
    }
    birth.assign(h.numVertices(J), 0);
    for (int l = 1; l <= J; ++l)
      for (int v = h.numVertices(l - 1); v < h.numVertices(l); ++v) birth[v] = l;
    baseTopology = topology(base);
    for (int f = 0; f < base.F.rows(); ++f) {
      const double a = area(base.V, base.F(f, 0), base.F(f, 1), base.F(f, 2));
      totalArea += a;
      minBaseArea = std::min(minBaseArea, a);
    }
    quantum = boundingBoxDiagonal(base.V) * 1e-9;
  }

  std::array<long long, 3> key(const Eigen::Vector3d& p) const {
    return {std::llround(p.x() / quantum), std::llround(p.y() / quantum),
            std::llround(p.z() / quantum)};
  }
};

struct KeyHash {
  std::size_t operator()(const std::array<long long, 3>& k) const {
    std::uint64_t x = static_cast<std::uint64_t>(k[0]);
    x = x * 0x9E3779B97F4A7C15ull ^ static_cast<std::uint64_t>(k[1]);
    x = x * 0x9E3779B97F4A7C15ull ^ static_cast<std::uint64_t>(k[2]);
    return static_cast<std::size_t>(x ^ (x >> 31));
  }
};

const std::vector<std::unique_ptr<Shape>>& shapesUnderTest() {
  static const std::vector<std::unique_ptr<Shape>> all = [] {
    std::vector<std::unique_ptr<Shape>> v;
    for (auto& [name, mesh] : shapes::all()) {
      // Level 4 where the base is small, 3 elsewhere, to keep the suite fast.
      const int J = mesh.F.rows() <= 20 ? 4 : 3;
      v.push_back(std::make_unique<Shape>(name, mesh, J));
    }
    return v;
  }();
  return all;
}

KeepMask emptyMask(const Hierarchy& h) {
  KeepMask keep(h.levels());
  for (int j = 0; j < h.levels(); ++j)
    keep[j].assign(static_cast<std::size_t>(h.numVertices(j + 1) - h.numVertices(j)), 0);
  return keep;
}

// Keeps coefficient m when u_m < density, with one uniform u_m per coefficient drawn
// from `seed`: masks of the same seed are nested in their density.
KeepMask randomMask(const Hierarchy& h, unsigned seed, double density) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  KeepMask keep = emptyMask(h);
  for (auto& level : keep)
    for (auto& k : level) k = u(rng) < density ? 1 : 0;
  return keep;
}

// An edge of the output with the hierarchy level it lives on, or the diagonal of a
// green split of a level-`level` face, which is no hierarchy edge.
struct LevelEdge {
  int u, v, level;
  bool diagonal = false;
};

// Checks everything a level-of-detail mesh promises; see the file comment.
void checkLod(const Shape& s, const KeepMask& keep, const LodMesh& lod) {
  const Hierarchy& h = s.h;
  const int J = s.J, nf = static_cast<int>(lod.faces.rows());
  ASSERT_EQ(lod.compactFaces.rows(), nf);
  ASSERT_EQ(static_cast<int>(lod.faceLevel.size()), nf);
  EXPECT_EQ(lod.redTriangles + lod.greenTriangles, nf);

  // vertices: ascending, distinct, exactly the indices used; compactFaces maps back.
  std::vector<char> used(h.numVertices(J), 0);
  for (int r = 0; r < nf; ++r)
    for (int k = 0; k < 3; ++k) {
      ASSERT_GE(lod.faces(r, k), 0);
      ASSERT_LT(lod.faces(r, k), h.numVertices(J));
      used[lod.faces(r, k)] = 1;
    }
  const int nv = static_cast<int>(lod.vertices.size());
  EXPECT_EQ(nv, std::count(used.begin(), used.end(), 1));
  EXPECT_TRUE(std::adjacent_find(lod.vertices.begin(), lod.vertices.end(),
                                 [](int a, int b) { return a >= b; }) == lod.vertices.end());
  for (int r = 0; r < nf; ++r)
    for (int k = 0; k < 3; ++k) {
      ASSERT_GE(lod.compactFaces(r, k), 0);
      ASSERT_LT(lod.compactFaces(r, k), nv);
      ASSERT_EQ(lod.vertices[lod.compactFaces(r, k)], lod.faces(r, k));
    }

  // Every kept coefficient's vertex is in the mesh.
  for (int j = 0; j < J; ++j)
    for (std::size_t e = 0; e < keep[j].size(); ++e)
      if (keep[j][e]) {
        EXPECT_TRUE(used[h.numVertices(j) + static_cast<int>(e)]) << j << " " << e;
      }

  // A valid manifold (consistent orientation, no non-manifold edge or vertex) with
  // the base's Euler characteristic, boundary loops and components.
  TriMesh m;
  m.V.resize(nv, 3);
  for (int k = 0; k < nv; ++k) m.V.row(k) = s.linear.row(lod.vertices[k]);
  m.F = lod.compactFaces;
  EXPECT_NO_THROW(validate(m, s.name + " lod"));
  EXPECT_EQ(topology(m), s.baseTopology);

  // Three distinct corners and positive area; the triangles tile the base surface
  // exactly (linear positions lie on the base triangles).
  double total = 0;
  const double smallest = s.minBaseArea / std::pow(4.0, J) / 2;
  for (int r = 0; r < nf; ++r) {
    const int a = lod.faces(r, 0), b = lod.faces(r, 1), d = lod.faces(r, 2);
    EXPECT_TRUE(a != b && b != d && d != a) << "face " << r;
    const double ar = area(s.linear, a, b, d);
    EXPECT_GT(ar, 0.99 * smallest) << "face " << r;
    total += ar;
  }
  EXPECT_NEAR(total, s.totalArea, 1e-9 * s.totalArea);

  // Provenance: each face is a whole face of M^L (L = faceLevel) or a green half of
  // one, (x, m, w) or (m, y, w) for the face (x, y, w) and m = midpoint(L, x, y), in
  // the hierarchy's winding. That also gives each edge its level.
  std::vector<LevelEdge> edges;
  int whole = 0, green = 0;
  for (int r = 0; r < nf; ++r) {
    const int L = lod.faceLevel[r];
    ASSERT_GE(L, 0);
    ASSERT_LE(L, J);
    const int v[3] = {lod.faces(r, 0), lod.faces(r, 1), lod.faces(r, 2)};
    ASSERT_EQ(static_cast<int>(lod.faceOrigin.size()), nf);
    const auto origin = h.faces(L).row(lod.faceOrigin[r]);
    const Tri originTri = rotated(origin(0), origin(1), origin(2));
    if (s.levelFaces[L].count(rotated(v[0], v[1], v[2]))) {
      EXPECT_EQ(rotated(v[0], v[1], v[2]), originTri) << "face " << r << ": wrong origin";
      ++whole;
      for (int k = 0; k < 3; ++k) edges.push_back({v[k], v[(k + 1) % 3], L});
      continue;
    }
    ASSERT_LT(L, J) << "face " << r << " is not a face of M^" << L;
    int k = 0;
    while (k < 3 && s.birth[v[k]] != L + 1) ++k;
    ASSERT_LT(k, 3) << "face " << r << " is neither a face of M^" << L << " nor a green half";
    const int mid = v[k], next = v[(k + 1) % 3], prev = v[(k + 2) % 3];
    ASSERT_LE(s.birth[next], L);
    ASSERT_LE(s.birth[prev], L);
    const auto xy = h.parentEdge(L, mid - h.numVertices(L));
    Tri parent;
    if (prev == xy[0] || prev == xy[1]) {  // (x, m, w): m -> w, w -> x
      const int y = prev == xy[0] ? xy[1] : xy[0];
      parent = rotated(prev, y, next);
      edges.push_back({prev, mid, L + 1});
      edges.push_back({mid, next, L, true});
      edges.push_back({next, prev, L});
    } else {
      ASSERT_TRUE(next == xy[0] || next == xy[1]) << "face " << r << " is not a green half";
      const int x = next == xy[0] ? xy[1] : xy[0];  // (m, y, w): m -> y, y -> w
      parent = rotated(x, next, prev);
      edges.push_back({mid, next, L + 1});
      edges.push_back({next, prev, L});
      edges.push_back({prev, mid, L, true});
    }
    EXPECT_TRUE(s.levelFaces[L].count(parent)) << "green face " << r << ": no parent in M^" << L;
    EXPECT_EQ(parent, originTri) << "green face " << r << ": wrong origin";
    ++green;
  }
  EXPECT_EQ(whole, lod.redTriangles);
  EXPECT_EQ(green, lod.greenTriangles);
  EXPECT_EQ(green % 2, 0);

  // No T-junctions, combinatorially: for an output edge (u, v) of level l, no vertex
  // of its midpoint chain (midpoint(l, u, v), then the midpoints of both halves at
  // l + 1, ... down to level J) is an output vertex.
  std::vector<std::array<int, 3>> chain;
  for (const LevelEdge& e : edges) {
    if (e.diagonal) continue;
    if (e.level < J) {
      ASSERT_GE(h.midpoint(e.level, e.u, e.v), 0) << "not an edge of M^" << e.level;
    }
    chain.assign(1, {e.level, e.u, e.v});
    while (!chain.empty()) {
      const auto [l, a, b] = chain.back();
      chain.pop_back();
      if (l == J) continue;
      const int mid = h.midpoint(l, a, b);
      ASSERT_GE(mid, 0);
      EXPECT_FALSE(used[mid]) << "T-junction: vertex " << mid << " inside edge " << e.u << "-"
                              << e.v << " of level " << e.level;
      chain.push_back({l + 1, a, mid});
      chain.push_back({l + 1, mid, b});
    }
  }

  // No T-junctions, geometrically (covers the green diagonals too): no output vertex
  // sits at a dyadic point u + k/2^s (v - u) inside an output edge, for the
  // denominators the level-J grid can have on it.
  std::unordered_map<std::array<long long, 3>, int, KeyHash> at;
  for (int v : lod.vertices) at.emplace(s.key(point(s.linear, v)), v);
  for (const LevelEdge& e : edges) {
    const Eigen::Vector3d pu = point(s.linear, e.u), pv = point(s.linear, e.v);
    for (int sh = 1; sh <= J - e.level + 1; ++sh) {
      const double den = std::ldexp(1.0, sh);
      for (int k = 1; k < (1 << sh); k += 2) {
        const auto hit = at.find(s.key(pu + (k / den) * (pv - pu)));
        EXPECT_TRUE(hit == at.end())
            << "T-junction: vertex " << hit->second << " on edge " << e.u << "-" << e.v;
      }
    }
  }
}

LodMesh checked(const Shape& s, const KeepMask& keep) {
  LodMesh lod = extractLod(s.h, keep);
  checkLod(s, keep, lod);
  return lod;
}

bool subset(const std::vector<int>& a, const std::vector<int>& b) {
  return std::includes(b.begin(), b.end(), a.begin(), a.end());
}

}  // namespace

// The test itself: distinct M^J vertices are at distinct linear positions, so the
// geometric T-junction check cannot confuse two vertices.
TEST(Lod, ShapesHaveDistinctPositions) {
  for (const auto& s : shapesUnderTest()) {
    std::unordered_set<std::array<long long, 3>, KeyHash> seen;
    for (int v = 0; v < s->linear.rows(); ++v)
      EXPECT_TRUE(seen.insert(s->key(point(s->linear, v))).second) << s->name << " " << v;
  }
}

// Nothing kept: the base mesh; everything kept: M^J, row for row.
TEST(Lod, EndsAreBaseAndFinest) {
  for (const auto& sp : shapesUnderTest()) {
    const Shape& s = *sp;
    SCOPED_TRACE(s.name);
    const LodMesh none = checked(s, emptyMask(s.h));
    EXPECT_EQ(none.faces, s.base.F);
    EXPECT_EQ(none.greenTriangles, 0);
    EXPECT_TRUE(
        std::all_of(none.faceLevel.begin(), none.faceLevel.end(), [](int l) { return l == 0; }));
    std::vector<int> baseVertices(s.base.V.rows());
    for (int v = 0; v < s.base.V.rows(); ++v) baseVertices[v] = v;
    EXPECT_EQ(none.vertices, baseVertices);
    EXPECT_EQ(none.compactFaces, s.base.F);

    const LodMesh all = checked(s, randomMask(s.h, 1, 2.0));
    EXPECT_EQ(all.faces, s.h.faces(s.J));
    EXPECT_EQ(all.greenTriangles, 0);
    EXPECT_EQ(static_cast<int>(all.vertices.size()), s.h.numVertices(s.J));
    EXPECT_TRUE(
        std::all_of(all.faceLevel.begin(), all.faceLevel.end(), [&](int l) { return l == s.J; }));
  }
}

// Random masks of 1%, 10% and 50% under several seeds; masks of one seed are nested,
// and a superset never gives fewer triangles or loses a vertex.
TEST(Lod, RandomMasksAreConformingAndMonotone) {
  for (const auto& sp : shapesUnderTest()) {
    const Shape& s = *sp;
    for (unsigned seed : {1u, 2u, 3u}) {
      SCOPED_TRACE(s.name + " seed " + std::to_string(seed));
      LodMesh previous = extractLod(s.h, emptyMask(s.h));
      for (double density : {0.01, 0.1, 0.5, 2.0}) {
        SCOPED_TRACE(density);
        const LodMesh lod = checked(s, randomMask(s.h, seed, density));
        EXPECT_GE(lod.faces.rows(), previous.faces.rows());
        EXPECT_TRUE(subset(previous.vertices, lod.vertices));
        previous = lod;
      }
    }
  }
}

// The triangle count of every prefix of an order, computed in one pass, is what
// extractLod gives for that prefix's mask, and never decreases.
TEST(Lod, TriangleCountsOfEveryPrefix) {
  for (const auto& sp : shapesUnderTest()) {
    const Shape& s = *sp;
    SCOPED_TRACE(s.name);
    std::vector<std::pair<int, int>> order;
    for (int j = 0; j < s.J; ++j)
      for (int e = 0; e < s.h.numVertices(j + 1) - s.h.numVertices(j); ++e)
        order.emplace_back(j, e);
    // Coarse coefficients first, as an importance order tends to give, then shuffled
    // within a window so that closures interleave across levels.
    std::mt19937 rng(11);
    for (std::size_t i = 0; i + 1 < order.size(); ++i)
      std::swap(order[i], order[i + rng() % std::min<std::size_t>(40, order.size() - i)]);
    const std::vector<long long> counts = lodTriangleCounts(s.h, order);
    const int K = static_cast<int>(order.size());
    ASSERT_EQ(static_cast<int>(counts.size()), K + 1);
    EXPECT_EQ(counts[0], s.base.F.rows());
    EXPECT_EQ(counts[K], s.h.numFaces(s.J));
    EXPECT_TRUE(std::is_sorted(counts.begin(), counts.end()));
    KeepMask keep = emptyMask(s.h);
    const int stride = std::max(1, K / 120);
    for (int k = 0; k <= K; ++k) {
      if (k > 0) keep[order[k - 1].first][order[k - 1].second] = 1;
      if (k % stride == 0 || k == K) {
        ASSERT_EQ(counts[k], extractLod(s.h, keep).faces.rows()) << "k = " << k;
      }
    }
  }
  const Hierarchy h(shapes::tetrahedron().F, 4, 2);
  EXPECT_THROW(lodTriangleCounts(h, {{2, 0}}), Error);
  EXPECT_THROW(lodTriangleCounts(h, {{0, 6}}), Error);
}

// saturate() adds exactly the coefficients that leave the mesh unchanged.
TEST(Lod, SaturateKeepsTheMeshAndIsMaximal) {
  for (const auto& sp : shapesUnderTest()) {
    const Shape& s = *sp;
    SCOPED_TRACE(s.name);
    for (double density : {0.005, 0.05, 0.3}) {
      SCOPED_TRACE(density);
      const KeepMask keep = randomMask(s.h, 4, density);
      const KeepMask full = saturate(s.h, keep);
      const LodMesh lod = extractLod(s.h, keep);
      EXPECT_EQ(extractLod(s.h, full).faces, lod.faces);
      EXPECT_EQ(saturate(s.h, full), full);
      // Both from one closure: the same mask and the same mesh, vertex for vertex.
      KeepMask shared;
      const LodMesh both = extractSaturated(s.h, keep, shared);
      EXPECT_EQ(shared, full);
      EXPECT_EQ(both.faces, lod.faces);
      EXPECT_EQ(both.compactFaces, lod.compactFaces);
      EXPECT_EQ(both.vertices, lod.vertices);
      EXPECT_EQ(both.faceLevel, lod.faceLevel);
      EXPECT_EQ(both.faceOrigin, lod.faceOrigin);
      std::mt19937 rng(8);
      for (int j = 0; j < s.J; ++j)
        for (std::size_t e = 0; e < keep[j].size(); ++e) {
          if (keep[j][e]) {
            EXPECT_TRUE(full[j][e]);  // a superset
            continue;
          }
          if (rng() % 8 != 0) continue;  // a sample of the rest
          KeepMask plus = full;
          plus[j][e] = 1;
          // Free coefficients change nothing; any other one changes the mesh.
          EXPECT_EQ(extractLod(s.h, plus).faces.rows() == lod.faces.rows(), full[j][e] != 0)
              << "level " << j << " coefficient " << e;
        }
    }
  }
}

// One coefficient at the finest level: a valid mesh that refines only around it.
TEST(Lod, SingleDeepCoefficient) {
  for (const auto& sp : shapesUnderTest()) {
    const Shape& s = *sp;
    const int j = s.J - 1;
    const int n = s.h.numVertices(j + 1) - s.h.numVertices(j);
    for (int e : {0, n / 2, n - 1}) {
      SCOPED_TRACE(s.name + " e " + std::to_string(e));
      KeepMask keep = emptyMask(s.h);
      keep[j][e] = 1;
      const LodMesh lod = checked(s, keep);
      EXPECT_GT(lod.faces.rows(), s.base.F.rows());
      // The closure is local: a bounded number of splits per level.
      EXPECT_LE(lod.faces.rows(), s.base.F.rows() + 30 * s.J);
      EXPECT_GT(lod.greenTriangles, 0);
    }
  }
}

// A mask from real importances (Loop, displaced surface, 10% largest): valid on the
// displaced surface's own positions, too. Quasi-wavelets where their filter bank is
// cheap; lazy ones on the shapes with many distinct neighbourhoods, whose
// quasi-wavelet set-up alone would take most of the suite's time budget.
TEST(Lod, ImportanceMask) {
  for (const auto& sp : shapesUnderTest()) {
    const Shape& s = *sp;
    SCOPED_TRACE(s.name);
    const bool heavy = s.name == "genus2" || s.name == "genus3" || s.name == "valences";
    const TriMesh surface = subdivide(s.base, s.J, Scheme::Loop, 0.05, 7);
    const FilterBank bank = makeFilterBank(
        s.h, Scheme::Loop, {heavy ? WaveletKind::Lazy : WaveletKind::Quasi, kDefaultRings});
    const Decomposition d = analyze(bank, surface.V);
    const auto imp = importance(d, bank.norms);
    long long total = 0;
    for (const auto& level : imp) total += level.size();
    const KeepMask keep = keepLargest(imp, total / 10);
    const LodMesh lod = checked(s, keep);
    EXPECT_GT(lod.faces.rows(), s.base.F.rows());
    EXPECT_LT(lod.faces.rows(), s.h.numFaces(s.J));
    TriMesh m;
    m.V.resize(static_cast<Eigen::Index>(lod.vertices.size()), 3);
    for (std::size_t k = 0; k < lod.vertices.size(); ++k)
      m.V.row(static_cast<Eigen::Index>(k)) = surface.V.row(lod.vertices[k]);
    m.F = lod.compactFaces;
    EXPECT_NO_THROW(validate(m, s.name + " lod on the surface"));
  }
}

// On the octahedron (convex, centred at the origin) every face faces outwards, as
// the base faces do.
TEST(Lod, OctahedronFacesPointOutwards) {
  for (const auto& sp : shapesUnderTest()) {
    const Shape& s = *sp;
    if (s.name != "octahedron") continue;
    for (double density : {0.01, 0.1, 0.5}) {
      const LodMesh lod = extractLod(s.h, randomMask(s.h, 5, density));
      for (int r = 0; r < lod.faces.rows(); ++r) {
        const Eigen::Vector3d a = point(s.linear, lod.faces(r, 0)),
                              b = point(s.linear, lod.faces(r, 1)),
                              c = point(s.linear, lod.faces(r, 2));
        EXPECT_GT((b - a).cross(c - a).dot(a + b + c), 0) << "face " << r;
      }
    }
  }
}

TEST(Lod, RejectsMismatchedMask) {
  const Shape& s = *shapesUnderTest().front();
  KeepMask keep = emptyMask(s.h);
  keep.pop_back();
  EXPECT_THROW(extractLod(s.h, keep), Error);
  keep = emptyMask(s.h);
  keep[0].push_back(0);
  EXPECT_THROW(extractLod(s.h, keep), Error);
}

// Timing on a level-8 octahedron with 10% kept (run with
// --gtest_also_run_disabled_tests).
TEST(Lod, DISABLED_TimingOctahedron8) {
  const TriMesh base = shapes::octahedron();
  const auto t0 = std::chrono::steady_clock::now();
  const Hierarchy h(base.F, static_cast<int>(base.V.rows()), 8);
  for (int j = 0; j < 8; ++j) h.connectivity(j);
  const auto t1 = std::chrono::steady_clock::now();
  const KeepMask keep = randomMask(h, 1, 0.1);
  LodMesh lod;
  const int runs = 5;
  const auto t2 = std::chrono::steady_clock::now();
  for (int r = 0; r < runs; ++r) lod = extractLod(h, keep);
  const auto t3 = std::chrono::steady_clock::now();
  const auto ms = [](auto a, auto b) {
    return std::chrono::duration<double, std::milli>(b - a).count();
  };
  std::printf(
      "hierarchy + connectivity: %.1f ms; extractLod: %.2f ms (%lld kept, %d faces, %d "
      "green, of %d)\n",
      ms(t0, t1), ms(t2, t3) / runs, countKept(keep), static_cast<int>(lod.faces.rows()),
      lod.greenTriangles, h.numFaces(8));
}
