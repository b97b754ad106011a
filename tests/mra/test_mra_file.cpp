#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <limits>
#include <numeric>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "osdmra/base/error.h"
#include "osdmra/mra/mra_file.h"
#include "osdmra/subdivision/hierarchy.h"
#include "osdmra/subdivision/shapes.h"
#include "support.h"

using namespace osdmra;
using namespace osdmra::test;
namespace fs = std::filesystem;

namespace {

using Bytes = std::string;

// A decomposition of the octahedron with arbitrary (but exactly representable and
// awkward) coefficients, optionally with the input-order parts.
Decomposition makeDecomposition(int levels, bool withOrder, bool withFaces, unsigned seed = 1) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> coef(-2.0, 2.0);
  Hierarchy h(shapes::octahedron().F, 6, levels);
  Decomposition d;
  d.scheme = Scheme::Linear;
  d.wavelets.kind = WaveletKind::Pre;
  d.wavelets.rings = 3;
  d.levels = levels;
  d.baseFaces = h.faces(0);
  d.base = Points(6, 3);
  d.base << 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1;
  d.base(0, 0) = 1.0 / 3.0;  // not a short binary fraction: tests exactness
  for (int j = 0; j < levels; ++j) {
    Points D(h.numVertices(j + 1) - h.numVertices(j), 3);
    for (Eigen::Index r = 0; r < D.rows(); ++r)
      for (int c = 0; c < 3; ++c) D(r, c) = coef(rng);
    if (D.rows() > 0) D(0, 0) = -0.0;  // sign of zero must survive
    d.details.push_back(D);
  }
  const int n = h.numVertices(levels);
  if (withOrder) {
    d.inputOrder.resize(static_cast<std::size_t>(n));
    std::iota(d.inputOrder.begin(), d.inputOrder.end(), 0);
    std::shuffle(d.inputOrder.begin(), d.inputOrder.end(), rng);
  }
  if (withFaces) {
    d.inputFaces = h.faces(levels);
    for (Eigen::Index f = 0; f < d.inputFaces.rows(); ++f)
      for (int c = 0; c < 3; ++c)
        d.inputFaces(f, c) = withOrder ? d.inputOrder[static_cast<std::size_t>(d.inputFaces(f, c))]
                                       : d.inputFaces(f, c);
  }
  return d;
}

Bytes toBytes(const Decomposition& d) {
  std::ostringstream out(std::ios::binary);
  writeMra(out, d);
  return out.str();
}

Decomposition fromBytes(const Bytes& b, const std::string& name = "test.mra") {
  std::istringstream in(b, std::ios::binary);
  return readMra(in, name);
}

// Message of the Error reading `b` throws; fails the test if it reads or throws
// anything else.
std::string readError(const Bytes& b) {
  return errorOf([&] { fromBytes(b); });
}

void putU32(Bytes& b, std::size_t at, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) b[at + i] = static_cast<char>(v >> (8 * i));
}

// Recomputes the trailing checksum so that a test reaches the check it aims at.
void fixChecksum(Bytes& b) {
  const std::size_t at = b.size() - 8;
  const std::uint64_t c = crc64(b.data(), at);
  for (int i = 0; i < 8; ++i) b[at + i] = static_cast<char>(c >> (8 * i));
}

void expectSame(const Decomposition& a, const Decomposition& b) {
  EXPECT_EQ(a.scheme, b.scheme);
  EXPECT_EQ(a.wavelets.kind, b.wavelets.kind);
  EXPECT_EQ(a.wavelets.rings, b.wavelets.rings);
  EXPECT_EQ(a.levels, b.levels);
  EXPECT_EQ(a.baseFaces, b.baseFaces);
  // Bitwise, so that -0.0 and the last ulp count.
  const auto sameBits = [](const Points& x, const Points& y) {
    return x.rows() == y.rows() &&
           std::memcmp(x.data(), y.data(), sizeof(double) * static_cast<std::size_t>(x.size())) ==
               0;
  };
  EXPECT_TRUE(sameBits(a.base, b.base));
  ASSERT_EQ(a.details.size(), b.details.size());
  for (std::size_t j = 0; j < a.details.size(); ++j)
    EXPECT_TRUE(sameBits(a.details[j], b.details[j])) << "level " << j;
  EXPECT_EQ(a.inputOrder, b.inputOrder);
  EXPECT_EQ(a.inputFaces, b.inputFaces);
}

