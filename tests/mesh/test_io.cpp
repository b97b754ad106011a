// Mesh I/O: exact round trips, every accepted format variant, every rejection with
// a message naming the file and the line or element, and a mutation fuzz loop.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "osdmra/base/error.h"
#include "osdmra/mesh/detail/text.h"
#include "osdmra/mesh/io.h"
#include "osdmra/mesh/mesh.h"
#include "support.h"

using namespace osdmra;
using namespace osdmra::test;
namespace fs = std::filesystem;

namespace {

/// Reads `content` from a file called `name` and returns the error message.
std::string readError(const TempDir& dir, const std::string& name, std::string_view content) {
  const std::string path = dir.write(name, content);
  return errorOf([&] { readMesh(path); });
}

/// A closed octahedron whose coordinates are awkward doubles (thirds, tiny, huge,
/// subnormal, negative zero), so that any loss of precision shows.
TriMesh awkwardOctahedron() {
  TriMesh m;
  m.V.resize(6, 3);
  m.V << 1.0 / 3, 0.1, -0.0, -2.0 / 3, 1e-300, 5e-324, 0, 1e300, -1.7976931348623157e308,
      0.30000000000000004, -123456.789, 2.5e-8, 3.141592653589793, 2.718281828459045, -1,
      std::nextafter(1.0, 2.0), 0, -1e-7;
  m.F.resize(8, 3);
  m.F << 0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5;
  return m;
}

void expectSameBits(const Points& a, const Points& b) {
  ASSERT_EQ(a.rows(), b.rows());
  for (Eigen::Index i = 0; i < a.rows(); ++i)
    for (int k = 0; k < 3; ++k)
      EXPECT_EQ(std::memcmp(&a(i, k), &b(i, k), sizeof(double)), 0)
          << "row " << i << " col " << k << ": " << a(i, k) << " vs " << b(i, k);
}

void expectSameMesh(const TriMesh& a, const TriMesh& b) {
  expectSameBits(a.V, b.V);
  ASSERT_EQ(a.F.rows(), b.F.rows());
  EXPECT_TRUE((a.F.array() == b.F.array()).all());
  expectSameBits(a.N, b.N);
}

struct Variant {
  const char* file;
  WriteOptions opts;
};
std::vector<Variant> allVariants() {
  WriteOptions ascii;
  ascii.plyEncoding = PlyEncoding::Ascii;
  return {{"m.obj", {}}, {"m.off", {}}, {"m.ply", {}}, {"ascii.ply", ascii}};
}

// `m` as an STL file: binary (floats, little-endian; a header that starts with "solid",
// as some exporters write) or ASCII.
std::string stlOf(const TriMesh& m, bool binary) {
  std::string s;
  if (binary) {
    s = "solid, but binary";
    s.resize(80, ' ');
    auto put = [&](auto value) {
      char bytes[sizeof value];
      std::memcpy(bytes, &value, sizeof value);
      for (std::size_t i = 0; i < sizeof value; ++i)  // little-endian whatever the host
        s += bytes[detail::hostIsLittleEndian() ? i : sizeof value - 1 - i];
    };
    put(static_cast<std::uint32_t>(m.F.rows()));
    for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
      for (int k = 0; k < 3; ++k) put(0.0f);
      for (int c = 0; c < 3; ++c)
        for (int k = 0; k < 3; ++k) put(static_cast<float>(m.V(m.F(f, c), k)));
      put(std::uint16_t{0});
    }
    return s;
  }
  s = "solid m\n";
  for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
    s += "facet normal 0 0 0\n outer loop\n";
    for (int c = 0; c < 3; ++c)
      s += "  vertex " + std::to_string(m.V(m.F(f, c), 0)) + " " +
           std::to_string(m.V(m.F(f, c), 1)) + " " + std::to_string(m.V(m.F(f, c), 2)) + "\n";
    s += " endloop\nendfacet\n";
  }
  return s + "endsolid m\n";
}

// Big-endian byte builders for hand-made binary PLY files.
template <class T>
void putBE(std::string& s, T value) {
  unsigned char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  const std::uint16_t probe = 1;
  unsigned char first = 0;
  std::memcpy(&first, &probe, 1);
  for (std::size_t i = 0; i < sizeof(T); ++i)
    s += static_cast<char>(first == 1 ? bytes[sizeof(T) - 1 - i] : bytes[i]);
}
template <class T>
void putLE(std::string& s, T value) {
  std::string be;
  putBE(be, value);
  s.append(be.rbegin(), be.rend());
}

/// A stream that cannot seek (like a pipe): the readers must still bound memory.
class PipeBuf : public std::stringbuf {
 public:
  explicit PipeBuf(const std::string& s) : std::stringbuf(s) {}

 protected:
  pos_type seekoff(off_type, std::ios_base::seekdir, std::ios_base::openmode) override {
    return pos_type(off_type(-1));
  }
  pos_type seekpos(pos_type, std::ios_base::openmode) override { return pos_type(off_type(-1)); }
};

}  // namespace

// ---- Round trips ------------------------------------------------------------------

