// Helpers shared by the test suite (namespace osdmra::test): error messages,
// scratch directories, small hand-made meshes, shuffled meshes and topology
// summaries. Anything two test files would otherwise each write lives here.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <initializer_list>
#include <iosfwd>
#include <string>
#include <string_view>
#include <vector>

#include "osdmra/mesh/connectivity.h"
#include "osdmra/mesh/mesh.h"
#include "osdmra/mra/decomposition.h"

namespace osdmra::test {

// ---- Errors ------------------------------------------------------------------------

/// The message of the osdmra::Error `f` throws; "" and a test failure when it throws
/// nothing or another exception.
std::string errorOf(const std::function<void()>& f);

/// Expects every one of `parts` in `message`, naming the missing ones.
void expectContains(const std::string& message, std::initializer_list<std::string_view> parts);

// ---- Files -------------------------------------------------------------------------

/// A fresh directory under the system temporary directory, removed with everything in
/// it when the object dies (so it is neither copied nor moved).
class TempDir {
 public:
  TempDir();
  TempDir(TempDir&&) = delete;
  ~TempDir();

  const std::filesystem::path& path() const { return path_; }
  /// The path of `name` inside the directory (nothing is created).
  std::string file(const std::string& name) const;
  /// Writes `bytes` to `name` exactly and returns its path.
  std::string write(const std::string& name, std::string_view bytes) const;
  /// The names of the directory's entries, sorted.
  std::vector<std::string> entries() const;

 private:
  std::filesystem::path path_;
};

/// The whole content of a file, byte for byte ("" when it cannot be opened).
std::string readFile(const std::string& path);

// ---- Meshes ------------------------------------------------------------------------

/// A mesh from listed points and faces.
TriMesh makeMesh(std::initializer_list<std::array<double, 3>> points,
                 std::initializer_list<std::array<int, 3>> faces);

/// The tetrahedron on the origin and the three unit points, faces outwards:
/// V = (0,0,0) (1,0,0) (0,1,0) (0,0,1), F = (0,2,1) (0,1,3) (0,3,2) (1,2,3). (Unlike
/// shapes::tetrahedron, its coordinates are simple enough to write out in a file.)
TriMesh cornerTetrahedron();

/// The unit square [0,1]^2 at height z in two triangles (0,1,2) (0,2,3), facing +z:
/// an open disc.
TriMesh unitSquare(double z = 0.0);

/// The unit cube [0,1]^3 in 12 triangles facing outwards; vertex i is at
/// (i & 1, i >> 1 & 1, i >> 2 & 1).
TriMesh unitCube();

/// The sum of the faces' areas.
double surfaceArea(const TriMesh& m);

/// The unit cube as CAD exports write it: each side a polygon with k points along each
/// of its edges, fanned from the second point of its first edge, so that the fan's
/// first two triangles have their three corners on that edge (zero-area caps: 12 for
/// k = 4). Every side's loop runs counter-clockwise seen from outside.
TriMesh fannedCube(int k);

/// The unit cube with five sides meshed as n x n grids and its top (z = 1) one polygon
/// of 4 n points fanned from its corner at the origin, as CAD exports fan: the fan's
/// first and last n - 1 triangles lie along the two edges at that corner, two chains of
/// caps around one vertex.
TriMesh cubeWithATopFannedFromACorner(int n);

/// A Moebius strip of n quads (2 n triangles) closed with a half twist: every face
/// agrees with its neighbours' winding but at the twist, which no winding mends.
TriMesh moebiusStrip(int n);

// ---- Orders ------------------------------------------------------------------------

/// A random permutation of 0..n-1 (std::shuffle of the identity with mt19937_64(seed)).
std::vector<int> randomPermutation(int n, std::uint64_t seed);

/// Asserts (gtest) that two Connectivity objects over the same faces hold the same
/// twins, edge numbering, rings, fans, flags and recorded defects.
void expectSameConnectivity(const Connectivity& a, const Connectivity& b);

/// `m` with vertex i renumbered newIndexOf[i]; faces in the same order.
TriMesh renumberVertices(const TriMesh& m, const std::vector<int>& newIndexOf);

/// `m` with its vertices, its faces and the corners within each face in random order
/// (the same surface, as a file from elsewhere would have it). `newIndexOf`, when
/// given, receives each old vertex's new index.
TriMesh shuffle(const TriMesh& m, std::uint64_t seed, std::vector<int>* newIndexOf = nullptr);

// ---- Names -------------------------------------------------------------------------

/// "lazy", "quasi<r>" or "pre": wavelet options as test names and traces show them.
std::string waveletsName(const WaveletOptions& w);

// ---- Topology ----------------------------------------------------------------------

/// What the topology of a (valid) triangle mesh is, from Connectivity.
struct Topology {
  int euler = 0;          ///< V - E + F
  int boundaryLoops = 0;  ///< boundary curves
  int components = 0;     ///< connected components
  int genus = 0;          ///< (2 components - euler - boundaryLoops) / 2
  bool operator==(const Topology& o) const {
    return euler == o.euler && boundaryLoops == o.boundaryLoops && components == o.components &&
           genus == o.genus;
  }
  bool operator!=(const Topology& o) const { return !(*this == o); }
};
std::ostream& operator<<(std::ostream& os, const Topology& t);

Topology topology(const Faces& F, int numVertices);
Topology topology(const TriMesh& m);

}  // namespace osdmra::test
