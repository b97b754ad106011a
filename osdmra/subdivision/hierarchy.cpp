#include "osdmra/subdivision/hierarchy.h"

#include <opensubdiv/far/error.h>
#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <mutex>
#include <sstream>
#include <string>

#include "osdmra/base/error.h"

namespace osdmra {

namespace Far = OpenSubdiv::Far;
namespace Sdc = OpenSubdiv::Sdc;

const char* schemeName(Scheme s) {
  return s == Scheme::Loop ? "loop" : "linear";
}

Scheme parseScheme(const std::string& name) {
  if (name == "loop") return Scheme::Loop;
  if (name == "linear" || name == "polyhedral") return Scheme::Linear;
  throw Error("unknown scheme '" + name + "' (expected loop or linear)");
}

namespace {

// OpenSubdiv reports errors through a global callback; we keep the last message of
// this thread and turn a failed factory call into an Error.
thread_local std::string lastFarError;
void farErrorCallback(Far::ErrorType, const char* message) {
  lastFarError = message;
}
void farWarningCallback(const char*) {}
std::once_flag callbackOnce;

// A primvar that records (row, column, weight) instead of adding values: driving
// PrimvarRefiner with it yields the refinement matrix (or the limit stencils) itself.
struct Source {
  int index;
};
struct SourceArray {
  Source operator[](int i) const { return Source{i}; }
};

// The rows as PrimvarRefiner writes them: each row one run of entries after a
// Clear(). Copied straight into compressed rows, this takes half the time and memory
// of triplets, which setFromTriplets sorts into a column-major temporary and converts
// (P's rows are the finest level's vertices).
struct Runs {
  std::vector<int> row, start, col;  // per run: row, first entry; per entry: column
  std::vector<double> weight;
};
struct RunWriter {
  Runs* runs;
  int row;
  void Clear() {
    runs->row.push_back(row);
    runs->start.push_back(static_cast<int>(runs->col.size()));
  }
  void AddWithWeight(const Source& s, double w) {
    runs->col.push_back(s.index);
    runs->weight.push_back(w);
  }
  // Only reached for schemes with face-centre vertices (never for Loop on triangles),
  // which PrimvarRefiner instantiates regardless.
  void AddWithWeight(const RunWriter&, double) {
    throw Error("internal: unexpected face-vertex interpolation in a Loop refinement");
  }
};
struct RunWriterArray {
  Runs* runs;
  RunWriter operator[](int i) const { return RunWriter{runs, i}; }
};

// Sorts each (short) row of a compressed row-major matrix by column in place, summing
// repeated columns in the order they were written (as setFromTriplets sums them).
void sortRowsSummingRepeats(SparseMatrix& P) {
  int* outer = P.outerIndexPtr();
  int* col = P.innerIndexPtr();
  double* value = P.valuePtr();
  int nnz = 0;
  for (Eigen::Index r = 0; r < P.outerSize(); ++r) {
    const int begin = outer[r], end = outer[r + 1];
    for (int i = begin + 1; i < end; ++i) {  // stable insertion sort: short rows
      const int c = col[i];
      const double w = value[i];
      int k = i;
      for (; k > begin && col[k - 1] > c; --k) {
        col[k] = col[k - 1];
        value[k] = value[k - 1];
      }
      col[k] = c;
      value[k] = w;
    }
    outer[r] = nnz;
    for (int k = begin; k < end; ++k) {
      if (k > begin && col[k] == col[k - 1]) {
        value[nnz - 1] += value[k];
        continue;
      }
      col[nnz] = col[k];
      value[nnz++] = value[k];
    }
  }
  outer[P.outerSize()] = nnz;
  P.data().resize(nnz);
}

// The compressed row-major matrix of `runs`, each row's entries sorted by column and
// repeated columns summed in the order they came.
SparseMatrix fromRuns(int rows, int cols, const Runs& runs) {
  const int count = static_cast<int>(runs.row.size()), total = static_cast<int>(runs.col.size());
  const auto end = [&](int b) { return b + 1 < count ? runs.start[b + 1] : total; };
  std::vector<int> length(static_cast<std::size_t>(rows) + 1, 0);
  for (int b = 0; b < count; ++b) length[runs.row[b] + 1] += end(b) - runs.start[b];
  SparseMatrix P(rows, cols);
  P.resizeNonZeros(total);
  int* outer = P.outerIndexPtr();
  outer[0] = 0;
  for (int r = 0; r < rows; ++r) outer[r + 1] = outer[r] + length[r + 1];
  std::vector<int> fill(outer, outer + rows);
  for (int b = 0; b < count; ++b)
    for (int k = runs.start[b]; k < end(b); ++k) {
      const int at = fill[runs.row[b]]++;
      P.innerIndexPtr()[at] = runs.col[k];
      P.valuePtr()[at] = runs.weight[k];
    }
  sortRowsSummingRepeats(P);
  return P;
}

// One level's edges and, per face, its edges: face f's edge i joins its corners i and
// i + 1, as in OpenSubdiv's Vtr levels.
using Edges = std::vector<std::array<int, 2>>;
using FaceEdges = Connectivity::FaceEdgeList;

}  // namespace

struct Hierarchy::Impl {
  std::vector<Faces> faces;
  std::vector<int> numVertices;
  std::vector<Edges> edges;          // per level below the finest: OpenSubdiv's edges
  std::vector<FaceEdges> faceEdges;  // the same, for a manifold base (split by osdmra)
  std::vector<SparseMatrix> P[2];    // [Loop, Linear] per level
  // The refinement matrices are extracted on first use (refinement()), and the refiner
  // freed then: a decoder needs the faces and edges at once and the matrices only on
  // the thread that builds its filter bank.
  std::optional<Scheme> only;
  // Kept for a non-manifold base only, whose Loop matrices come from PrimvarRefiner.
  std::unique_ptr<Far::TopologyRefiner> refiner;
  mutable std::once_flag matricesOnce;
  void splitLevels(const Far::TopologyLevel& base, int levels);
  void refineWithOpenSubdiv(std::unique_ptr<Far::TopologyRefiner> R, int levels);
  void extractMatrices();
  // Connectivity is built on first use: analysis never walks the finest level.
  mutable std::vector<std::unique_ptr<Connectivity>> conn;
  mutable std::vector<std::once_flag> connOnce;
};

namespace {

// An unrefined Loop refiner over a triangle mesh, with osdmra's boundary rule;
// OpenSubdiv's complaints become an Error about `what`.
std::unique_ptr<Far::TopologyRefiner> createLoopRefiner(const Faces& F, int numVertices,
                                                        const std::string& what) {
  std::call_once(callbackOnce, [] {
    Far::SetErrorCallback(farErrorCallback);
    Far::SetWarningCallback(farWarningCallback);
  });
  std::vector<int> vertsPerFace(F.rows(), 3);
  Far::TopologyDescriptor desc;
  desc.numVertices = numVertices;
  desc.numFaces = static_cast<int>(F.rows());
  desc.numVertsPerFace = vertsPerFace.data();
  desc.vertIndicesPerFace = F.data();
  Sdc::Options options;
  options.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_EDGE_ONLY);
  using Factory = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;
  lastFarError.clear();
  std::unique_ptr<Far::TopologyRefiner> refiner(
      Factory::Create(desc, Factory::Options(Sdc::SCHEME_LOOP, options)));
  if (!refiner) throw Error("OpenSubdiv rejected " + what + ": " + lastFarError);
  return refiner;
}

// Loop's P^{j+1} from OpenSubdiv's interpolation with the recording primvar.
SparseMatrix extractLoopRefinement(const Far::TopologyRefiner& R, int j) {
  const int rows = R.GetLevel(j + 1).GetNumVertices(), cols = R.GetLevel(j).GetNumVertices();
  Runs runs;
  runs.col.reserve(static_cast<std::size_t>(rows) * 6);
  runs.weight.reserve(static_cast<std::size_t>(rows) * 6);
  runs.row.reserve(rows);
  runs.start.reserve(rows);
  SourceArray src;
  RunWriterArray dst{&runs};
  Far::PrimvarRefinerReal<double>(R).Interpolate(j + 1, src, dst);
  return fromRuns(rows, cols, runs);
}

// Loop's vertex mask on a vertex of `valence` faces by OpenSubdiv's smooth rule
// (sdc/loopScheme.h, assignSmoothMaskForVertex), evaluated in the same order, so the
// weights are the same doubles: {edge weight, vertex weight}.
std::array<double, 2> smoothVertexWeights(int valence) {
  if (valence == 6) return {0.0625, 0.625};
  const double d = valence, inv = 1.0 / d;
  const double beta = 0.25 * std::cos(M_PI * 2.0 * inv) + 0.375;
  const double e = (0.625 - beta * beta) * inv;
  return {e, 1.0 - e * d};
}

// Level j+1's faces, edges and face edges from level j's, numbered as OpenSubdiv's
// uniform triangle split numbers them (vtr/refinement.cpp, populateParentChildIndices;
// vtr/triRefinement.cpp): child vertices of vertices first (v), then of edges (n + e);
// face f's children 4f .. 4f + 3; child edges of faces first (3f + i, the inner edge
// across corner i), then of edges (3F + 2e + k, from the midpoint to end k). The test
// Hierarchy.OwnSplitIsOpenSubdivs holds it to OpenSubdiv's refiner, level by level.
void splitLevel(int n, const Faces& F, const Edges& E, const FaceEdges& FE, Faces& childF,
                Edges* childE, FaceEdges* childFE) {
  const int numFaces = static_cast<int>(F.rows()), numEdges = static_cast<int>(E.size());
  childF.resize(4 * static_cast<Eigen::Index>(numFaces), 3);
  for (int f = 0; f < numFaces; ++f) {
    const int v0 = F(f, 0), v1 = F(f, 1), v2 = F(f, 2);
    const int m0 = n + FE[f][0], m1 = n + FE[f][1], m2 = n + FE[f][2];
    childF.row(4 * f) << v0, m0, m2;
    childF.row(4 * f + 1) << m0, v1, m1;
    childF.row(4 * f + 2) << m2, m1, v2;
    childF.row(4 * f + 3) << m1, m2, m0;
  }
  if (!childE) return;
  const int edgeBase = 3 * numFaces;
  childE->resize(static_cast<std::size_t>(edgeBase) + 2 * static_cast<std::size_t>(numEdges));
  childFE->resize(4 * static_cast<std::size_t>(numFaces));
  Edges& cE = *childE;
  FaceEdges& cFE = *childFE;
  for (int f = 0; f < numFaces; ++f) {
    const int m0 = n + FE[f][0], m1 = n + FE[f][1], m2 = n + FE[f][2];
    cE[3 * f] = {m0, m2};
    cE[3 * f + 1] = {m1, m0};
    cE[3 * f + 2] = {m2, m1};
    // Half k of parent edge i, k counted from the face's corner i along the face.
    int half[3][2];
    for (int i = 0; i < 3; ++i) {
      const std::array<int, 2>& ends = E[FE[f][i]];
      const int reversed = ends[0] != ends[1] && F(f, i) != ends[0];
      half[i][0] = edgeBase + 2 * FE[f][i] + reversed;
      half[i][1] = edgeBase + 2 * FE[f][i] + 1 - reversed;
    }
    cFE[4 * f] = {half[0][0], 3 * f, half[2][1]};
    cFE[4 * f + 1] = {half[0][1], half[1][0], 3 * f + 1};
    cFE[4 * f + 2] = {3 * f + 2, half[1][1], half[2][0]};
    cFE[4 * f + 3] = {3 * f + 2, 3 * f, 3 * f + 1};
  }
  for (int e = 0; e < numEdges; ++e) {
    cE[edgeBase + 2 * e] = {n + e, E[e][0]};
    cE[edgeBase + 2 * e + 1] = {n + e, E[e][1]};
  }
}

// The vertex rows of Loop's P^{j+1} on a manifold level (outer already set): the
// vertex and each neighbour with the weights of its rule. Written column by column,
// which leaves every row's columns ascending (a transposition), with no sort: each
// neighbour is listed by its edge into the neighbour's column bucket, and the buckets
// are then read in column order.
void writeVertexRows(int n, const Edges& E, const std::vector<std::array<int, 2>>& opposite,
                     const std::vector<int>& degree, const std::vector<int>& boundaryEdges,
                     SparseMatrix& P) {
  const int* outer = P.outerIndexPtr();
  // Column w's bucket lists (row, weight) for w itself and each neighbour's row: the
  // pattern is symmetric, so bucket w has as many entries as row w.
  std::vector<int> bucketRow(outer[n]), fill(outer, outer + n);
  std::vector<double> bucketWeight(outer[n]), neighbourWeight(n);
  for (int v = 0; v < n; ++v) {
    const std::array<double, 2> w =
        boundaryEdges[v] ? std::array<double, 2>{0.125, 0.75} : smoothVertexWeights(degree[v]);
    neighbourWeight[v] = w[0];
    bucketRow[fill[v]] = v;
    bucketWeight[fill[v]++] = w[1];
  }
  for (std::size_t e = 0; e < E.size(); ++e) {
    const bool boundary = opposite[e][1] < 0;
    for (int k = 0; k < 2; ++k) {  // row E[e][k], column E[e][1 - k]
      const int v = E[e][k], w = E[e][1 - k];
      bucketRow[fill[w]] = v;
      // A crease rule weights its boundary neighbours only; OpenSubdiv stores the rest, 0.
      bucketWeight[fill[w]++] = boundaryEdges[v] && !boundary ? 0.0 : neighbourWeight[v];
    }
  }
  std::copy(outer, outer + n, fill.begin());
  int* col = P.innerIndexPtr();
  double* value = P.valuePtr();
  for (int w = 0; w < n; ++w)
    for (int k = outer[w]; k < outer[w + 1]; ++k) {
      const int v = bucketRow[k];
      col[fill[v]] = w;
      value[fill[v]++] = bucketWeight[k];
    }
}

// Loop's P^{j+1} of a manifold level, written from its topology with the masks of
// OpenSubdiv's Loop scheme (sdc/loopScheme.h) for the rules such a level has with
// infinitely sharp boundary edges: interior vertices Loop's beta (smooth), boundary
// vertices 3/4 and 1/8 on their two boundary neighbours (crease; OpenSubdiv also
// stores the other neighbours, with 0), interior edges 3/8, 3/8, 1/8, 1/8, boundary
// edges 1/2, 1/2. A manifold level's edges join distinct pairs of vertices, so each
// vertex row's columns are distinct and the rows written in column order are
// OpenSubdiv's matrix bit for bit (Hierarchy.LoopRefinementIsOpenSubdivsBitForBit) at a fraction
// of the cost of driving PrimvarRefiner.
SparseMatrix loopRefinementFromTopology(int n, const Faces& F, const Edges& E,
                                        const FaceEdges& FE) {
  const int numEdges = static_cast<int>(E.size());
  std::vector<std::array<int, 2>> opposite(numEdges, {-1, -1});
  for (std::size_t f = 0; f < FE.size(); ++f)
    for (int i = 0; i < 3; ++i) {
      std::array<int, 2>& o = opposite[FE[f][i]];
      o[o[0] < 0 ? 0 : 1] = F(static_cast<Eigen::Index>(f), (i + 2) % 3);
    }
  std::vector<int> degree(n, 0), boundaryEdges(n, 0);
  for (int e = 0; e < numEdges; ++e)
    for (int end : E[e]) {
      ++degree[end];
      if (opposite[e][1] < 0) ++boundaryEdges[end];
    }
  // An edge's row holds 4 columns (2 on a boundary; 3 where both faces have the same
  // third corner, whose weights add up as OpenSubdiv's do).
  const auto edgeRowSize = [&](int e) {
    return opposite[e][1] < 0 ? 2 : opposite[e][0] == opposite[e][1] ? 3 : 4;
  };
  SparseMatrix P(n + numEdges, n);
  int* outer = P.outerIndexPtr();
  outer[0] = 0;
  for (int v = 0; v < n; ++v) outer[v + 1] = outer[v] + 1 + degree[v];
  for (int e = 0; e < numEdges; ++e) outer[n + e + 1] = outer[n + e] + edgeRowSize(e);
  P.resizeNonZeros(outer[n + numEdges]);
  writeVertexRows(n, E, opposite, degree, boundaryEdges, P);
  int* col = P.innerIndexPtr();
  double* value = P.valuePtr();
  for (int e = 0; e < numEdges; ++e) {
    int k = outer[n + e];
    const auto put = [&](int c, double w) {
      col[k] = c;
      value[k++] = w;
    };
    const int a = std::min(E[e][0], E[e][1]), b = std::max(E[e][0], E[e][1]);
    if (opposite[e][1] < 0) {
      put(a, 0.5);
      put(b, 0.5);
      continue;
    }
    const int c = std::min(opposite[e][0], opposite[e][1]),
              d = std::max(opposite[e][0], opposite[e][1]);
    // Two sorted pairs merged: the ends (3/8) and the third corners (1/8), distinct.
    const int ends[2] = {a, b}, corners[2] = {c, d};
    int i = 0, m = 0;
    while (i < 2 || m < 2) {
      if (m == 2 || (i < 2 && ends[i] < corners[m]))
        put(ends[i++], 0.375);
      else if (k > outer[n + e] && col[k - 1] == corners[m])
        value[k - 1] += 0.125, ++m;
      else
        put(corners[m++], 0.125);
    }
  }
  return P;
}

// Whether osdmra's split and Loop rules cover this base: manifold, every vertex in a face.
bool isManifold(const Far::TopologyLevel& L) {
  for (int v = 0; v < L.GetNumVertices(); ++v)
    if (L.IsVertexNonManifold(v) || L.GetVertexFaces(v).size() == 0) return false;
  for (int e = 0; e < L.GetNumEdges(); ++e)
    if (L.IsEdgeNonManifold(e)) return false;
  return true;
}

// P^{j+1} of the polyhedral scheme, written from the edges: vertex v of level j keeps
// its position (row v) and edge e's new vertex n + e is the midpoint of its ends, as
// OpenSubdiv's varying interpolation gives (the ordering the constructor checks), at a
// fraction of its cost: a decoder of a polyhedral stream never runs PrimvarRefiner.
SparseMatrix linearRefinement(int n, const std::vector<std::array<int, 2>>& edges) {
  const int rows = n + static_cast<int>(edges.size());
  SparseMatrix P(rows, n);
  P.resizeNonZeros(n + 2 * static_cast<Eigen::Index>(edges.size()));
  int* outer = P.outerIndexPtr();
  int* col = P.innerIndexPtr();
  double* value = P.valuePtr();
  int k = 0;
  for (int v = 0; v < n; ++v) {
    outer[v] = k;
    col[k] = v;
    value[k++] = 1.0;
  }
  for (std::size_t e = 0; e < edges.size(); ++e) {
    outer[n + e] = k;
    for (int end : {std::min(edges[e][0], edges[e][1]), std::max(edges[e][0], edges[e][1])}) {
      col[k] = end;
      value[k++] = 0.5;
    }
  }
  outer[rows] = k;
  return P;
}

}  // namespace