// Offsets of the fixed header (see mra_file.h).
constexpr std::size_t kVersionAt = 8, kSchemeAt = 12, kKindAt = 13, kRingsAt = 14, kLevelsAt = 18,
                      kVertexCountAt = 22, kFaceCountAt = 26, kFacesAt = 30;

}  // namespace

TEST(MraFile, Crc64MatchesTheXzCheckValue) {
  const char* check = "123456789";
  EXPECT_EQ(crc64(check, 9), 0x995DC9BBDF1939FAULL);
  EXPECT_EQ(crc64(check + 4, 5, crc64(check, 4)), 0x995DC9BBDF1939FAULL);
  EXPECT_EQ(crc64(check, 0), 0u);
}

TEST(MraFile, RoundTripIsExactWithAndWithoutOptionalParts) {
  for (int levels : {0, 1, 2})
    for (bool withOrder : {false, true})
      for (bool withFaces : {false, true}) {
        SCOPED_TRACE("levels " + std::to_string(levels) + " order " + std::to_string(withOrder) +
                     " faces " + std::to_string(withFaces));
        const Decomposition d = makeDecomposition(levels, withOrder, withFaces);
        const Bytes b = toBytes(d);
        expectSame(d, fromBytes(b));
        // Writing is deterministic: the same decomposition gives the same bytes.
        EXPECT_EQ(toBytes(fromBytes(b)), b);
      }
}

TEST(MraFile, RoundTripKeepsEveryEnumValue) {
  for (Scheme s : {Scheme::Loop, Scheme::Linear})
    for (WaveletKind k :
         {WaveletKind::Lazy, WaveletKind::Quasi, WaveletKind::Pre, WaveletKind::Fixed}) {
      Decomposition d = makeDecomposition(1, false, false);
      d.scheme = s;
      d.wavelets.kind = k;
      d.wavelets.rings = 0;
      expectSame(d, fromBytes(toBytes(d)));
    }
}

TEST(MraFile, LayoutMatchesTheDocumentedOffsets) {
  const Decomposition d = makeDecomposition(2, true, true);
  const Bytes b = toBytes(d);
  EXPECT_EQ(b.substr(0, 8), std::string("\x89MRA\r\n\x1a\n", 8));
  EXPECT_EQ(static_cast<std::uint32_t>(static_cast<unsigned char>(b[kVersionAt])),
            kMraFormatVersion);
  EXPECT_EQ(b[kSchemeAt], 1);  // linear
  EXPECT_EQ(b[kKindAt], 2);    // pre
  EXPECT_EQ(b[kRingsAt], 3);
  EXPECT_EQ(b[kLevelsAt], 2);
  EXPECT_EQ(b[kVertexCountAt], 6);
  EXPECT_EQ(b[kFaceCountAt], 8);
  // header, faces, positions, two levels (12 and 48 rows), order (66), faces (128), crc
  const std::size_t expected = kFacesAt + 8 * 12 + 6 * 24 + (4 + 12 * 24) + (4 + 48 * 24) +
                               (4 + 66 * 4) + (4 + 128 * 12) + 8;
  EXPECT_EQ(b.size(), expected);
}

TEST(MraFile, FileRoundTripLeavesNoTemporaryFiles) {
  TempDir dir;
  const std::string path = dir.file("octa.mra");
  const Decomposition d = makeDecomposition(2, true, false);
  writeMra(path, d);
  expectSame(d, readMra(path));
  // Overwriting replaces the file.
  const Decomposition d2 = makeDecomposition(1, false, true, 7);
  writeMra(path, d2);
  expectSame(d2, readMra(path));
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"octa.mra"});
}

TEST(MraFile, FailedWriteKeepsTheOldFile) {
  TempDir dir;
  const std::string path = dir.file("octa.mra");
  const Decomposition d = makeDecomposition(1, false, false);
  writeMra(path, d);
  Decomposition broken = d;
  broken.details[0].conservativeResize(5, 3);
  expectContains(errorOf([&] { writeMra(path, broken); }), {path, "detail rows"});
  expectSame(d, readMra(path));
  EXPECT_THROW(writeMra((dir.path() / "missing" / "x.mra").string(), d), Error);
  EXPECT_FALSE(fs::exists(dir.path() / "missing"));
}

