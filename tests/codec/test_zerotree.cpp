// The edge zerotree (codec/zerotree.h): the tree matches the refinement of edges,
// coding is exact, and a cut stream leaves every coefficient in a true interval.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <random>
#include <set>

#include "osdmra/codec/osz_format.h"
#include "osdmra/codec/zerotree.h"
#include "osdmra/subdivision/shapes.h"

namespace osdmra {
namespace {

TEST(EdgeTree, ChildrenAreTheEdgesThatRefineTheParent) {
  for (const char* name : {"octahedron", "disc", "torus", "valences"}) {
    const TriMesh base = shapes::byName(name);
    const Hierarchy h(base.F, static_cast<int>(base.V.rows()), 3);
    const EdgeTree t = edgeTree(h);
    ASSERT_EQ(t.edges.size(), 3u);
    ASSERT_EQ(t.children.size(), 2u);
    for (int j = 0; j < 2; ++j) {
      const Connectivity& c = h.connectivity(j);
      std::vector<int> parents(t.edges[j + 1], 0);
      for (int e = 0; e < t.edges[j]; ++e) {
        const auto [a, b] = h.parentEdge(j, e);
        const int m = h.numVertices(j) + e;  // the new vertex on e, in M^{j+1}
        const std::array<int, 4>& kids = t.children[j][e];
        const int count =
            static_cast<int>(std::count_if(kids.begin(), kids.end(), [](int k) { return k >= 0; }));
        // Four children inside, three on a boundary (one triangle beside it).
        int faces = 0;
        for (int hIt : c.fan(a)) faces += c.to(hIt) == b;
        for (int hIt : c.fan(b)) faces += c.to(hIt) == a;
        EXPECT_EQ(count, 2 + faces) << name << " level " << j << " edge " << e;
        std::set<std::set<int>> halves, others;
        for (int k : kids) {
          if (k < 0) continue;
          ++parents[k];
          const auto [x, y] = h.parentEdge(j + 1, k);
          const std::set<int> ends{x, y};
          if (ends == std::set<int>{a, m} || ends == std::set<int>{m, b})
            halves.insert(ends);
          else
            others.insert(ends);
        }
        EXPECT_EQ(halves.size(), 2u) << name << " level " << j << " edge " << e;
        // Its neighbours: the other two edges of each triangle beside it, each sharing
        // one end with it.
        int neighbours = 0;
        for (int k : t.neighbours[j][e]) {
          if (k < 0) continue;
          ++neighbours;
          const auto [x, y] = h.parentEdge(j, k);
          EXPECT_EQ((x == a || x == b) + (y == a || y == b), 1) << name << " " << e << " " << k;
        }
        EXPECT_EQ(neighbours, 2 * faces) << name << " level " << j << " edge " << e;
        // The other children join the midpoints of the two other edges of a triangle
        // beside e: both ends are new vertices, neither is m.
        const std::array<int, 4>& beside = t.neighbours[j][e];
        for (const std::set<int>& o : others)
          for (int v : o) {
            EXPECT_GE(v, h.numVertices(j));
            EXPECT_NE(v, m);
            EXPECT_NE(std::find(beside.begin(), beside.end(), v - h.numVertices(j)), beside.end())
                << name << " level " << j << " edge " << e;
          }
      }
      // Every edge of M^{j+1} has exactly one parent.
      for (int k = 0; k < t.edges[j + 1]; ++k) EXPECT_EQ(parents[k], 1) << name << " " << k;
    }
  }
}

// Sparse coefficients that shrink with the level, as wavelet coefficients do.
QuantisedLevels randomLevels(const EdgeTree& t, std::uint32_t seed) {
  std::mt19937 rng(seed);
  QuantisedLevels q(t.edges.size());
  for (std::size_t j = 0; j < q.size(); ++j) {
    std::geometric_distribution<int> size(0.02 * (1 << j));
    std::bernoulli_distribution zero(0.3 + 0.15 * j);
    q[j].resize(3 * static_cast<std::size_t>(t.edges[j]));
    for (std::int32_t& v : q[j])
      v = zero(rng) ? 0 : (rng() & 1 ? 1 : -1) * std::min(size(rng), 1 << 20);
  }
  return q;
}

TEST(Zerotree, WholeStreamsDecodeEveryCoefficient) {
  const TriMesh base = shapes::byName("torus");
  const Hierarchy h(base.F, static_cast<int>(base.V.rows()), 4);
  const EdgeTree t = edgeTree(h);
  for (std::uint32_t seed : {1u, 2u, 3u}) {
    const QuantisedLevels q = randomLevels(t, seed);
    RangeEncoder enc;
    encodeZerotree(t, q, topPlane(q), enc);
    const std::vector<std::uint8_t> bytes = enc.finish();
    RangeDecoder dec(bytes.data(), bytes.size());
    const ZerotreeState s = decodeZerotree(t, topPlane(q), dec);
    EXPECT_TRUE(s.complete);
    const std::vector<std::vector<double>> v = reconstruct(s);
    for (std::size_t j = 0; j < q.size(); ++j)
      for (std::size_t i = 0; i < q[j].size(); ++i)
        ASSERT_EQ(v[j][i], reconstructed(q[j][i])) << "level " << j << " index " << i;
  }
}

// The stream is the file format: a change to the traversal or the contexts that
// changed a single decision would leave older .osz files undecodable. The levels come
// from mt19937's raw output (fixed by the standard, unlike its distributions), and
// the size and CRC-32 are those of format version 2 (osz_format.h; version 1's, before
// the signs had contexts: 6,905 bytes, CRC 2024620854; these random signs cost a little
// more in adaptive contexts than raw).
TEST(Zerotree, TheStreamOfFixedLevelsIsTheFormatsOwn) {
  const TriMesh base = shapes::byName("torus");
  const Hierarchy h(base.F, static_cast<int>(base.V.rows()), 4);
  const EdgeTree t = edgeTree(h);
  std::mt19937 rng(7);
  QuantisedLevels q(t.edges.size());
  for (std::size_t j = 0; j < q.size(); ++j) {
    q[j].resize(3 * static_cast<std::size_t>(t.edges[j]));
    for (std::int32_t& v : q[j]) {
      const std::uint32_t r = rng();
      const int bits = static_cast<int>(r % 13) - 2 * static_cast<int>(j);  // finer: smaller
      v = bits <= 0 || (r >> 8) % 3 == 0 ? 0 : static_cast<std::int32_t>((r >> 12) % (1u << bits));
      if ((r >> 4) & 1) v = -v;
    }
  }
  RangeEncoder enc;
  encodeZerotree(t, q, topPlane(q), enc);
  const std::vector<std::uint8_t> bytes = enc.finish();
  EXPECT_EQ(bytes.size(), 6925u);
  EXPECT_EQ(crc32(bytes.data(), bytes.size()), 3872254325u);
}

TEST(Zerotree, AllZeroLevelsCostAlmostNothing) {
  const TriMesh base = shapes::byName("octahedron");
  const Hierarchy h(base.F, static_cast<int>(base.V.rows()), 5);
  const EdgeTree t = edgeTree(h);
  QuantisedLevels q(t.edges.size());
  for (std::size_t j = 0; j < q.size(); ++j) q[j].assign(3 * t.edges[j], 0);
  q[0][0] = 1000;  // one coefficient at the root: ten planes of zerotrees elsewhere
  RangeEncoder enc;
  encodeZerotree(t, q, topPlane(q), enc);
  // 12 roots x 3 components x 10 planes of two decisions each, nearly all "no".
  EXPECT_LT(enc.finish().size(), 40u);
}

TEST(Zerotree, CutStreamsKnowATrueIntervalForEveryCoefficient) {
  const TriMesh base = shapes::byName("disc");
  const Hierarchy h(base.F, static_cast<int>(base.V.rows()), 4);
  const EdgeTree t = edgeTree(h);
  const QuantisedLevels q = randomLevels(t, 9);
  RangeEncoder enc;
  encodeZerotree(t, q, topPlane(q), enc);
  const std::vector<std::uint8_t> bytes = enc.finish();
  double previousError = 1e300;
  int previousPlanes = 0;
  for (std::size_t size = 0; size <= bytes.size(); size += std::max<std::size_t>(1, size / 8)) {
    RangeDecoder dec(bytes.data(), size);
    const ZerotreeState s = decodeZerotree(t, topPlane(q), dec);
    EXPECT_GE(s.planesDone, previousPlanes);
    previousPlanes = s.planesDone;
    const std::vector<std::vector<double>> values = reconstruct(s);
    double error = 0;
    for (std::size_t j = 0; j < q.size(); ++j)
      for (std::size_t i = 0; i < q[j].size(); ++i) {
        const std::int64_t mag = std::llabs(q[j][i]);
        if (s.plane[j][i] < 0) {
          // Insignificant: below every plane fully sorted.
          ASSERT_LT(mag, std::int64_t{1} << (topPlane(q) + 1 - s.planesDone)) << size;
        } else {
          const std::int64_t lo = std::int64_t{s.high[j][i]} << s.plane[j][i];
          ASSERT_GE(mag, lo) << size;
          ASSERT_LT(mag, lo + (std::int64_t{1} << s.plane[j][i])) << size;
          ASSERT_EQ(s.sign[j][i], q[j][i] < 0 ? -1 : 1);
        }
        const double d = values[j][i] - q[j][i];
        error += d * d;
      }
    EXPECT_LE(error, previousError * (1 + 1e-12)) << "size " << size;
    previousError = error;
  }
}

}  // namespace
}  // namespace osdmra