Hierarchy::Hierarchy(const Faces& baseFaces, int numBaseVertices, int levels,
                     std::optional<Scheme> only)
    : impl_(std::make_unique<Impl>()) {
  if (levels < 0 || levels > 15)
    throw Error("levels must be in 0..15, got " + std::to_string(levels));
  if (baseFaces.rows() == 0) throw Error("the base mesh has no faces");
  std::unique_ptr<Far::TopologyRefiner> refiner =
      createLoopRefiner(baseFaces, numBaseVertices, "the base mesh");
  impl_->only = only;
  if (isManifold(refiner->GetLevel(0)))
    impl_->splitLevels(refiner->GetLevel(0), levels);
  else
    impl_->refineWithOpenSubdiv(std::move(refiner), levels);
  impl_->conn.resize(levels + 1);
  impl_->connOnce = std::vector<std::once_flag>(levels + 1);
}

// A manifold base is split by splitLevel, OpenSubdiv's numbering without its full
// topology of every level: the faces, edges and face edges osdmra reads, in a fraction
// of the time.
void Hierarchy::Impl::splitLevels(const Far::TopologyLevel& L, int levels) {
  Faces F(L.GetNumFaces(), 3);
  FaceEdges FE(L.GetNumFaces());
  for (int f = 0; f < L.GetNumFaces(); ++f) {
    const auto fv = L.GetFaceVertices(f), fe = L.GetFaceEdges(f);
    for (int i = 0; i < 3; ++i) {
      F(f, i) = fv[i];
      FE[f][i] = fe[i];
    }
  }
  Edges E(L.GetNumEdges());
  for (int e = 0; e < L.GetNumEdges(); ++e)
    E[e] = {L.GetEdgeVertices(e)[0], L.GetEdgeVertices(e)[1]};
  numVertices.push_back(L.GetNumVertices());
  for (int j = 0; j < levels; ++j) {
    Faces childF;
    Edges childE;
    FaceEdges childFE;
    const bool last = j + 1 == levels;  // its edges are never read
    splitLevel(numVertices[j], F, E, FE, childF, last ? nullptr : &childE,
               last ? nullptr : &childFE);
    numVertices.push_back(numVertices[j] + static_cast<int>(E.size()));
    faces.push_back(std::move(F));
    edges.push_back(std::move(E));
    faceEdges.push_back(std::move(FE));
    F = std::move(childF);
    E = std::move(childE);
    FE = std::move(childFE);
  }
  faces.push_back(std::move(F));
}