TEST(MraFile, WriterRefusesWhatTheReaderWouldRefuse) {
  const Decomposition good = makeDecomposition(2, true, true);
  std::vector<Decomposition> bad(9, good);
  bad[0].levels = 16;
  bad[1].details.pop_back();
  bad[2].wavelets.rings = -1;
  bad[3].baseFaces(2, 1) = 6;
  bad[4].details[1](3, 2) = std::numeric_limits<double>::quiet_NaN();
  bad[5].inputOrder[0] = bad[5].inputOrder[1];
  bad[6].inputOrder.pop_back();
  bad[7].inputFaces(0, 0) = 66;
  bad[8].baseFaces = Faces();
  for (std::size_t i = 0; i < bad.size(); ++i) {
    std::ostringstream out;
    EXPECT_THROW(writeMra(out, bad[i]), Error) << "case " << i;
  }
}

TEST(MraFile, EveryTruncationIsAnError) {
  const Bytes b = toBytes(makeDecomposition(1, true, true));
  for (std::size_t n = 0; n < b.size(); ++n) {
    const std::string message = readError(b.substr(0, n));
    EXPECT_NE(message.find("test.mra"), std::string::npos) << n << ": " << message;
    if (n >= 8) {
      EXPECT_NE(message.find("truncated"), std::string::npos) << n << ": " << message;
    }
  }
}

TEST(MraFile, EverySingleByteCorruptionIsAnError) {
  const Bytes b = toBytes(makeDecomposition(1, true, true));
  for (std::size_t i = 0; i < b.size(); ++i)
    for (unsigned char flip : {0x01, 0x80, 0xFF, 0x5A}) {
      Bytes c = b;
      c[i] = static_cast<char>(static_cast<unsigned char>(c[i]) ^ flip);
      const std::string message = readError(c);
      EXPECT_NE(message.find("test.mra"), std::string::npos) << i << ": " << message;
    }
}

// Random multi-byte damage behind a valid checksum reaches the structural and
// semantic checks: the reader must either accept the file or throw Error.
TEST(MraFile, RandomDamageWithAValidChecksumNeverEscapesAsAnotherError) {
  const Bytes good = toBytes(makeDecomposition(2, true, true));
  std::mt19937 rng(12345);
  std::uniform_int_distribution<std::size_t> position(8, good.size() - 9);
  std::uniform_int_distribution<int> byte(0, 255), howMany(1, 4);
  int accepted = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    Bytes b = good;
    for (int k = howMany(rng); k > 0; --k) b[position(rng)] = static_cast<char>(byte(rng));
    fixChecksum(b);
    std::istringstream in(b, std::ios::binary);
    try {
      readMra(in, "fuzz.mra");
      ++accepted;
    } catch (const Error&) {
    } catch (const std::exception& e) {
      ADD_FAILURE() << "trial " << trial << ": non-Error exception: " << e.what();
    }
  }
  // Most damage lands in coefficients, which any finite value makes valid again.
  EXPECT_GT(accepted, 0);
}

TEST(MraFile, ChecksumCatchesValueCorruption) {
  Bytes b = toBytes(makeDecomposition(1, false, false));
  b[b.size() - 20] ^= 0x10;  // inside the last detail coefficient
  EXPECT_NE(readError(b).find("checksum mismatch: file is corrupt"), std::string::npos);
}

TEST(MraFile, ForeignFilesAreRecognised) {
  for (const Bytes& foreign : {Bytes(""), Bytes("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"),
                               Bytes("\x89PNG\r\n\x1a\n....", 12), Bytes("OSDMRA")})
    EXPECT_NE(readError(foreign).find("not an osdmra coefficient file"), std::string::npos)
        << readError(foreign);
  // What a text-mode transfer does to the signature.
  Bytes b = toBytes(makeDecomposition(0, false, false));
  b.erase(4, 1);
  EXPECT_NE(readError(b).find("line endings"), std::string::npos) << readError(b);
}