TEST(MeshIO, RoundTripsAreBitExact) {
  TempDir dir;
  const TriMesh mesh = awkwardOctahedron();
  for (const Variant& v : allVariants()) {
    SCOPED_TRACE(v.file);
    const std::string path = dir.file(v.file);
    writeMesh(path, mesh, v.opts);
    expectSameMesh(readValidMesh(path), mesh);
  }
}

TEST(MeshIO, NormalsRoundTrip) {
  TempDir dir;
  TriMesh mesh = awkwardOctahedron();
  mesh.N = mesh.V.rowwise().normalized();
  mesh.N(0, 0) = 1.0 / 7;
  for (const Variant& v : allVariants()) {
    SCOPED_TRACE(v.file);
    const std::string path = dir.file(v.file);
    writeMesh(path, mesh, v.opts);
    expectSameMesh(readMesh(path), mesh);
    WriteOptions without = v.opts;
    without.writeNormals = false;
    writeMesh(path, mesh, without);
    EXPECT_EQ(readMesh(path).N.rows(), 0);
  }
}

TEST(MeshIO, WritesTheDocumentedSyntax) {
  TempDir dir;
  TriMesh mesh = cornerTetrahedron();
  mesh.V(1, 0) = 0.1;
  writeMesh(dir.file("t.obj"), mesh);
  const std::string obj = readFile(dir.file("t.obj"));
  expectContains(obj, {"v 0.1 0 0\n", "f 1 3 2\n"});
  mesh.N = Points::Ones(4, 3);
  writeMesh(dir.file("n.obj"), mesh);
  expectContains(readFile(dir.file("n.obj")), {"vn 1 1 1\n", "f 1//1 3//3 2//2\n"});
  writeMesh(dir.file("t.ply"), mesh);
  const std::string ply = readFile(dir.file("t.ply"));
  expectContains(ply, {"format binary_little_endian 1.0\n", "property double nx\n",
                       "property list uchar int vertex_indices\n"});
  EXPECT_EQ(ply.size(), ply.find("end_header\n") + 11 + 4 * 6 * 8 + 4 * 13);
}

TEST(MeshIO, ExtensionsAreCaseInsensitive) {
  TempDir dir;
  for (const char* name : {"A.OBJ", "b.Off", "c.pLy"}) {
    writeMesh(dir.file(name), cornerTetrahedron());
    EXPECT_EQ(readMesh(dir.file(name)).F.rows(), 4) << name;
  }
  EXPECT_EQ(meshFormatFromPath("x/y.PLY"), MeshFormat::Ply);
  expectContains(errorOf([&] { readMesh(dir.file("mesh.stl2")); }),
                 {"mesh.stl2", "unknown mesh format", ".obj, .off, .ply or .stl"});
  expectContains(errorOf([&] { writeMesh(dir.file("noext"), cornerTetrahedron()); }),
                 {"noext", "no extension"});
}

TEST(MeshIO, StreamsWork) {
  std::stringstream s;
  writeMesh(s, MeshFormat::Off, cornerTetrahedron());
  expectSameMesh(readMesh(s, MeshFormat::Off, "<stream>"), cornerTetrahedron());
}

// ---- Atomic writes ----------------------------------------------------------------

TEST(MeshIO, WritesReplaceAtomicallyAndLeaveNoTemporaries) {
  TempDir dir;
  const std::string path = dir.file("m.ply");
  writeMesh(path, cornerTetrahedron());
  writeMesh(path, awkwardOctahedron());  // replaces
  EXPECT_EQ(readMesh(path).F.rows(), 8);
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"m.ply"});

  // A mesh the readers would reject is refused; the old file is untouched.
  const std::string before = readFile(path);
  TriMesh bad = cornerTetrahedron();
  bad.F(3, 2) = 9;
  expectContains(errorOf([&] { writeMesh(path, bad); }),
                 {"m.ply", "face 3", "index 9", "out of range"});
  bad = cornerTetrahedron();
  bad.V(2, 2) = std::numeric_limits<double>::quiet_NaN();
  expectContains(errorOf([&] { writeMesh(path, bad); }), {"m.ply", "vertex 2", "non-finite"});
  EXPECT_EQ(readFile(path), before);
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"m.ply"});

  expectContains(errorOf([&] { writeMesh(dir.file("missing/dir/m.obj"), cornerTetrahedron()); }),
                 {"missing/dir/m.obj", "cannot create"});
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"m.ply"});
}

TEST(MeshIO, ReadErrorsNameTheFile) {
  TempDir dir;
  expectContains(errorOf([&] { readMesh(dir.file("absent.obj")); }),
                 {"absent.obj", "cannot open", "No such file"});
  fs::create_directory(dir.file("folder.ply"));
  expectContains(errorOf([&] { readMesh(dir.file("folder.ply")); }), {"folder.ply", "directory"});
  for (const char* name : {"empty.obj", "empty.off", "empty.ply"})
    expectContains(readError(dir, name, ""), {name, "empty"});
}

// ---- OBJ --------------------------------------------------------------------------