// A non-manifold base goes through OpenSubdiv's refiner, whose index conventions (the
// file comment's) are checked here; PrimvarRefiner gives its Loop matrices.
void Hierarchy::Impl::refineWithOpenSubdiv(std::unique_ptr<Far::TopologyRefiner> R, int levels) {
  if (levels > 0) {
    Far::TopologyRefiner::UniformOptions uniform(levels);
    // The last level needs its faces only: its edges and adjacency are never read.
    uniform.fullTopologyInLastLevel = false;
    R->RefineUniform(uniform);
  }
  for (int j = 0; j <= levels; ++j) {
    const Far::TopologyLevel& L = R->GetLevel(j);
    Faces F(L.GetNumFaces(), 3);
    for (int f = 0; f < L.GetNumFaces(); ++f) {
      auto fv = L.GetFaceVertices(f);
      for (int i = 0; i < 3; ++i) F(f, i) = fv[i];
    }
    if (j < levels) {
      const int n = L.GetNumVertices();
      for (int v = 0; v < n; ++v)
        if (L.GetVertexChildVertex(v) != v)
          throw Error("OpenSubdiv vertex ordering is not vertices-first at level " +
                      std::to_string(j));
      for (int e = 0; e < L.GetNumEdges(); ++e)
        if (L.GetEdgeChildVertex(e) != n + e)
          throw Error("OpenSubdiv edge-vertex ordering unexpected at level " + std::to_string(j));
      for (int f = 0; f < L.GetNumFaces(); ++f) {
        auto cf = L.GetFaceChildFaces(f);
        for (int i = 0; i < cf.size(); ++i)
          if (cf[i] != 4 * f + i)
            throw Error("OpenSubdiv child-face ordering unexpected at level " + std::to_string(j));
      }
      Edges E(L.GetNumEdges());
      for (int e = 0; e < L.GetNumEdges(); ++e) {
        auto ev = L.GetEdgeVertices(e);
        E[e] = {ev[0], ev[1]};
      }
      edges.push_back(std::move(E));
    }
    numVertices.push_back(L.GetNumVertices());
    faces.push_back(std::move(F));
  }
  if (only != Scheme::Linear) refiner = std::move(R);  // linearRefinement needs none
}

