// Hierarchy (hierarchy.h): level sizes, refinement rows, the index conventions
// checked against the faces themselves, and Loop limit evaluation.
#include <gtest/gtest.h>
#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>

#include <cmath>
#include <map>
#include <thread>

#include "osdmra/base/error.h"
#include "osdmra/mesh/mesh.h"
#include "osdmra/subdivision/hierarchy.h"
#include "osdmra/subdivision/shapes.h"
#include "support.h"

using namespace osdmra;
using namespace osdmra::test;

TEST(Hierarchy, OctahedronCounts) {
  Hierarchy h(shapes::octahedron().F, 6, 3);
  EXPECT_EQ(h.numVertices(3), 4 * 4 * 4 * 8 / 2 + 2);
  const auto& P = h.refinement(Scheme::Loop, 2);
  for (int r = 0; r < P.rows(); ++r) EXPECT_NEAR(P.row(r).sum(), 1.0, 1e-15);
}

// Index conventions of hierarchy.h, checked against the faces themselves.
TEST(Hierarchy, ChildFacesAndMidpoints) {
  const TriMesh base = shapes::slab(2);
  Hierarchy h(base.F, static_cast<int>(base.V.rows()), 2);
  for (int j = 0; j < 2; ++j) {
    const Faces& F = h.faces(j);
    const Faces& G = h.faces(j + 1);
    for (int f = 0; f < F.rows(); ++f) {
      const int m0 = h.midpoint(j, F(f, 0), F(f, 1)), m1 = h.midpoint(j, F(f, 1), F(f, 2)),
                m2 = h.midpoint(j, F(f, 2), F(f, 0));
      EXPECT_EQ(G.row(4 * f), Eigen::RowVector3i(F(f, 0), m0, m2));
      EXPECT_EQ(G.row(4 * f + 1), Eigen::RowVector3i(m0, F(f, 1), m1));
      EXPECT_EQ(G.row(4 * f + 2), Eigen::RowVector3i(m2, m1, F(f, 2)));
      EXPECT_EQ(G.row(4 * f + 3), Eigen::RowVector3i(m1, m2, m0));
      for (int m : {m0, m1, m2}) {
        ASSERT_GE(m, h.numVertices(j));
        const auto [a, b] = h.parentEdge(j, m - h.numVertices(j));
        EXPECT_EQ(h.midpoint(j, a, b), m);
      }
    }
  }
  // Canonical order round trip: the finest faces give back the base and the levels.
  EXPECT_EQ(Hierarchy::detectCanonicalLevels(h.faces(2), h.numVertices(2)), 2);
  EXPECT_TRUE(Hierarchy::baseFacesFromCanonical(h.faces(2), 2) == base.F);
}