TEST(ObjReader, AcceptsAllCornerFormsAndIgnoresTheRest) {
  TempDir dir;
  const std::string path = dir.write("forms.obj",
                                     "# comment\r\n"
                                     "mtllib a.mtl\r\n"
                                     "o thing\n"
                                     "v 0 0 0\n"
                                     "v 1 0 0 1.0\n"          // w
                                     "v 0 1 0 0.5 0.5 0.5\n"  // colour
                                     "v 0 0 +1e0\n"
                                     "vt 0 0\n"
                                     "vn 0 0 1\n"
                                     "g group\n"
                                     "s 1\n"
                                     "usemtl m\n"
                                     "f 1/1 3/1 2/1\n"
                                     "f 1/1/1 2//1 4\n"
                                     "f -4 -1 -2   # relative\n"
                                     "f 2 \\\n 3 4\n"
                                     "l 1 2\n");
  const TriMesh m = readValidMesh(path);
  ASSERT_EQ(m.V.rows(), 4);
  EXPECT_EQ(m.V(3, 2), 1.0);
  ASSERT_EQ(m.F.rows(), 4);
  EXPECT_EQ(m.F.row(2), Eigen::RowVector3i(0, 3, 2));
  EXPECT_EQ(m.F.row(3), Eigen::RowVector3i(1, 2, 3));
  EXPECT_EQ(m.N.rows(), 0);  // not every corner has a normal
}