TEST(MraFile, OtherVersionsAreRejectedByName) {
  for (std::uint32_t version : {0u, 2u, 0xFFFFFFFFu}) {
    Bytes b = toBytes(makeDecomposition(1, false, false));
    putU32(b, kVersionAt, version);
    fixChecksum(b);
    const std::string message = readError(b);
    EXPECT_NE(message.find("version " + std::to_string(version) + " is not supported"),
              std::string::npos)
        << message;
    EXPECT_NE(message.find("reads version 1"), std::string::npos) << message;
  }
}

TEST(MraFile, AbsurdCountsAreRejectedBeforeAllocating) {
  const Bytes good = toBytes(makeDecomposition(2, true, true));
  const std::size_t level0At = kFacesAt + 8 * 12 + 6 * 24;
  const std::size_t level1At = level0At + 4 + 12 * 24;
  const std::size_t orderAt = level1At + 4 + 48 * 24;
  const std::size_t inputFacesAt = orderAt + 4 + 66 * 4;
  struct Case {
    std::size_t at;
    std::uint32_t value;
    const char* expect;
  };
  for (const Case& k :
       {Case{kVertexCountAt, 0xFFFFFFFFu, "exceeds the limit"},
        Case{kVertexCountAt, 0x7FFFFFFFu, "remain"}, Case{kFaceCountAt, 0x7FFFFFFFu, "remain"},
        Case{kFaceCountAt, 0, "no faces"}, Case{kLevelsAt, 16, "outside 0..15"},
        Case{kLevelsAt, 0xFFFFFFFFu, "outside 0..15"},
        Case{level0At, 0x7FFFFFFFu, "adds one vertex per edge: 12"},
        Case{level1At, 47, "adds one vertex per edge: 48"}, Case{orderAt, 0xFFFFFFFFu, "neither 0"},
        Case{inputFacesAt, 127, "neither 0"}}) {
    Bytes b = good;
    putU32(b, k.at, k.value);
    fixChecksum(b);
    const std::string message = readError(b);
    EXPECT_NE(message.find(k.expect), std::string::npos) << message;
    EXPECT_NE(message.find("byte offset " + std::to_string(k.at)), std::string::npos) << message;
  }
}

TEST(MraFile, ValuesOutOfRangeAreRejectedEvenWithAValidChecksum) {
  const Bytes good = toBytes(makeDecomposition(1, true, true));
  const std::size_t positionsAt = kFacesAt + 8 * 12;
  const std::size_t orderAt = positionsAt + 6 * 24 + 4 + 12 * 24;
  const auto withByte = [&](std::size_t at, unsigned char v) {
    Bytes b = good;
    b[at] = static_cast<char>(v);
    fixChecksum(b);
    return readError(b);
  };
  EXPECT_NE(withByte(kSchemeAt, 2).find("scheme"), std::string::npos);
  EXPECT_NE(withByte(kKindAt, 4).find("wavelet kind"), std::string::npos);
  EXPECT_NE(withByte(kRingsAt + 3, 0x80).find("negative"), std::string::npos);
  EXPECT_NE(withByte(kFacesAt + 4, 9).find("outside 0..5"), std::string::npos);
  EXPECT_NE(withByte(kFacesAt + 4, 0).find("repeats a vertex"), std::string::npos);
  // 0x7FF0... in the top bytes of a double: infinity or NaN.
  Bytes b = good;
  b[positionsAt + 7] = 0x7F;
  b[positionsAt + 6] = static_cast<char>(0xF0);
  fixChecksum(b);
  EXPECT_NE(readError(b).find("not finite"), std::string::npos) << readError(b);
  // inputOrder entry 1 := entry 0.
  b = good;
  std::memcpy(&b[orderAt + 8], &b[orderAt + 4], 4);
  fixChecksum(b);
  EXPECT_NE(readError(b).find("not a permutation"), std::string::npos) << readError(b);
  b = good + "x";
  EXPECT_NE(readError(b).find("1 trailing bytes"), std::string::npos) << readError(b);
}

TEST(MraFile, ReadErrorsNameTheFile) {
  TempDir dir;
  const std::string missing = dir.file("nope.mra");
  expectContains(errorOf([&] { readMra(missing); }), {missing});
  EXPECT_THROW(readMra(dir.path().string()), Error);
  const std::string obj = dir.write("mesh.obj", "v 0 0 0\n");
  expectContains(errorOf([&] { readMra(obj); }), {obj + ": not an osdmra coefficient file"});
}
