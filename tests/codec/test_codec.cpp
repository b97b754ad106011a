// The geometry codec (codec/codec.h): whole streams within the quantisation bound,
// prefixes that decode with falling error, rate targets, and damaged streams that
// are an Error and never a crash.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <string>

#include "osdmra/base/error.h"
#include "osdmra/codec/codec.h"
#include "osdmra/subdivision/shapes.h"
#include "support.h"

namespace osdmra {
namespace {

// A displaced subdivision surface, analysed: what compress() takes.
struct Surface {
  TriMesh mesh;
  Hierarchy hierarchy;
  FilterBank bank;
  Decomposition d;
  Surface(const std::string& shape, int J, Scheme scheme, WaveletOptions w = {},
          double amplitude = 0.02)
      : mesh(subdivide(shapes::byName(shape), J, scheme, amplitude, 5)),
        hierarchy(shapes::byName(shape).F, static_cast<int>(shapes::byName(shape).V.rows()), J),
        bank(makeFilterBank(hierarchy, scheme, w)),
        d(analyze(bank, mesh.V)) {}
};

Decompressed decode(const std::vector<std::uint8_t>& bytes, std::size_t size) {
  return decompress(bytes.data(), std::min(size, bytes.size()), "test.osz");
}

// The largest coordinate error quantisation can leave, from the synthesis of
// math.md 4: c^{j+1} = P (c^j - alpha d^j) + E d^j with P's rows of non-negative
// weights summing to 1, so an error grows by at most (1 + |alpha|_inf) |d error|
// per level. Per component the dead-zone quantiser errs by less than one step.
double errorBound(const Surface& s, const CodecOptions& o) {
  const int J = s.hierarchy.levels();
  const double diag = boundingBoxDiagonal(s.mesh.V);
  const double step = o.precision * diag;
  const Points& c0 = s.d.base;
  const double extent = (c0.colwise().maxCoeff() - c0.colwise().minCoeff()).maxCoeff();
  double bound = std::max(step / std::pow(o.levelGain, J), extent * 1.001 / std::ldexp(1.0, 30));
  for (int j = 0; j < J; ++j) {
    double alphaNorm = 0;
    const SparseMatrix a = s.bank.alpha[j];  // row-major: rows are coarse vertices
    for (int r = 0; r < a.outerSize(); ++r) {
      double sum = 0;
      for (SparseMatrix::InnerIterator it(a, r); it; ++it) sum += std::abs(it.value());
      alphaNorm = std::max(alphaNorm, sum);
    }
    const double unit = step / std::pow(o.levelGain, J - 1 - j);
    // Tangential steps are at most the floor's (CodecOptions::bendGain).
    const double vector = unit * std::sqrt(1 + 2 / (o.tangentFloor * o.tangentFloor));
    bound += (1 + alphaNorm) * vector;
  }
  return bound * (1 + 1e-6);  // f32 header values
}

TEST(Codec, WholeStreamsAreWithinTheQuantisationBound) {
  struct Case {
    const char* shape;
    int J;
    Scheme scheme;
    WaveletKind kind;
  };
  for (const Case& c : {Case{"octahedron", 4, Scheme::Loop, WaveletKind::Quasi},
                        Case{"octahedron", 4, Scheme::Linear, WaveletKind::Lazy},
                        Case{"torus", 3, Scheme::Loop, WaveletKind::Lazy},
                        Case{"disc", 3, Scheme::Loop, WaveletKind::Quasi},
                        Case{"cylinder", 3, Scheme::Linear, WaveletKind::Quasi},
                        Case{"valences", 3, Scheme::Loop, WaveletKind::Fixed},
                        Case{"disc", 3, Scheme::Linear, WaveletKind::Fixed}}) {
    SCOPED_TRACE(std::string(c.shape) + " " + schemeName(c.scheme));
    WaveletOptions w;
    w.kind = c.kind;
    if (c.kind != WaveletKind::Quasi) w.rings = 0;
    const Surface s(c.shape, c.J, c.scheme, w);
    for (double precision : {1e-3, 1e-5}) {
      CodecOptions o;
      o.precision = precision;
      o.measureSurface = false;  // the bound is on vertices; the surface measure is slow
      const Compressed z = compress(s.bank, s.d, s.mesh.V, RateTarget::whole(), o);
      const Decompressed back = decode(z.bytes, z.bytes.size());
      EXPECT_TRUE(back.complete);
      EXPECT_FALSE(back.cut);
      EXPECT_EQ(back.levels, c.J);
      EXPECT_EQ(back.scheme, c.scheme);
      ASSERT_EQ(back.mesh.F, s.hierarchy.faces(c.J));  // the connectivity, free
      const double worst = (back.mesh.V - s.mesh.V).cwiseAbs().maxCoeff();
      EXPECT_LE(worst, errorBound(s, o)) << "precision " << precision;
      // The encoder's PSNR is the decoder's.
      EXPECT_DOUBLE_EQ(z.psnrVertices, psnr(back.mesh.V, s.mesh.V, boundingBoxDiagonal(s.mesh.V)));
      EXPECT_EQ(z.bytes.size(), z.wholeBytes);
    }
  }
}

// Where the surface is flat, sliding along it costs nothing: its tangential components
// get the floor's step, so tangential details cost fewer bits than with one weight
// everywhere, and still decode within the floor's bound.
TEST(Codec, TangentialStepsFollowTheBend) {
  const TriMesh square = test::unitSquare();
  const Hierarchy h(square.F, static_cast<int>(square.V.rows()), 4);
  Points fine = subdivide(square, 4, Scheme::Linear, 0, 1).V;  // flat, z = 0
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> slide(-0.01, 0.01);
  for (Eigen::Index v = square.V.rows(); v < fine.rows(); ++v) {
    fine(v, 0) += slide(rng);
    fine(v, 1) += slide(rng);
  }
  const FilterBank bank = makeFilterBank(h, Scheme::Linear, WaveletOptions{WaveletKind::Lazy, 0});
  const Decomposition d = analyze(bank, fine);
  CodecOptions bent, constant;
  bent.precision = constant.precision = 1e-4;
  bent.measureSurface = constant.measureSurface = false;
  constant.bendGain = 0;
  constant.tangentFloor = constant.tangentWeight;
  const Compressed a = compress(bank, d, fine, RateTarget::whole(), bent);
  const Compressed b = compress(bank, d, fine, RateTarget::whole(), constant);
  EXPECT_LT(a.bytes.size(), b.bytes.size() * 3 / 4);
  const Decompressed back = decode(a.bytes, a.bytes.size());
  EXPECT_LT(back.mesh.V.col(2).cwiseAbs().maxCoeff(), 1e-12);  // nothing leaves the plane
  const double step = bent.precision * boundingBoxDiagonal(fine) / bent.tangentFloor;
  const double worst = (back.mesh.V - fine).cwiseAbs().maxCoeff();
  EXPECT_LE(worst, 4 * step);  // at most one step per level of the lazy synthesis
}

TEST(Codec, FinerPrecisionCostsMoreAndErrsLess) {
  const Surface s("octahedron", 4, Scheme::Loop);
  double lastPsnr = 0;
  std::size_t lastSize = 0;
  for (double precision : {1e-2, 1e-3, 1e-4, 1e-5}) {
    CodecOptions o;
    o.precision = precision;
    o.tangentWeight = o.tangentFloor = 1;  // every component on the same step
    o.measureSurface = false;
    const Compressed z = compress(s.bank, s.d, s.mesh.V, RateTarget::whole(), o);
    EXPECT_GT(z.psnrVertices, lastPsnr + 10) << precision;  // 20 dB per decade, roughly
    EXPECT_GT(z.bytes.size(), lastSize) << precision;
    lastPsnr = z.psnrVertices;
    lastSize = z.bytes.size();
  }
}

// Strictly falling error holds plane by plane: once a bit plane is whole, every
// coefficient's interval has halved. Inside a plane, a refinement bit can move one
// coefficient's value away from it (the middle of the lower half is farther from a
// value just below the old middle), the frames of finer levels turn as coarser
// levels sharpen, and the wavelets are not orthogonal; so a prefix is only promised
// to be no worse than the last whole plane it holds.
TEST(Codec, EveryPrefixDecodesAndItsErrorFallsWithLength) {
  for (Scheme scheme : {Scheme::Loop, Scheme::Linear}) {
    SCOPED_TRACE(schemeName(scheme));
    const Surface s("icosahedron", 4, scheme);
    CodecOptions o;
    o.measureSurface = false;  // prefixes are measured by vertices below
    const Compressed z = compress(s.bank, s.d, s.mesh.V, RateTarget::whole(), o);
    const double diag = boundingBoxDiagonal(s.mesh.V);
    // Too short for the header and base mesh: an Error that says so.
    for (std::size_t size : {std::size_t{0}, std::size_t{5}, std::size_t{60}, z.baseBytes - 13})
      test::expectContains(test::errorOf([&] { decode(z.bytes, size); }),
                           {"test.osz", "truncated"});
    std::vector<std::size_t> sizes;
    for (std::size_t size = z.baseBytes - 12; size < z.bytes.size(); size += z.bytes.size() / 80)
      sizes.push_back(size);
    sizes.push_back(z.bytes.size());
    std::vector<double> wholePlanes;  // the PSNR when plane k was first whole
    int planes = -1;
    double last = 0;
    for (std::size_t size : sizes) {
      const Decompressed p = decode(z.bytes, size);
      ASSERT_EQ(p.mesh.F, s.hierarchy.faces(4)) << size;
      ASSERT_TRUE(p.mesh.V.allFinite()) << size;
      EXPECT_EQ(p.cut, size < z.bytes.size());
      ASSERT_GE(p.planesDecoded, planes);
      last = psnr(p.mesh.V, s.mesh.V, diag);
      if (p.planesDecoded > planes) {
        if (!wholePlanes.empty()) {
          EXPECT_GT(last, wholePlanes.back()) << size;
        }
        wholePlanes.push_back(last);
        planes = p.planesDecoded;
      }
      EXPECT_GE(last, wholePlanes.back()) << size << " of " << z.bytes.size() << " bytes";
    }
    EXPECT_GE(wholePlanes.size(), 10u);  // the sampling saw most planes complete
    EXPECT_DOUBLE_EQ(last, z.psnrVertices);
  }
}

TEST(Codec, RateTargetsAreMet) {
  const Surface s("octahedron", 4, Scheme::Loop);
  // A PSNR search measures the surface at each step: 5,000 samples a side keep it
  // quick (the targets hold for whatever measure the options give).
  CodecOptions o;
  o.distance.samples = 5000;
  const Compressed whole = compress(s.bank, s.d, s.mesh.V, RateTarget::whole(), o);
  for (double fraction : {0.1, 0.3, 0.6}) {
    const double target = fraction * static_cast<double>(whole.bytes.size());
    const Compressed z = compress(s.bank, s.d, s.mesh.V, RateTarget::bytes(target), o);
    EXPECT_LE(static_cast<double>(z.bytes.size()), target);
    EXPECT_GE(static_cast<double>(z.bytes.size()), 0.95 * target);  // within 5%
    // What the encoder reports is what a decoder gets.
    const Decompressed back = decode(z.bytes, z.bytes.size());
    EXPECT_DOUBLE_EQ(z.psnrVertices, psnr(back.mesh.V, s.mesh.V, boundingBoxDiagonal(s.mesh.V)));
    EXPECT_FALSE(back.cut);  // a cut stream, but a whole file
  }
  for (PsnrMeasure measure : {PsnrMeasure::Surface, PsnrMeasure::Vertices})
    for (double dB : {40.0, 55.0, 70.0}) {
      const auto got = [&](const Compressed& z) {
        return measure == PsnrMeasure::Surface ? z.psnrSurface : z.psnrVertices;
      };
      const Compressed z = compress(s.bank, s.d, s.mesh.V, RateTarget::psnr(dB, measure), o);
      EXPECT_GE(got(z), dB);
      // The shortest stream that does it: one byte less falls short, unless the base
      // mesh alone reaches the target.
      if (z.bytes.size() == z.baseBytes) continue;
      const Compressed shorter = compress(
          s.bank, s.d, s.mesh.V, RateTarget::bytes(static_cast<double>(z.bytes.size()) - 1), o);
      EXPECT_LT(got(shorter), dB);
    }
  // The surface measure forgives sliding along the surface: above the vertex one.
  const Compressed z = compress(s.bank, s.d, s.mesh.V, RateTarget::bytes(3000), o);
  EXPECT_GT(z.psnrSurface, z.psnrVertices);
  test::expectContains(
      test::errorOf([&] { compress(s.bank, s.d, s.mesh.V, RateTarget::bytes(20)); }),
      {"cannot hold the header and base mesh"});
  test::expectContains(
      test::errorOf([&] { compress(s.bank, s.d, s.mesh.V, RateTarget::psnr(300)); }),
      {"below the target"});
}

TEST(Codec, EverySingleByteCorruptionOfAWholeFileIsAnError) {
  const Surface s("tetrahedron", 3, Scheme::Loop);
  CodecOptions o;
  o.precision = 1e-3;
  const std::vector<std::uint8_t> good = compress(s.bank, s.d, s.mesh.V, {}, o).bytes;
  for (std::size_t i = 0; i < good.size(); ++i)
    for (std::uint8_t flip : {0x01, 0x80, 0xFF}) {
      std::vector<std::uint8_t> b = good;
      b[i] ^= flip;
      test::expectContains(test::errorOf([&] { decode(b, b.size()); }), {"test.osz"});
    }
}

// ---- Fuzz -------------------------------------------------------------------------

// Recomputes the checksums of a (possibly damaged) .osz file in place, so that
// damage reaches the checks behind them. Stops where the layout no longer parses.
void fixChecksums(std::vector<std::uint8_t>& b) {
  const auto u32 = [&](std::size_t at) {
    std::uint32_t v = 0;
    for (int i = 0; i < 4; ++i) v |= std::uint32_t{b[at + i]} << (8 * i);
    return v;
  };
  const auto put = [&](std::size_t at, std::uint32_t v) {
    for (int i = 0; i < 4; ++i) b[at + i] = static_cast<std::uint8_t>(v >> (8 * i));
  };
  std::size_t at = 9;
  if (b.size() < at + 8) return;
  const std::size_t head = u32(at + 4);
  if (b.size() < at + 12 + head) return;
  put(at + 8 + head, crc32(b.data() + at, 8 + head));
  at += 12 + head;
  if (b.size() < at + 12) return;
  const std::size_t n = u32(at + 4);
  put(at + 8, crc32(b.data() + at, 8));
  at += 12;
  for (std::size_t done = 0; done < n && at < b.size(); done += kOszBlock) {
    const std::size_t len = std::min(kOszBlock, n - done);
    if (b.size() < at + len + 4) return;
    put(at + len, crc32(b.data() + at, len));
    at += len + 4;
  }
}

// Streams of format version 2 (one tangential weight, 8 bytes fewer in HEAD) still
// decode, to what a version 3 stream of the same weights decodes to.
TEST(Codec, ReadsFormatVersion2Streams) {
  const Surface s("torus", 3, Scheme::Loop);
  CodecOptions o;
  o.precision = 1e-4;
  o.measureSurface = false;
  o.bendGain = 0;
  o.tangentFloor = o.tangentWeight;
  const std::vector<std::uint8_t> v3 = compress(s.bank, s.d, s.mesh.V, {}, o).bytes;
  std::vector<std::uint8_t> v2 = v3;
  ASSERT_EQ(v2[8], 3);
  v2[8] = 2;
  const std::size_t payload = 9 + 8;  // after the HEAD tag and length
  v2.erase(v2.begin() + payload + kHeadFixedBytes - 8, v2.begin() + payload + kHeadFixedBytes);
  v2[13] = static_cast<std::uint8_t>(v2[13] - 8);  // HEAD length, little-endian (< 256 here)
  ASSERT_LT(v3[13], 255);
  fixChecksums(v2);
  EXPECT_EQ(decode(v2, v2.size()).mesh.V, decode(v3, v3.size()).mesh.V);
  v2[8] = 1;
  test::expectContains(test::errorOf([&] { decode(v2, v2.size()); }),
                       {"test.osz", "format version 1", "reads versions 2 and 3"});
}

TEST(CodecFuzz, DamagedStreamsDecodeOrThrowError) {
  const Surface s("octahedron", 2, Scheme::Loop);
  CodecOptions o;
  o.precision = 1e-3;
  const std::vector<std::uint8_t> good = compress(s.bank, s.d, s.mesh.V, {}, o).bytes;
  std::mt19937 rng(2024);
  std::uniform_int_distribution<int> byte(0, 255), howMany(1, 4);
  int decoded = 0, rejected = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    std::vector<std::uint8_t> b = good;
    const int edits = howMany(rng);
    for (int k = 0; k < edits; ++k) {
      const std::size_t at = std::uniform_int_distribution<std::size_t>(0, b.size() - 1)(rng);
      switch (rng() % 4) {
        case 0:  // overwrite a byte
          b[at] = static_cast<std::uint8_t>(byte(rng));
          break;
        case 1:  // cut
          b.resize(at);
          break;
        case 2:  // insert
          b.insert(b.begin() + static_cast<std::ptrdiff_t>(at),
                   static_cast<std::uint8_t>(byte(rng)));
          break;
        default:  // delete
          b.erase(b.begin() + static_cast<std::ptrdiff_t>(at));
          break;
      }
      if (b.empty()) break;
    }
    if (trial % 2) fixChecksums(b);  // half of them reach the checks behind the CRCs
    try {
      const Decompressed d = decode(b, b.size());
      ASSERT_TRUE(d.mesh.V.allFinite()) << trial;
      ++decoded;
    } catch (const Error& e) {
      ++rejected;
      ASSERT_EQ(std::string(e.what()).rfind("test.osz", 0), 0u) << e.what();
    } catch (const std::exception& e) {
      FAIL() << "trial " << trial << ": non-osdmra exception " << e.what();
    }
  }
  EXPECT_GT(decoded, 100);
  EXPECT_GT(rejected, 100);
}

TEST(CodecFuzz, CountsAreCheckedBeforeAllocation) {
  const Surface s("octahedron", 2, Scheme::Loop);
  std::vector<std::uint8_t> b = compress(s.bank, s.d, s.mesh.V).bytes;
  // Claim 2^31 - 1 base faces (offset 9 + 8 + 8: after the tag, length and codes).
  const std::size_t f0 = 9 + 8 + 8;
  for (int i = 0; i < 4; ++i) b[f0 + i] = i == 3 ? 0x7F : 0xFF;
  fixChecksums(b);
  test::expectContains(test::errorOf([&] { decode(b, b.size()); }),
                       {"test.osz", "base mesh needs"});
  // And a stream whose finest level exceeds the decoder's limit.
  std::vector<std::uint8_t> big = compress(s.bank, s.d, s.mesh.V).bytes;
  DecodeOptions small;
  small.maxFaces = 100;
  test::expectContains(
      test::errorOf([&] { decompress(big.data(), big.size(), "test.osz", small); }),
      {"test.osz", "exceed the limit of 100 triangles"});
}

}  // namespace
}  // namespace osdmra