TEST(ObjReader, SkipsAByteOrderMark) {
  std::istringstream in("\xEF\xBB\xBFv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  EXPECT_EQ(readObj(in, "bom.obj").V.rows(), 3);
}

TEST(ObjReader, ForwardReferencesAreResolvedAtTheEnd) {
  std::istringstream in("f 1 2 3\nv 0 0 0\nv 1 0 0\nv 0 1 0\n");
  EXPECT_EQ(readObj(in, "fwd.obj").F.rows(), 1);
}

TEST(ObjReader, SplitNormalsAreDropped) {
  std::istringstream in(
      "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvn 0 0 1\nvn 0 0 -1\n"
      "f 1//1 2//1 3//1\nf 2//2 4//2 3//2\n");
  EXPECT_EQ(readObj(in, "split.obj").N.rows(), 0);  // vertices 2, 3 have two normals
}

TEST(ObjReader, RejectsWithFileAndLine) {
  TempDir dir;
  const std::string v = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n";
  expectContains(readError(dir, "quad.obj", v + "# a quad\nf 1 2 4 3\n"),
                 {"quad.obj:6: ", "face has 4 vertices; osdmra needs triangles"});
  expectContains(readError(dir, "line.obj", v + "f 1 2\n"), {"line.obj:5: ", "2 vertices"});
  expectContains(readError(dir, "range.obj", v + "f 1 2 3\nf 1 2 9\n"),
                 {"range.obj:6: ", "vertex 9", "only 4 vertices"});
  expectContains(readError(dir, "zero.obj", v + "f 0 1 2\n"),
                 {"zero.obj:5: ", "index 0 is invalid"});
  expectContains(readError(dir, "rel.obj", v + "f -1 -2 -5\n"),
                 {"rel.obj:5: ", "relative vertex index -5"});
  expectContains(readError(dir, "nan.obj", "v 0 0 0\nv 0 nan 0\n"),
                 {"nan.obj:2: ", "non-finite", "'nan'"});
  expectContains(readError(dir, "inf.obj", "v 0 0 0\nv 0 0 -inf\n"), {"inf.obj:2: ", "'-inf'"});
  expectContains(readError(dir, "huge.obj", "v 0 0 1e999\n"), {"huge.obj:1: ", "'1e999'"});
  expectContains(readError(dir, "word.obj", "v 0 zero 0\n"),
                 {"word.obj:1: ", "'zero' is not a number"});
  expectContains(readError(dir, "short.obj", "v 0 0\n"), {"short.obj:1: ", "3 coordinates"});
  expectContains(readError(dir, "corner.obj", v + "f 1/a 2 3\n"),
                 {"corner.obj:5: ", "bad texture index 'a'"});
  expectContains(readError(dir, "slash.obj", v + "f 1/1/1/1 2 3\n"),
                 {"slash.obj:5: ", "bad face corner"});
  expectContains(readError(dir, "vn.obj", v + "f 1//3 2//3 3//3\n"),
                 {"vn.obj:5: ", "normal 3", "only 0 normals"});
  expectContains(readError(dir, "stmt.obj", v + "bogus 1 2\n"),
                 {"stmt.obj:5: ", "unknown OBJ statement 'bogus'"});
  expectContains(readError(dir, "curve.obj", v + "curv 0 1 1 2\n"), {"curve.obj:5: ", "free-form"});
  expectContains(readError(dir, "garbage.obj", std::string("\x7f\x00\xff\x12 junk\n", 10)),
                 {"garbage.obj:1: ", "unknown OBJ statement '\\x7f\\x00\\xff\\x12'"});
}

// ---- OFF --------------------------------------------------------------------------

TEST(OffReader, AcceptsHeaderVariants) {
  const char* const variants[] = {
      "OFF\n4 4 6\n",
      "OFF 4 4 6\n",
      "# leading comment\n\nOFF # trailing comment\n\n# between\n4 4 0\n",
      "4 4 0\n",     // no keyword at all
      "OFF4 4 0\n",  // counts glued to the keyword by some exporters
      "COFF\n4 4 0\n",
  };
  const std::string body =
      "0 0 0 255 0 0 255\n1 0 0\n0 1 0\n0 0 1\n"           // extra colour values ignored
      "3 0 2 1\n3 0 1 3 0.5 0.5 0.5\n3 0 3 2\n3 1 2 3\n";  // face colour ignored
  for (const char* header : variants) {
    std::istringstream in(std::string(header) + body);
    const TriMesh m = readOff(in, "v.off");
    expectSameMesh(m, cornerTetrahedron());
  }
}

TEST(OffReader, ReadsNoffNormals) {
  std::istringstream in("NOFF\n3 1 0\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n3 0 1 2\n");
  const TriMesh m = readOff(in, "n.off");
  ASSERT_EQ(m.N.rows(), 3);
  EXPECT_EQ(m.N(2, 2), 1.0);
}

TEST(OffReader, RejectsWithFileAndLine) {
  TempDir dir;
  const std::string head = "OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n";
  expectContains(readError(dir, "quad.off", head + "4 0 1 3 2\n3 0 1 2\n"),
                 {"quad.off:7: ", "face 0: has 4 vertices; osdmra needs triangles"});
  expectContains(readError(dir, "range.off", head + "3 0 1 2\n3 0 1 4\n"),
                 {"range.off:8: ", "face 1", "vertex index 4 is out of range"});
  expectContains(readError(dir, "neg.off", head + "3 0 1 2\n3 0 -1 2\n"),
                 {"neg.off:8: ", "index -1"});
  expectContains(
      readError(dir, "trunc.off",
                "OFF\n4 2 0\n0.0 0.0 0.0\n1.0 0.0 0.0\n0.0 1.0 0.0\n1.0 1.0 0.0\n3 0 1 2\n"),
      {"trunc.off:7: ", "1 of 2 faces", "truncated"});
  expectContains(readError(dir, "nan.off", "OFF\n3 1 0\n0 0 0\nNaN 0 0\n0 1 0\n3 0 1 2\n"),
                 {"nan.off:4: ", "vertex 1", "non-finite"});
  expectContains(readError(dir, "word.off", "OFF\n3 1 0\n0 0 0\n1 O 0\n0 1 0\n3 0 1 2\n"),
                 {"word.off:4: ", "vertex 1", "'O' is not a number"});
  expectContains(readError(dir, "few.off", "OFF\n3 1 0\n0 0\n1 0 0\n0 1 0\n3 0 1 2\n"),
                 {"few.off:3: ", "vertex 0"});
  expectContains(readError(dir, "extra.off", head + "3 0 1 2\n3 0 1 3\n3 1 2 3\n"),
                 {"extra.off:9: ", "after the last of 2 faces"});
  expectContains(readError(dir, "counts.off", "OFF\n4\n"), {"counts.off:2: ", "counts"});
  expectContains(readError(dir, "big.off", "OFF\n2000000000 1 0\n0 0 0\n"),
                 {"big.off:2: ", "2000000000 vertices", "remaining"});
  expectContains(readError(dir, "huge.off", "OFF\n4000000000 1 0\n0 0 0\n"),
                 {"huge.off:2: ", "too large"});
  expectContains(readError(dir, "4d.off", "4OFF\n"), {"4d.off:1: ", "3-dimensional"});
  expectContains(readError(dir, "bin.off", "OFF BINARY\n"), {"bin.off:1: ", "binary OFF"});
  expectContains(readError(dir, "text.off", "hello world\n"), {"text.off:1: ", "not an OFF file"});
  expectContains(readError(dir, "comments.off", "# nothing\n\n"), {"comments.off", "no content"});
}

// ---- PLY --------------------------------------------------------------------------

TEST(PlyReader, AsciiWithExtraPropertiesAndElements) {
  std::istringstream in(
      "ply\r\nformat ascii 1.0\r\ncomment hi\r\nobj_info x\r\n"
      "element vertex 4\r\n"
      "property uchar red\r\nproperty float32 x\r\nproperty list uchar int junk\r\n"
      "property double y\r\nproperty short z\r\nproperty uint8 alpha\r\n"
      "element face 4\r\n"
      "property int flags\r\nproperty list int uint vertex_index\r\n"
      "property list uchar float texcoord\r\n"
      "element edge 1\r\nproperty list uchar int pair\r\n"
      "end_header\r\n"
      "1 0 0 0 0 2\r\n2 1 2 9 9 0 0 2\r\n3 0 0 1 0 2\r\n4 0 1 1 0 +1 2\r\n"
      "7 3 0 2 1 0\r\n7 3 0 1 3 0\r\n7 3 0 3 2 6 0 0 0 0 0 0\r\n7 3 1 2 3 0\r\n"
      "2 0 1\r\n");
  expectSameMesh(readPly(in, "a.ply"), cornerTetrahedron());
}

TEST(PlyReader, BinaryBigEndianWithMixedTypes) {
  std::string s =
      "ply\nformat binary_big_endian 1.0\n"
      "element vertex 4\nproperty int8 x\nproperty double y\nproperty float z\n"
      "property list ushort ushort skipme\nproperty float nx\nproperty float ny\n"
      "property float nz\n"
      "element face 4\nproperty list uchar uint vertex_indices\n"
      "element other 2\nproperty list int short stuff\nproperty uint code\n"
      "end_header\n";
  const double V[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  for (int v = 0; v < 4; ++v) {
    putBE(s, static_cast<std::int8_t>(V[v][0]));
    putBE(s, V[v][1]);
    putBE(s, static_cast<float>(V[v][2]));
    putBE(s, std::uint16_t{2});
    putBE(s, std::uint16_t{7});
    putBE(s, std::uint16_t{8});
    for (int k = 0; k < 3; ++k) putBE(s, 0.5f);
  }
  const int F[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  for (const auto& f : F) {
    putBE(s, std::uint8_t{3});
    for (int i : f) putBE(s, static_cast<std::uint32_t>(i));
  }
  for (int i = 0; i < 2; ++i) {
    putBE(s, std::int32_t{1});
    putBE(s, std::int16_t{-1});
    putBE(s, std::uint32_t{42});
  }
  std::istringstream in(s);
  TriMesh expected = cornerTetrahedron();
  expected.N = Points::Constant(4, 3, 0.5);
  expectSameMesh(readPly(in, "be.ply"), expected);
}

TEST(PlyReader, BinaryLittleEndianWithSmallIndexTypes) {
  std::string s =
      "ply\nformat binary_little_endian 1.0\nelement vertex 4\n"
      "property ushort x\nproperty int y\nproperty uint z\nproperty float nx\n"
      "element face 4\nproperty list char short vertex_indices\nend_header\n";
  const int V[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  for (const auto& v : V) {
    putLE(s, static_cast<std::uint16_t>(v[0]));
    putLE(s, static_cast<std::int32_t>(v[1]));
    putLE(s, static_cast<std::uint32_t>(v[2]));
    putLE(s, 9.0f);  // a lone nx is no normal
  }
  const int F[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  for (const auto& f : F) {
    putLE(s, std::int8_t{3});
    for (int i : f) putLE(s, static_cast<std::int16_t>(i));
  }
  std::istringstream in(s);
  expectSameMesh(readPly(in, "le.ply"), cornerTetrahedron());
}

TEST(PlyReader, RejectsWithFileAndElement) {
  TempDir dir;
  std::ostringstream bin;
  writePly(bin, cornerTetrahedron());
  const std::string valid = bin.str();
  const std::size_t body = valid.find("end_header\n") + 11;

  // Truncated: the last face loses its last index.
  // A seekable file is measured before reading: the header line of the element
  // that does not fit, and how many of its entries do.
  expectContains(readError(dir, "trunc.ply", valid.substr(0, valid.size() - 2)),
                 {"trunc.ply:8: ", "element 'face' declares 4 entries", "at most 3", "truncated"});
  expectContains(readError(dir, "trailing.ply", valid + "xx"),
                 {"trailing.ply: ", "after the last"});
  expectContains(readError(dir, "nohead.ply", valid.substr(0, body - 11)),
                 {"nohead.ply:", "without 'end_header'"});

  // Quad, index out of range, NaN: patch the binary in place.
  std::string quad = valid;
  quad[body + 4 * 24 + 2 * 13] = 4;  // face 2's count
  expectContains(readError(dir, "quad.ply", quad),
                 {"quad.ply: ", "face 2", "4 vertices; osdmra needs triangles"});
  std::string range = valid;
  range[body + 4 * 24 + 1 * 13 + 1] = 57;  // face 1, first index
  expectContains(readError(dir, "range.ply", range),
                 {"range.ply: ", "face 1", "index 57 is out of range"});
  std::string nan = valid;
  const double q = std::numeric_limits<double>::quiet_NaN();
  std::memcpy(&nan[body + 2 * 24 + 8], &q, 8);  // vertex 2, y (little-endian host)
  expectContains(readError(dir, "nan.ply", nan), {"nan.ply: ", "vertex 2", "y is not finite"});

  // Absurd declared counts in a tiny file: an error, not an allocation.
  const std::string props = "property float x\nproperty float y\nproperty float z\n";
  expectContains(readError(dir, "absurd.ply",
                           "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\n" +
                               props + "end_header\n0123456789"),
                 {"absurd.ply:3: ", "4000000000"});
  expectContains(readError(dir, "absurd_face.ply",
                           "ply\nformat binary_little_endian 1.0\nelement vertex 3\n" + props +
                               "element face 700000000\nproperty list uchar int vertex_indices\n"
                               "end_header\n" +
                               std::string(36, '\0')),
                 {"absurd_face.ply:7: ", "700000000 entries", "truncated file or corrupt header"});
  expectContains(readError(dir, "absurd_other.ply",
                           "ply\nformat ascii 1.0\nelement vertex 3\n" + props +
                               "element junk 18446744073709551615\nproperty list int int a\n"
                               "end_header\n0 0 0\n1 0 0\n0 1 0\n"),
                 {"absurd_other.ply:7: ", "'junk'", "at most 0"});

  // Ascii errors name the line as well as the element.
  const std::string asciiHead = "ply\nformat ascii 1.0\nelement vertex 3\n" + props +
                                "element face 1\nproperty list uchar int vertex_indices\n"
                                "end_header\n";
  expectContains(readError(dir, "aquad.ply", asciiHead + "0 0 0\n1 0 0\n0 1 0\n4 0 1 2 0\n"),
                 {"aquad.ply:13: ", "face 0", "4 vertices"});
  expectContains(readError(dir, "anan.ply", asciiHead + "0 0 0\n1 inf 0\n0 1 0\n3 0 1 2\n"),
                 {"anan.ply:11: ", "vertex 1", "y is not finite"});
  expectContains(readError(dir, "aword.ply", asciiHead + "0 0 0\n1 x 0\n0 1 0\n3 0 1 2\n"),
                 {"aword.ply:11: ", "vertex 1", "'x' is not a number"});
  expectContains(readError(dir, "atrunc.ply", asciiHead + "0.0 0.0 0.0\n1 0 0\n0 1 0\n3 0 1\n"),
                 {"atrunc.ply:13: ", "face 0", "truncated"});
  expectContains(readError(dir, "abyte.ply",
                           "ply\nformat ascii 1.0\nelement vertex 1\nproperty uchar x\n"
                           "property uchar y\nproperty uchar z\nend_header\n0 256 0\n"),
                 {"abyte.ply:8: ", "'256' does not fit"});

  // Header problems name the header line.
  expectContains(readError(dir, "magic.ply", "PLY\n"), {"magic.ply:1: ", "not a PLY file"});
  expectContains(readError(dir, "type.ply",
                           "ply\nformat ascii 1.0\nelement vertex 1\n"
                           "property float128 x\nend_header\n"),
                 {"type.ply:4: ", "unknown property type 'float128'"});
  expectContains(readError(dir, "noz.ply",
                           "ply\nformat ascii 1.0\nelement vertex 1\n"
                           "property float x\nproperty float y\nend_header\n"),
                 {"noz.ply:3: ", "x, y and z"});
  expectContains(readError(dir, "nolist.ply",
                           "ply\nformat ascii 1.0\nelement vertex 0\n" + props +
                               "element face 0\nproperty int vertex_indices\n"
                               "end_header\n"),
                 {"nolist.ply:7: ", "must be a list"});
  expectContains(readError(dir, "fmt.ply", "ply\nformat binary_middle_endian 1.0\n"),
                 {"fmt.ply:2: ", "unknown PLY encoding"});
  expectContains(readError(dir, "novertex.ply", "ply\nformat ascii 1.0\nend_header\n"),
                 {"novertex.ply:3: ", "no 'vertex' element"});
  expectContains(readError(dir, "long.ply", "ply\n" + std::string(100000, 'a')),
                 {"long.ply:2: ", "too long"});

  // Garbage.
  std::mt19937 rng(7);
  std::string garbage(4096, '\0');
  for (char& c : garbage) c = static_cast<char>(rng());
  for (const char* name : {"garbage.ply", "garbage.obj", "garbage.off"})
    expectContains(readError(dir, name, garbage), {name});
}

TEST(PlyReader, UnseekableStreamsStayBounded) {
  // Without a size to check against, a huge count must fail on the missing data
  // (and reserve only a bounded amount).
  PipeBuf buf(
      "ply\nformat binary_little_endian 1.0\nelement vertex 2000000000\nproperty float x\n"
      "property float y\nproperty float z\nend_header\n0123456789ab");
  std::istream in(&buf);
  expectContains(errorOf([&] { readPly(in, "pipe.ply"); }),
                 {"pipe.ply: ", "vertex 1", "truncated"});

  PipeBuf offBuf("OFF\n1000000000 1 0\n0 0 0\n");
  std::istream offIn(&offBuf);
  expectContains(errorOf([&] { readOff(offIn, "pipe.off"); }), {"pipe.off:3: ", "1 of 1000000000"});
}

// ---- Validation through files -------------------------------------------------------

TEST(MeshIO, ReadValidMeshNamesFileAndElement) {
  TempDir dir;
  const std::string tet = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n";
  const auto validError = [&](const std::string& name, const std::string& content) {
    const std::string path = dir.write(name, content);
    EXPECT_NO_THROW(readMesh(path));
    return errorOf([&] { readValidMesh(path); });
  };
  expectContains(validError("flip.obj", tet + "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 4 3\n"),
                 {"flip.obj: ", "face 3 (1, 3, 2)", "oriented inconsistently"});
  expectContains(validError("iso.off", "OFF\n4 1 0\n0 0 0\n1 0 0\n0 1 0\n5 5 5\n3 0 1 2\n"),
                 {"iso.off: ", "vertex 3", "not used by any face"});
  expectContains(validError("fin.obj", tet + "v 0 -1 0\nf 1 2 3\nf 2 1 4\nf 1 2 5\n"),
                 {"fin.obj: ", "face 0", "edge (0, 1)", "shared by 3 faces"});
  expectContains(validError("bowtie.obj", tet + "v 0 -1 0\nf 1 2 3\nf 1 4 5\n"),
                 {"bowtie.obj: ", "vertex 0 is non-manifold"});
  expectContains(validError("points.obj", tet), {"points.obj: ", "no faces"});
  expectContains(validError("repeat.obj", tet + "f 1 2 2\n"),
                 {"repeat.obj: ", "face 0 (0, 1, 1)", "twice"});
}

// ---- Fuzz -------------------------------------------------------------------------

namespace {

/// Applies 1-4 random edits: byte flips, insertions of interesting tokens or
/// random bytes, deletions, duplications and truncation.
std::string mutate(std::string s, std::mt19937& rng) {
  static const char* const tokens[] = {
      "4000000000",  "-1",   "nan",   "1e999", "0",     "3",    "4",          "\n",
      " ",           "list", "uchar", "int",   "float", "face", "vertex",     "element",
      "property",    "#",    "/",     "//",    "-",     "\\",   "end_header", "2147483647",
      "-2147483648", "\r\n", "OFF",   "f",     "v",     "vn",   "\0",         "65535"};
  const auto pick = [&](std::size_t n) {
    return n == 0 ? std::size_t{0} : std::uniform_int_distribution<std::size_t>(0, n - 1)(rng);
  };
  const int edits = 1 + static_cast<int>(pick(4));
  for (int e = 0; e < edits; ++e) {
    const std::size_t at = pick(s.size() + 1);
    switch (pick(6)) {
      case 0:  // flip a byte
        if (!s.empty()) s[pick(s.size())] ^= static_cast<char>(1 + pick(255));
        break;
      case 1: {  // insert a token
        const char* t = tokens[pick(std::size(tokens))];
        s.insert(at, std::string(t, std::max<std::size_t>(1, std::strlen(t))));
        break;
      }
      case 2:  // erase a range
        s.erase(at, pick(16) + 1);
        break;
      case 3:  // truncate
        s.resize(at);
        break;
      case 4: {  // duplicate a range
        const std::size_t len = std::min(pick(32) + 1, s.size() - std::min(at, s.size()));
        s.insert(at, s.substr(at, len));
        break;
      }
      default:  // random bytes
        for (std::size_t n = pick(8) + 1; n > 0; --n)
          s.insert(s.begin() + static_cast<std::ptrdiff_t>(std::min(at, s.size())),
                   static_cast<char>(pick(256)));
        break;
    }
  }
  return s;
}

}  // namespace

TEST(MeshIOFuzz, MutatedFilesParseOrThrowError) {
  TriMesh mesh = awkwardOctahedron();
  mesh.N = mesh.V.rowwise().normalized();
  struct Seed {
    MeshFormat format;
    std::string bytes;
  };
  std::vector<Seed> seeds;
  for (const Variant& v : allVariants()) {
    std::ostringstream out;
    writeMesh(out, meshFormatFromPath(v.file), mesh, v.opts);
    seeds.push_back({meshFormatFromPath(v.file), out.str()});
  }
  for (const bool binary : {true, false}) seeds.push_back({MeshFormat::Stl, stlOf(mesh, binary)});
  std::mt19937 rng(20240611);
  int parsed = 0, rejected = 0;
  for (int i = 0; i < 2000; ++i)
    for (const Seed& seed : seeds) {
      const std::string input = mutate(seed.bytes, rng);
      std::istringstream in(input);
      try {
        const TriMesh m = readMesh(in, seed.format, "fuzz");
        ++parsed;
        try {
          validate(m, "fuzz");  // must not crash on whatever topology was read
        } catch (const Error&) {
        }
      } catch (const Error& e) {
        ++rejected;
        ASSERT_EQ(std::string_view(e.what()).rfind("fuzz", 0), 0u) << e.what();
      } catch (const std::exception& e) {
        FAIL() << "non-osdmra exception " << e.what() << " on mutation " << i;
      }
    }
  // Both outcomes must actually occur, or the fuzz loop tests nothing.
  EXPECT_GT(parsed, 100);
  EXPECT_GT(rejected, 100);
}

TEST(MeshIO, PolygonsAreFansOnlyWhenAsked) {
  // A unit square as one quad, and a pentagon (the square with a point above its top
  // edge), in each format: refused by default; with ReadOptions::triangulate, the fans
  // (0, 1, 2) (0, 2, 3) and (0, 1, 2) (0, 2, 3) (0, 3, 4) from each first corner.
  const std::string points = "0 0 0\n1 0 0\n1 1 0\n0.5 1.5 0\n0 1 0\n";
  const std::string obj =
      "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0.5 1.5 0\nv 0 1 0\nf 1 2 3 5\nf 1 2 3 4 5\n";
  const std::string off = "OFF\n5 2 0\n" + points + "4 0 1 2 4\n5 0 1 2 3 4\n";
  const std::string ply =
      "ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nproperty float y\n"
      "property float z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n" +
      points + "4 0 1 2 4\n5 0 1 2 3 4\n";
  ReadOptions triangulate;
  triangulate.triangulate = true;
  const Faces expected = (Faces(5, 3) << 0, 1, 2, 0, 2, 4, 0, 1, 2, 0, 2, 3, 0, 3, 4).finished();
  for (const auto& [format, text] :
       {std::pair{MeshFormat::Obj, obj}, std::pair{MeshFormat::Off, off},
        std::pair{MeshFormat::Ply, ply}}) {
    SCOPED_TRACE(text);
    std::istringstream refused(text), read(text);
    expectContains(errorOf([&] { readMesh(refused, format, "poly"); }),
                   {"4 vertices; osdmra needs triangles"});
    const TriMesh m = readMesh(read, format, "poly", triangulate);
    EXPECT_EQ(m.V.rows(), 5);
    EXPECT_EQ(m.F, expected);
  }
}

TEST(StlReader, BinaryAndAsciiSoupsBecomeTheMesh) {
  // Each face with its own three corners; merged by position, the tetrahedron again
  // (faces in order, vertices in the order of their first corner).
  const TriMesh tet = cornerTetrahedron();
  for (const bool binary : {true, false}) {
    SCOPED_TRACE(binary ? "binary" : "ascii");
    std::istringstream in(stlOf(tet, binary));
    const TriMesh m = readStl(in, "t.stl");
    ASSERT_EQ(m.V.rows(), 4);
    ASSERT_EQ(m.F.rows(), 4);
    EXPECT_NO_THROW(validate(m, "t.stl"));
    for (Eigen::Index f = 0; f < 4; ++f)
      for (int c = 0; c < 3; ++c)
        EXPECT_EQ(Eigen::RowVector3d(m.V.row(m.F(f, c))),
                  Eigen::RowVector3d(tet.V.row(tet.F(f, c))));
  }
  // Two solids in one ASCII file.
  const std::string one = stlOf(tet, false);
  std::istringstream two(one + one);
  EXPECT_EQ(readStl(two, "two.stl").F.rows(), 8);
}

TEST(StlReader, RejectsWithFileAndLine) {
  TempDir dir;
  const TriMesh tet = cornerTetrahedron();
  std::string binary = stlOf(tet, true);
  expectContains(readError(dir, "short.stl", binary.substr(0, binary.size() - 7)),
                 {"short.stl: ", "declares 4 triangles (200 bytes) but 193 bytes follow"});
  expectContains(readError(dir, "tiny.stl", "abc"), {"tiny.stl: ", "too short"});
  const std::string ascii = stlOf(tet, false);
  const std::size_t loop = ascii.find(" endloop");
  expectContains(
      readError(dir, "four.stl", ascii.substr(0, loop) + "  vertex 0 0 0\n" + ascii.substr(loop)),
      {"four.stl:7: ", "more than 3 vertices"});
  expectContains(readError(dir, "cut.stl", ascii.substr(0, loop)),
                 {"cut.stl:", "file ends inside a facet"});
  expectContains(readError(dir, "nan.stl", "solid\nfacet\nouter loop\nvertex nan 0 0\n"),
                 {"nan.stl:4: ", "non-finite"});
  // STL is read only: writing one is refused before any file is made.
  const std::string out = dir.file("out.stl");
  expectContains(errorOf([&] { writeMesh(out, tet); }), {out, "does not write STL"});
  EXPECT_FALSE(fs::exists(out));
}

TEST(MeshIO, APolygonWhoseFanFoldsIsEarClipped) {
  // An L-shaped face, listed from a corner it is not star-shaped from: its fan's first
  // triangle is clockwise. Read, its four triangles are counter-clockwise (+z) and
  // cover the L's area (3) exactly once.
  const std::string off = "OFF\n6 1 0\n2 1 0\n1 1 0\n1 2 0\n0 2 0\n0 0 0\n2 0 0\n6 0 1 2 3 4 5\n";
  ReadOptions triangulate;
  triangulate.triangulate = true;
  std::istringstream in(off);
  const TriMesh m = readMesh(in, MeshFormat::Off, "l.off", triangulate);
  ASSERT_EQ(m.F.rows(), 4);
  double area = 0;
  for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
    const Eigen::Vector3d a = m.V.row(m.F(f, 0)), b = m.V.row(m.F(f, 1)), c = m.V.row(m.F(f, 2));
    const double z = (b - a).cross(c - a).z();
    EXPECT_GT(z, 0) << "face " << f;
    area += 0.5 * z;
  }
  EXPECT_DOUBLE_EQ(area, 3.0);
}