// Loop limit evaluation through OpenSubdiv: the limit of a refined control mesh is
// the same surface, the regular limit mask is (1/2, 1/12 x 6), normals are unit.
TEST(Hierarchy, LoopLimitPositionsAndNormals) {
  for (const char* name : {"icosahedron", "disc", "torus"}) {
    SCOPED_TRACE(name);
    const TriMesh base = shapes::byName(name);
    Hierarchy h(base.F, static_cast<int>(base.V.rows()), 3);
    const TriMesh s2 = subdivide(base, 2, Scheme::Loop, 0.05, 4);
    Points p2, n2, p3, n3;
    h.loopLimit(2, s2.V, p2, n2);
    const Points c3 = h.refinement(Scheme::Loop, 2) * s2.V;
    h.loopLimit(3, c3, p3, n3);
    // Old vertices keep their index and their limit point and normal.
    EXPECT_LT((p3.topRows(p2.rows()) - p2).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_LT((n3.topRows(n2.rows()) - n2).cwiseAbs().maxCoeff(), 1e-10);
    for (int v = 0; v < n3.rows(); ++v) EXPECT_NEAR(n3.row(v).norm(), 1.0, 1e-12);
    const Connectivity& c = h.connectivity(3);
    for (int v = 0; v < c.numVertices(); ++v) {
      if (c.isBoundaryVertex(v) || c.valence(v) != 6) continue;
      Eigen::RowVector3d expected = 0.5 * c3.row(v);
      for (int w : c.ring(v)) expected += c3.row(w) / 12.0;
      EXPECT_LT((p3.row(v) - expected).cwiseAbs().maxCoeff(), 1e-12);
    }
  }
  // Outward normals on a closed convex shape.
  const TriMesh ico = shapes::icosahedron();
  Hierarchy h(ico.F, 12, 1);
  Points p, n;
  h.loopLimit(0, ico.V, p, n);
  for (int v = 0; v < 12; ++v) EXPECT_GT(n.row(v).dot(p.row(v)), 0.0);
}

// Every row of P^{j+1} is Loop's closed-form rule (or the linear one), stored in
// compressed rows with ascending columns: vertex rows beta = (5/8 - (3/8 + cos(2 pi /
// k) / 4)^2) / k on each of k neighbours (1/8, 3/4, 1/8 on a boundary), edge rows 3/8
// on the ends and 1/8 on the opposite vertices (1/2, 1/2 on a boundary); linear rows
// 1 and 1/2, 1/2 (other columns, if stored, hold 0). A hierarchy built for one scheme holds the
// same matrices for it and refuses the other.
TEST(Hierarchy, RefinementRowsAreTheClosedFormRules) {
  const double pi = std::acos(-1.0);
  for (const char* name : {"valences", "disc"}) {
    SCOPED_TRACE(name);
    const TriMesh base = shapes::byName(name);
    const int n0 = static_cast<int>(base.V.rows());
    const Hierarchy h(base.F, n0, 2);
    for (Scheme s : {Scheme::Loop, Scheme::Linear}) {
      const Hierarchy only(base.F, n0, 2, s);
      EXPECT_THROW(only.refinement(s == Scheme::Loop ? Scheme::Linear : Scheme::Loop, 0), Error);
      for (int j = 0; j < 2; ++j) {
        const SparseMatrix& P = h.refinement(s, j);
        ASSERT_TRUE(P.isCompressed());
        EXPECT_EQ(Eigen::MatrixXd(P), Eigen::MatrixXd(only.refinement(s, j)));
        const Connectivity& c = h.connectivity(j);
        const int n = h.numVertices(j);
        for (int r = 0; r < P.rows(); ++r) {
          std::map<int, double> expected;
          if (r < n && s == Scheme::Linear) {
            expected[r] = 1;
          } else if (r < n && c.isBoundaryVertex(r)) {
            const IndexSpan ring = c.ring(r);
            expected = {{r, 0.75}, {ring[0], 0.125}, {ring[ring.size() - 1], 0.125}};
          } else if (r < n) {
            const int k = c.valence(r);
            const double t = 0.375 + 0.25 * std::cos(2 * pi / k), beta = (0.625 - t * t) / k;
            expected[r] = 1 - k * beta;
            for (int w : c.ring(r)) expected[w] = beta;
          } else {
            const auto [a, b] = h.parentEdge(j, r - n);
            const bool interior = s == Scheme::Loop && !c.isBoundaryEdge(c.findEdge(a, b));
            expected = {{a, interior ? 0.375 : 0.5}, {b, interior ? 0.375 : 0.5}};
            if (interior)  // the third corners of the edge's two faces
              for (int hh :
                   {c.edgeHalfedge(c.findEdge(a, b)), c.twin(c.edgeHalfedge(c.findEdge(a, b)))})
                expected[c.from(Connectivity::prev(hh))] = 0.125;
          }
          std::map<int, double> stored;
          int previous = -1;
          for (SparseMatrix::InnerIterator it(P, r); it; ++it) {
            EXPECT_GT(it.col(), previous) << "row " << r;
            previous = static_cast<int>(it.col());
            stored[static_cast<int>(it.col())] = it.value();
          }
          // OpenSubdiv's boundary rule also lists the interior neighbours, with 0.
          for (const auto& [col, value] : stored)
            if (!expected.count(col)) {
              EXPECT_EQ(value, 0.0) << "row " << r << " column " << col;
            }
          for (const auto& [col, value] : expected) {
            ASSERT_TRUE(stored.count(col)) << "row " << r << " column " << col;
            EXPECT_NEAR(stored[col], value, 1e-15) << "row " << r << " column " << col;
          }
        }
      }
    }
  }
}

namespace {

// A primvar that records each row's weights, in the order PrimvarRefiner adds them.
struct Recorded {
  std::vector<std::pair<int, double>>* row;
  void Clear() { row->clear(); }
  void AddWithWeight(const Recorded& src, double w) { row->emplace_back(src.index, w); }
  int index = -1;
};

// OpenSubdiv's refiner over `base` (boundary edges sharp, as the hierarchy's), refined
// `levels` times with full topology.
std::unique_ptr<OpenSubdiv::Far::TopologyRefiner> refinerOf(const TriMesh& base, int levels) {
  namespace Far = OpenSubdiv::Far;
  namespace Sdc = OpenSubdiv::Sdc;
  std::vector<int> sizes(base.F.rows(), 3);
  Far::TopologyDescriptor desc;
  desc.numVertices = static_cast<int>(base.V.rows());
  desc.numFaces = static_cast<int>(base.F.rows());
  desc.numVertsPerFace = sizes.data();
  desc.vertIndicesPerFace = base.F.data();
  Sdc::Options options;
  options.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_EDGE_ONLY);
  using Factory = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;
  std::unique_ptr<Far::TopologyRefiner> R(
      Factory::Create(desc, Factory::Options(Sdc::SCHEME_LOOP, options)));
  R->RefineUniform(Far::TopologyRefiner::UniformOptions(levels));
  return R;
}

// OpenSubdiv's own Loop refinement matrices of `base` (PrimvarRefiner, boundary edges
// sharp as in the hierarchy): per level, per row, (column, weight) in column order with
// repeats summed in the order they came, as a compressed row would hold them.
std::vector<std::vector<std::vector<std::pair<int, double>>>> primvarLoopRows(const TriMesh& base,
                                                                              int levels) {
  const auto R = refinerOf(base, levels);
  std::vector<std::vector<std::vector<std::pair<int, double>>>> out;
  for (int j = 0; j < levels; ++j) {
    std::vector<std::vector<std::pair<int, double>>> rows(R->GetLevel(j + 1).GetNumVertices());
    std::vector<Recorded> src(R->GetLevel(j).GetNumVertices()), dst(rows.size());
    for (std::size_t v = 0; v < src.size(); ++v) src[v].index = static_cast<int>(v);
    for (std::size_t r = 0; r < rows.size(); ++r) dst[r].row = &rows[r];
    OpenSubdiv::Far::PrimvarRefinerReal<double>(*R).Interpolate(j + 1, src, dst);
    for (auto& row : rows) {
      std::stable_sort(row.begin(), row.end(),
                       [](const auto& a, const auto& b) { return a.first < b.first; });
      std::vector<std::pair<int, double>> summed;
      for (const auto& [c, w] : row)
        if (!summed.empty() && summed.back().first == c)
          summed.back().second += w;
        else
          summed.emplace_back(c, w);
      row = std::move(summed);
    }
    out.push_back(std::move(rows));
  }
  return out;
}

// The shapes, a non-manifold base (two tetrahedra sharing a vertex) and one with a
// vertex in no face, which the hierarchy hands to OpenSubdiv's refiner instead.
std::vector<std::pair<std::string, TriMesh>> bases() {
  std::vector<std::pair<std::string, TriMesh>> all = shapes::all();
  const TriMesh t = shapes::tetrahedron();
  TriMesh bowtie;
  bowtie.V.resize(7, 3);
  bowtie.V << t.V, t.V.bottomRows(3) * -1.0;
  bowtie.F.resize(8, 3);
  bowtie.F.topRows(4) = t.F;
  for (int f = 0; f < 4; ++f)
    for (int i = 0; i < 3; ++i) bowtie.F(4 + f, i) = t.F(f, 2 - i) == 0 ? 0 : t.F(f, 2 - i) + 3;
  all.emplace_back("bowtie", bowtie);
  TriMesh isolated = shapes::octahedron();  // and a vertex in no face
  isolated.V.conservativeResize(7, 3);
  isolated.V.row(6) << 0, 0, 0;
  all.emplace_back("isolated vertex", isolated);
  return all;
}

}  // namespace