void Hierarchy::Impl::extractMatrices() {
  const int J = static_cast<int>(faces.size()) - 1;
  // Swapped into place: Eigen 3.4's SparseMatrix has no move constructor, and a copy
  // of every level's matrix cost as much as writing it.
  std::vector<SparseMatrix> extracted[2];
  for (Scheme s : {Scheme::Loop, Scheme::Linear}) {
    std::vector<SparseMatrix>& out = extracted[s == Scheme::Loop ? 0 : 1];
    out.resize(J);
    for (int j = 0; j < J && (!only || *only == s); ++j) {
      SparseMatrix Pj =
          s == Scheme::Linear ? linearRefinement(numVertices[j], edges[j])
          : refiner           ? extractLoopRefinement(*refiner, j)
                    : loopRefinementFromTopology(numVertices[j], faces[j], edges[j], faceEdges[j]);
      out[j].swap(Pj);
    }
  }
  P[0].swap(extracted[0]);
  P[1].swap(extracted[1]);
  refiner.reset();
}

Hierarchy::~Hierarchy() = default;
Hierarchy::Hierarchy(Hierarchy&&) noexcept = default;
Hierarchy& Hierarchy::operator=(Hierarchy&&) noexcept = default;

int Hierarchy::levels() const {
  return static_cast<int>(impl_->faces.size()) - 1;
}
int Hierarchy::numVertices(int j) const {
  return impl_->numVertices[j];
}
int Hierarchy::numFaces(int j) const {
  return static_cast<int>(impl_->faces[j].rows());
}
const Faces& Hierarchy::faces(int j) const {
  return impl_->faces[j];
}

