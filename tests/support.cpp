#include "support.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <fstream>
#include <map>
#include <numeric>
#include <ostream>
#include <random>

#include "osdmra/base/error.h"
#include "osdmra/mesh/connectivity.h"

namespace osdmra::test {

namespace fs = std::filesystem;

// ---- Errors ------------------------------------------------------------------------

std::string errorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "expected an osdmra::Error, got another exception: " << e.what();
    return "";
  }
  ADD_FAILURE() << "expected an osdmra::Error, nothing was thrown";
  return "";
}

void expectContains(const std::string& message, std::initializer_list<std::string_view> parts) {
  for (std::string_view part : parts)
    EXPECT_NE(message.find(part), std::string::npos)
        << "message \"" << message << "\" lacks \"" << part << "\"";
}

// ---- Files -------------------------------------------------------------------------

TempDir::TempDir() {
  // Test processes run in parallel (one per test under ctest): the process id keeps
  // their directories apart, the counter those of one process. A directory of the
  // same name can only be a leftover of a dead process.
  static std::atomic<int> counter{0};
  path_ = fs::temp_directory_path() /
          ("osdmra_test_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
  fs::remove_all(path_);
  fs::create_directories(path_);
}

TempDir::~TempDir() {
  std::error_code ignored;
  fs::remove_all(path_, ignored);
}

std::string TempDir::file(const std::string& name) const {
  return (path_ / name).string();
}

std::string TempDir::write(const std::string& name, std::string_view bytes) const {
  const std::string p = file(name);
  std::ofstream out(p, std::ios::binary);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  return p;
}

std::vector<std::string> TempDir::entries() const {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(path_)) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

std::string readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// ---- Meshes ------------------------------------------------------------------------

TriMesh makeMesh(std::initializer_list<std::array<double, 3>> points,
                 std::initializer_list<std::array<int, 3>> faces) {
  TriMesh m;
  m.V.resize(static_cast<Eigen::Index>(points.size()), 3);
  m.F.resize(static_cast<Eigen::Index>(faces.size()), 3);
  Eigen::Index r = 0;
  for (const auto& p : points) m.V.row(r++) << p[0], p[1], p[2];
  r = 0;
  for (const auto& f : faces) m.F.row(r++) << f[0], f[1], f[2];
  return m;
}

TriMesh cornerTetrahedron() {
  return makeMesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}},
                  {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}});
}

TriMesh unitSquare(double z) {
  return makeMesh({{0, 0, z}, {1, 0, z}, {1, 1, z}, {0, 1, z}}, {{0, 1, 2}, {0, 2, 3}});
}

TriMesh unitCube() {
  TriMesh c;
  c.V.resize(8, 3);
  for (int i = 0; i < 8; ++i) c.V.row(i) << (i & 1), (i >> 1 & 1), (i >> 2 & 1);
  c.F.resize(12, 3);
  c.F << 0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4, 2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6,
      1, 3, 5, 3, 7, 5;
  return c;
}

double surfaceArea(const TriMesh& m) {
  double a = 0;
  for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
    const Eigen::Vector3d p = m.V.row(m.F(f, 0)), q = m.V.row(m.F(f, 1)), r = m.V.row(m.F(f, 2));
    a += 0.5 * (q - p).cross(r - p).norm();
  }
  return a;
}

namespace {

// Points on the 1/k lattice of the unit cube, each kept once (sides meeting at an edge
// share its points), and the mesh they make with `faces`.
class LatticePoints {
 public:
  explicit LatticePoints(int k) : k_(k) {}
  int operator()(const Eigen::RowVector3d& p) {
    const std::array<long, 3> key = {std::lround(p(0) * k_), std::lround(p(1) * k_),
                                     std::lround(p(2) * k_)};
    const auto [it, added] = index_.emplace(key, static_cast<int>(points_.size()));
    if (added) points_.push_back(p);
    return it->second;
  }
  TriMesh mesh(const std::vector<std::array<int, 3>>& faces) const {
    TriMesh m;
    m.V.resize(static_cast<Eigen::Index>(points_.size()), 3);
    for (std::size_t i = 0; i < points_.size(); ++i)
      m.V.row(static_cast<Eigen::Index>(i)) = points_[i];
    m.F.resize(static_cast<Eigen::Index>(faces.size()), 3);
    for (std::size_t f = 0; f < faces.size(); ++f)
      m.F.row(static_cast<Eigen::Index>(f)) << faces[f][0], faces[f][1], faces[f][2];
    return m;
  }