// osdmra splits a manifold base itself (hierarchy.cpp, splitLevel) in OpenSubdiv's
// numbering: every level's faces and every edge with its ends in order are the
// refiner's, on closed shapes of every genus and open ones (and a non-manifold base's,
// which the refiner splits).
TEST(Hierarchy, OwnSplitIsOpenSubdivs) {
  for (const auto& [name, base] : bases()) {
    SCOPED_TRACE(name);
    const int levels = 4;
    const Hierarchy h(base.F, static_cast<int>(base.V.rows()), levels);
    const auto R = refinerOf(base, levels);
    for (int j = 0; j <= levels; ++j) {
      const OpenSubdiv::Far::TopologyLevel& L = R->GetLevel(j);
      ASSERT_EQ(h.numVertices(j), L.GetNumVertices());
      ASSERT_EQ(h.numFaces(j), L.GetNumFaces());
      for (int f = 0; f < L.GetNumFaces(); ++f)
        for (int i = 0; i < 3; ++i)
          ASSERT_EQ(h.faces(j)(f, i), L.GetFaceVertices(f)[i]) << "level " << j << " face " << f;
      if (j == levels) continue;
      ASSERT_EQ(h.numVertices(j + 1) - h.numVertices(j), L.GetNumEdges());
      for (int e = 0; e < L.GetNumEdges(); ++e) {
        const std::array<int, 2> ends{L.GetEdgeVertices(e)[0], L.GetEdgeVertices(e)[1]};
        ASSERT_EQ(h.parentEdge(j, e), ends) << "level " << j << " edge " << e;
      }
    }
  }
}