const Connectivity& Hierarchy::connectivity(int j) const {
  std::call_once(impl_->connOnce[j], [&] {
    const int n = impl_->numVertices[j];
    // Below the finest level a split hierarchy knows each face's edges.
    impl_->conn[j] = j < static_cast<int>(impl_->faceEdges.size())
                         ? std::make_unique<Connectivity>(impl_->faces[j], n, impl_->faceEdges[j],
                                                          static_cast<int>(impl_->edges[j].size()))
                         : std::make_unique<Connectivity>(impl_->faces[j], n);
  });
  return *impl_->conn[j];
}

const Connectivity::FaceEdgeList* Hierarchy::faceEdges(int j) const {
  return j < static_cast<int>(impl_->faceEdges.size()) ? &impl_->faceEdges[j] : nullptr;
}

std::array<int, 2> Hierarchy::parentEdge(int j, int e) const {
  return impl_->edges[j][e];
}

int Hierarchy::midpoint(int j, int a, int b) const {
  // The child faces of face f = (v0, v1, v2) are (v0, m0, m2), (m0, v1, m1), ...:
  // the midpoint of the face's edge i is read off them.
  const Connectivity& c = connectivity(j);
  const Faces& fine = impl_->faces[j + 1];
  auto fromHalfedge = [&](int h) {
    const int f = h / 3, i = h % 3;
    return i == 0 ? fine(4 * f, 1) : i == 1 ? fine(4 * f + 1, 2) : fine(4 * f, 2);
  };
  for (int h : c.fan(a))
    if (c.to(h) == b) return fromHalfedge(h);
  for (int h : c.fan(b))
    if (c.to(h) == a) return fromHalfedge(h);
  return -1;
}