 private:
  int k_;
  std::map<std::array<long, 3>, int> index_;
  std::vector<Eigen::RowVector3d> points_;
};

// The loop of a square side with corners `corners`, k points along each edge.
std::vector<int> sideLoop(LatticePoints& vertex, const std::array<Eigen::RowVector3d, 4>& corners,
                          int k) {
  std::vector<int> loop;
  for (int c = 0; c < 4; ++c)
    for (int s = 0; s < k; ++s)
      loop.push_back(vertex(corners[c] + (corners[(c + 1) % 4] - corners[c]) * s / k));
  return loop;
}

}  // namespace

TriMesh fannedCube(int k) {
  LatticePoints vertex(k);
  std::vector<std::array<int, 3>> faces;
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side) {
      Eigen::RowVector3d o = Eigen::RowVector3d::Zero(), u = Eigen::RowVector3d::Zero(),
                         v = Eigen::RowVector3d::Zero();
      o(axis) = side;
      u((axis + 1) % 3) = 1;
      v((axis + 2) % 3) = 1;
      if (side == 0) std::swap(u, v);  // counter-clockwise seen from outside
      const std::vector<int> loop = sideLoop(vertex, {o, o + u, o + u + v, o + v}, k);
      const int n = static_cast<int>(loop.size());
      for (int i = 1; i + 1 < n; ++i)
        faces.push_back({loop[1], loop[(1 + i) % n], loop[(2 + i) % n]});
    }
  return vertex.mesh(faces);
}

TriMesh cubeWithATopFannedFromACorner(int n) {
  LatticePoints vertex(n);
  std::vector<std::array<int, 3>> faces;
  const Eigen::RowVector3d x(1, 0, 0), y(0, 1, 0), z(0, 0, 1), o(0, 0, 0);
  // Each grid spans u and v from its origin, counter-clockwise seen from outside.
  const std::array<std::array<Eigen::RowVector3d, 3>, 5> grids = {
      {{o, y, x}, {o, x, z}, {y, z, x}, {o, z, y}, {x, y, z}}};
  for (const auto& [origin, u, v] : grids)
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        auto at = [&](int a, int b) { return vertex(origin + (u * a + v * b) / n); };
        faces.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
        faces.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
      }
  const std::vector<int> loop = sideLoop(vertex, {z, z + x, z + x + y, z + y}, n);
  for (std::size_t i = 1; i + 1 < loop.size(); ++i)
    faces.push_back({loop[0], loop[i], loop[i + 1]});
  return vertex.mesh(faces);
}

TriMesh moebiusStrip(int n) {
  TriMesh m;
  m.V.resize(2 * n, 3);
  for (int i = 0; i < n; ++i) {
    const double a = 2 * M_PI * i / n, t = a / 2;
    for (int s = 0; s < 2; ++s) {
      const double w = s == 0 ? -0.3 : 0.3;
      m.V.row(2 * i + s) << (1 + w * std::cos(t)) * std::cos(a),
          (1 + w * std::cos(t)) * std::sin(a), w * std::sin(t);
    }
  }
  m.F.resize(2 * n, 3);
  for (int i = 0; i < n; ++i) {
    const int a0 = 2 * i, a1 = 2 * i + 1;
    // The last quad joins the strip's two sides crossed: the half twist.
    const int b0 = i + 1 < n ? 2 * i + 2 : 1, b1 = i + 1 < n ? 2 * i + 3 : 0;
    m.F.row(2 * i) << a0, b0, b1;
    m.F.row(2 * i + 1) << a0, b1, a1;
  }
  return m;
}

// ---- Orders ------------------------------------------------------------------------

namespace {

std::vector<int> permutation(int n, std::mt19937_64& rng) {
  std::vector<int> perm(static_cast<std::size_t>(n));
  std::iota(perm.begin(), perm.end(), 0);
  std::shuffle(perm.begin(), perm.end(), rng);
  return perm;
}

}  // namespace