// A split hierarchy builds its levels' Connectivity from the face edges it knows: the
// same as built from the faces alone, at every level.
TEST(Hierarchy, ConnectivityOfEveryLevelIsTheGeneralOne) {
  for (const auto& [name, base] : bases()) {
    SCOPED_TRACE(name);
    const Hierarchy h(base.F, static_cast<int>(base.V.rows()), 3);
    for (int j = 0; j <= 3; ++j)
      expectSameConnectivity(h.connectivity(j), Connectivity(h.faces(j), h.numVertices(j)));
  }
}

// The Loop matrices are written from the rules (hierarchy.cpp), not by PrimvarRefiner:
// they are OpenSubdiv's own, bit for bit and entry for entry (the explicit zeros of its
// crease rule included), on closed shapes of every genus, open ones and low valences
// (and a non-manifold base's, which PrimvarRefiner writes).
TEST(Hierarchy, LoopRefinementIsOpenSubdivsBitForBit) {
  for (const auto& [name, base] : bases()) {
    SCOPED_TRACE(name);
    const int levels = 3;
    const Hierarchy h(base.F, static_cast<int>(base.V.rows()), levels, Scheme::Loop);
    const auto reference = primvarLoopRows(base, levels);
    for (int j = 0; j < levels; ++j) {
      const SparseMatrix& P = h.refinement(Scheme::Loop, j);
      ASSERT_EQ(P.rows(), static_cast<Eigen::Index>(reference[j].size()));
      for (Eigen::Index r = 0; r < P.rows(); ++r) {
        std::vector<std::pair<int, double>> stored;
        for (SparseMatrix::InnerIterator it(P, r); it; ++it)
          stored.emplace_back(static_cast<int>(it.col()), it.value());
        ASSERT_EQ(stored, reference[j][r]) << "level " << j << " row " << r;
      }
    }
  }
}

// The refinement matrices are extracted once, on first use, whichever thread asks first
// (a decoder asks from the thread that builds its filter bank while another decodes):
// the same matrices as a hierarchy asked on one thread, and only the scheme asked for.
TEST(Hierarchy, RefinementIsExtractedOnceWhicheverThreadAsks) {
  const TriMesh base = shapes::torus();
  const int n = static_cast<int>(base.V.rows());
  const Hierarchy alone(base.F, n, 3);
  for (int trial = 0; trial < 4; ++trial) {
    const Hierarchy shared(base.F, n, 3);
    std::thread other([&] { shared.prepareRefinement(); });
    const SparseMatrix& here = shared.refinement(Scheme::Loop, 2);
    other.join();
    EXPECT_EQ(SparseMatrix(here - alone.refinement(Scheme::Loop, 2)).norm(), 0.0);
    for (int j = 0; j < 3; ++j)
      for (Scheme s : {Scheme::Loop, Scheme::Linear}) {
        const SparseMatrix d = shared.refinement(s, j) - alone.refinement(s, j);
        EXPECT_EQ(d.norm(), 0.0);
      }
  }
  const Hierarchy linearOnly(base.F, n, 2, Scheme::Linear);
  EXPECT_EQ(linearOnly.refinement(Scheme::Linear, 1).rows(), linearOnly.numVertices(2));
  EXPECT_THROW(linearOnly.refinement(Scheme::Loop, 1), Error);
}