Hierarchy::LimitStencils Hierarchy::limitStencils(int level) const {
  if (level < 0 || level > levels()) throw Error("limitStencils: level out of range");
  const int n = numVertices(level);
  // A refiner over M^level itself, unrefined: its only level has full topology, which
  // Limit() needs, and the limit masks depend on the local topology alone.
  const std::unique_ptr<Far::TopologyRefiner> refiner =
      createLoopRefiner(faces(level), n, "level " + std::to_string(level));
  Runs position, tangent1, tangent2;
  SourceArray src;
  RunWriterArray dp{&position}, d1{&tangent1}, d2{&tangent2};
  Far::PrimvarRefinerReal<double>(*refiner).Limit(src, dp, d1, d2);
  if (!lastFarError.empty()) throw Error("OpenSubdiv limit evaluation failed: " + lastFarError);
  LimitStencils s;
  s.position = fromRuns(n, n, position);
  s.tangent1 = fromRuns(n, n, tangent1);
  s.tangent2 = fromRuns(n, n, tangent2);
  return s;
}

void Hierarchy::loopLimit(int level, const Points& c, Points& positions, Points& normals) const {
  if (c.rows() != numVertices(level))
    throw Error("loopLimit: expected " + std::to_string(numVertices(level)) +
                " control points at level " + std::to_string(level));
  const LimitStencils s = limitStencils(level);
  positions = s.position * c;
  normals = unitNormals(s.tangent1 * c, s.tangent2 * c);
}