void expectSameConnectivity(const Connectivity& a, const Connectivity& b) {
  ASSERT_EQ(a.numVertices(), b.numVertices());
  ASSERT_EQ(a.numFaces(), b.numFaces());
  ASSERT_EQ(a.numEdges(), b.numEdges());
  for (int h = 0; h < 3 * a.numFaces(); ++h) {
    ASSERT_EQ(a.twin(h), b.twin(h)) << "halfedge " << h;
    ASSERT_EQ(a.edge(h), b.edge(h)) << "halfedge " << h;
  }
  for (int e = 0; e < a.numEdges(); ++e) ASSERT_EQ(a.edgeHalfedge(e), b.edgeHalfedge(e));
  const auto list = [](IndexSpan s) { return std::vector<int>(s.begin(), s.end()); };
  for (int v = 0; v < a.numVertices(); ++v) {
    ASSERT_EQ(list(a.ring(v)), list(b.ring(v))) << "vertex " << v;
    ASSERT_EQ(list(a.fan(v)), list(b.fan(v))) << "vertex " << v;
    ASSERT_EQ(a.isBoundaryVertex(v), b.isBoundaryVertex(v)) << "vertex " << v;
    ASSERT_EQ(a.isManifoldVertex(v), b.isManifoldVertex(v)) << "vertex " << v;
  }
  EXPECT_EQ(a.firstNonManifoldEdgeFace, b.firstNonManifoldEdgeFace);
  EXPECT_EQ(a.firstFlippedFace, b.firstFlippedFace);
  EXPECT_EQ(a.firstNonManifoldVertex, b.firstNonManifoldVertex);
  EXPECT_EQ(a.firstIsolatedVertex, b.firstIsolatedVertex);
}

std::vector<int> randomPermutation(int n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  return permutation(n, rng);
}

TriMesh renumberVertices(const TriMesh& m, const std::vector<int>& newIndexOf) {
  TriMesh out;
  out.V.resize(m.V.rows(), 3);
  for (Eigen::Index v = 0; v < m.V.rows(); ++v) out.V.row(newIndexOf[v]) = m.V.row(v);
  out.F.resize(m.F.rows(), 3);
  for (Eigen::Index f = 0; f < m.F.rows(); ++f)
    for (int k = 0; k < 3; ++k) out.F(f, k) = newIndexOf[m.F(f, k)];
  return out;
}

TriMesh shuffle(const TriMesh& m, std::uint64_t seed, std::vector<int>* newIndexOf) {
  std::mt19937_64 rng(seed);
  const std::vector<int> perm = permutation(static_cast<int>(m.V.rows()), rng);  // perm[old]
  const std::vector<int> order = permutation(static_cast<int>(m.F.rows()), rng);
  TriMesh out;
  out.V.resize(m.V.rows(), 3);
  for (Eigen::Index i = 0; i < m.V.rows(); ++i) out.V.row(perm[i]) = m.V.row(i);
  out.F.resize(m.F.rows(), 3);
  for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
    const int r = static_cast<int>(rng() % 3);
    for (int c = 0; c < 3; ++c) out.F(f, c) = perm[m.F(order[f], (c + r) % 3)];
  }
  if (newIndexOf) *newIndexOf = perm;
  return out;
}

// ---- Names -------------------------------------------------------------------------

std::string waveletsName(const WaveletOptions& w) {
  return w.kind == WaveletKind::Quasi ? "quasi" + std::to_string(w.rings) : waveletKindName(w.kind);
}

// ---- Topology ----------------------------------------------------------------------

std::ostream& operator<<(std::ostream& os, const Topology& t) {
  return os << "{euler " << t.euler << ", boundary loops " << t.boundaryLoops << ", components "
            << t.components << ", genus " << t.genus << "}";
}

Topology topology(const Faces& F, int numVertices) {
  const Connectivity c(F, numVertices);
  Topology t;
  t.euler = c.eulerCharacteristic();
  t.boundaryLoops = c.numBoundaryLoops();
  t.components = c.numComponents();
  t.genus = (2 * t.components - t.euler - t.boundaryLoops) / 2;
  return t;
}

Topology topology(const TriMesh& m) {
  return topology(m.F, static_cast<int>(m.V.rows()));
}

}  // namespace osdmra::test