Points unitNormals(const Points& du, const Points& dv) {
  Points normals(du.rows(), 3);
  for (Eigen::Index v = 0; v < du.rows(); ++v) {
    const Eigen::Vector3d nv = Eigen::Vector3d(du.row(v)).cross(Eigen::Vector3d(dv.row(v)));
    const double len = nv.norm();
    normals.row(v) = len > 0 ? Eigen::RowVector3d(nv / len) : Eigen::RowVector3d::Zero();
  }
  return normals;
}

void Hierarchy::prepareRefinement() const {
  std::call_once(impl_->matricesOnce, [this] { impl_->extractMatrices(); });
}

const SparseMatrix& Hierarchy::refinement(Scheme scheme, int j) const {
  if (j < 0 || j >= levels())
    throw Error("refinement level " + std::to_string(j) + " out of range 0.." +
                std::to_string(levels() - 1));
  prepareRefinement();
  const SparseMatrix& P = impl_->P[scheme == Scheme::Loop ? 0 : 1][j];
  if (P.rows() == 0)
    throw Error(std::string("this hierarchy was built without the ") + schemeName(scheme) +
                " refinement matrices");
  return P;
}

Faces Hierarchy::baseFacesFromCanonical(const Faces& finest, int levels) {
  const long long stride = 1LL << (2 * levels);
  if (levels < 0 || levels > 15) throw Error("levels must be in 0..15");
  if (finest.rows() == 0 || finest.rows() % stride != 0) {
    std::ostringstream os;
    os << "a mesh of " << finest.rows() << " faces cannot be " << levels
       << " uniform refinements in canonical order (the face count must be a multiple of 4^"
       << levels << ")";
    throw Error(os.str());
  }
  // Corner i of base face f is corner i of the level-J face reached by always taking
  // the child at corner i: child index i at every level.
  Faces base(finest.rows() / stride, 3);
  for (Eigen::Index f = 0; f < base.rows(); ++f)
    for (int i = 0; i < 3; ++i) {
      long long g = f;
      for (int l = 0; l < levels; ++l) g = 4 * g + i;
      base(f, i) = finest(g, i);
    }
  return base;
}

namespace {

// Vertex count of M^levels over `base`, from Euler's relations for a 1-to-4 split:
// n' = n + E, E' = 2E + 3F, F' = 4F. Returns -1 on overflow of int.
long long predictedVertices(const Faces& base, int n0, int levels) {
  const Connectivity c(base, n0);
  long long n = n0, e = c.numEdges(), f = base.rows();
  for (int j = 0; j < levels; ++j) {
    n += e;
    e = 2 * e + 3 * f;
    f *= 4;
  }
  return n;
}

// Base faces and vertex count if `finest` can be canonical at `levels`, else false.
bool canonicalBase(const Faces& finest, int numVertices, int levels, Faces& base, int& n0,
                   std::string& why) {
  if (finest.rows() == 0 || finest.rows() % (1LL << (2 * levels)) != 0) {
    why = "the face count " + std::to_string(finest.rows()) + " is not a multiple of 4^" +
          std::to_string(levels);
    return false;
  }
  base = Hierarchy::baseFacesFromCanonical(finest, levels);
  n0 = base.rows() ? base.maxCoeff() + 1 : 0;
  if (base.minCoeff() < 0 || n0 > numVertices) {
    why = "base face indices are out of range";
    return false;
  }
  std::vector<char> used(n0, 0);
  for (Eigen::Index i = 0; i < base.size(); ++i) used[base.data()[i]] = 1;
  for (int v = 0; v < n0; ++v)
    if (!used[v]) {
      why = "vertex " + std::to_string(v) + " is not a corner of the implied base mesh";
      return false;
    }
  const Connectivity c(base, n0);
  if (c.firstNonManifoldEdgeFace >= 0 || c.firstFlippedFace >= 0 || c.firstNonManifoldVertex >= 0) {
    why = "the implied base mesh is not a manifold";
    return false;
  }
  const long long expected = predictedVertices(base, n0, levels);
  if (expected != numVertices) {
    why = "the implied base mesh of " + std::to_string(base.rows()) + " faces gives " +
          std::to_string(expected) + " vertices at level " + std::to_string(levels) + ", not " +
          std::to_string(numVertices);
    return false;
  }
  return true;
}

}  // namespace

Hierarchy Hierarchy::fromCanonical(const Faces& finest, int numVertices, int levels) {
  if (levels < 0 || levels > 15)
    throw Error("levels must be in 0..15, got " + std::to_string(levels));
  Faces base;
  int n0 = 0;
  std::string why;
  if (!canonicalBase(finest, numVertices, levels, base, n0, why))
    throw Error("not in osdmra's canonical order for " + std::to_string(levels) +
                " levels: " + why);
  Hierarchy h(base, n0, levels);
  const Faces& F = h.faces(levels);
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    if (F.row(f) != finest.row(f)) {
      std::ostringstream os;
      os << "not in osdmra's canonical order for " << levels << " levels: face " << f << " is ("
         << finest(f, 0) << " " << finest(f, 1) << " " << finest(f, 2) << "), expected (" << F(f, 0)
         << " " << F(f, 1) << " " << F(f, 2) << ")";
      throw Error(os.str());
    }
  return h;
}

int Hierarchy::detectCanonicalLevels(const Faces& finest, int numVertices) {
  int J = 0;
  while (J < 15 && finest.rows() % (1LL << (2 * (J + 1))) == 0) ++J;
  for (; J > 0; --J) {
    Faces base;
    int n0 = 0;
    std::string why;
    if (!canonicalBase(finest, numVertices, J, base, n0, why)) continue;
    try {
      fromCanonical(finest, numVertices, J);
      return J;
    } catch (const Error&) {
    }
  }
  return 0;
}

}  // namespace osdmra
