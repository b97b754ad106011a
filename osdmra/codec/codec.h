// The progressive wavelet geometry codec: a surface with subdivision connectivity,
// analysed by a filter bank (mra/filter_bank.h), to a .osz stream (osz_format.h)
// whose every prefix decodes to the same connectivity with coarser geometry.
//
// After Khodakovsky, Schroder and Sweldens, "Progressive Geometry Compression"
// (SIGGRAPH 2000):
//   1. the base mesh: connectivity, and c^0 quantised finely (it moves everything);
//   2. the wavelet coefficients d^j, expressed in local frames of the surface the
//      decoder has already rebuilt (local_frames.h), weighted so that one step of
//      quantisation costs about the same error at every level and more on the
//      normal component than the tangential ones, quantised by one uniform step;
//   3. their bit planes, coarse planes first, by an edge zerotree (zerotree.h) and a
//      context-adaptive range coder (range_coder.h).
// The connectivity of levels 1..J costs nothing: it follows from the base and J.
//
// The frames of level j come from c^j as the decoder rebuilds it, so the encoder
// rebuilds the same c^j from the quantised coefficients ("closed loop") before it
// expresses d^j in them: a complete stream decodes to within the quantisation bound,
// bit for bit as the encoder predicted. A prefix decodes with frames of a coarser
// c^j, the small price of progressivity.
//
// Error measure (PSNR): 20 log10(diagonal / RMS), with the diagonal of the original
// full-resolution surface's bounding box and RMS the sampled symmetric distance
// between the decoded and the original surfaces (PsnrMeasure::Surface), or the root
// mean square distance between their corresponding vertices (Vertices).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "osdmra/codec/osz_format.h"
#include "osdmra/geometry/distance.h"
#include "osdmra/mra/filter_bank.h"

namespace osdmra {

struct CodecOptions {
  /// Finest quantisation step of a normal component at the finest level, relative to
  /// the bounding-box diagonal: a complete stream is within about this of the input
  /// (PSNR about 20 log10(sqrt(12) / precision), 109 dB at 1e-5). Rate targets cut
  /// the stream earlier.
  double precision = 1e-5;
  /// Coefficients of level j are weighted levelGain^(J-1-j) before quantisation, so a
  /// coarse coefficient, which moves a larger region, is coded more precisely. 2 would
  /// be the L2 norm ratio of scaling functions one level apart (support area 1/4); by
  /// sampled surface distance 1.5 codes better from 1.5 bits per vertex up (bench/
  /// osdmra_codec_rd --level-gain, 2026-11-28, dB of 1.5 against 2 at 0.75 / 1.5 / 2.5 /
  /// 3.5 / 5 bits per vertex on J = 5 remeshes over 300 faces: spot -0.7 / +1.8 / +0.3 /
  /// +1.2 / +0.8, the rocker arm -0.8 / +0.3 / +1.5 / +1.1 / +0.5, the elephant -0.8 /
  /// +1.4 / +1.8 / +1.2 / +0.3; the bunny and armadillo +1.3 and +1.2 at 1.5, +1.2 and
  /// +0.2 at 2.5; the head with Loop -0.1 / 0.0 at 0.75 / 1.5, +0.3 / +0.3 / +0.2 at 3.5
  /// / 7 / 10), where the streams reach 85-95 dB; 0.7-0.8 dB worse at 0.75. 1.25 and
  /// 2.5 were worse than both. Over the other ten shared scans' remeshes, not uniform:
  /// on average +0.04 / +0.50 / +0.32 dB at 0.75 / 1.5 / 2.5, better on six or seven
  /// (up to +1.8), worse on the cow, the decimated knight and the screwdriver (-0.6 to
  /// -1.0 at 1.5 and 2.5) and bumpy-cube at 1.5 (-0.2). Measured again with the bend's
  /// tangential weights (2026-12-03; the head, the bunny's, the rocker arm's and the
  /// elephant's remeshes): 1.75 is 0.3-0.6 dB better at 0.75 bits per vertex and 0.1-0.4
  /// worse from 3.5 up; 1.25 is 0.1-2.2 dB worse at 0.75 and within -1.2 / +0.2 above.
  double levelGain = 1.5;
  /// Tangential components are weighted relative to the normal one by how much the
  /// coarser surface bends at their edge (LocalFrames::bend, b): w = clamp(bendGain
  /// b, tangentFloor, tangentWeight). Sliding a new vertex by t along the surface
  /// moves the finer surface by about t times the angle its faces make with its
  /// normal, about half the coarser one's at a level one finer (so bendGain 0.5);
  /// where the surface is flat sliding costs almost nothing and the floor bounds how
  /// coarse the step gets. With bendGain 0 (or floor = weight) every tangential
  /// component has the weight tangentWeight, as in format version 2.
  ///
  /// Measured by sampled surface distance (bench/osdmra_codec_rd --bend-gain 0
  /// --tangent-floor 0.25 against the defaults, 2026-12-03 16:05-16:13 UTC), on the J = 5
  /// remeshes over 300 faces of all 16 shared scans (the polyhedral scheme), dB at 0.75
  /// / 1.5 / 3.5 / 5 bits per vertex: -0.06 to +0.93 / -0.04 to +1.14 / +0.03 to +3.56 /
  /// +0.19 to +4.04 (but fandisk, whose whole stream is under 3.5 bits per vertex:
  /// 112.0 dB against 112.6; the bunny -0.06 / +0.14 / +0.69 / +1.89, armadillo -0.01 / -0.04 /
  /// +0.03 / +0.19, the elephant +0.14 / +0.33 / +2.05 / +3.31), at 7 bits per vertex
  /// +0.72 to +2.73 where the streams stay under the whole stream's precision (about
  /// 109 dB; there, where the constant weight reached 109.7-112.6 dB, 0.1-2.0 dB
  /// less: the floor's step is the whole stream's tangential precision); on the head
  /// with Loop -0.04 / +0.15 / +0.46 and +1.20 / +1.21 at 7 / 10. On six meshes never
  /// used for tuning (J = 5 over 300 faces; odedstein's hand and lion statue, libigl's
  /// bunny and camel, alecjacobson's homer and nefertiti; 16:36-16:40 UTC), at 0.75 /
  /// 1.5 / 3.5 / 5: -0.13 to +0.28 / -0.11 to +0.97 / +0.01 to +2.37 / +0.21 to +3.10
  /// (the lion statue -0.13 / -0.11 / +0.01 / +0.21). Tried alongside (the
  /// head, the bunny, armadillo and spot): a floor of 1/32 or 1/8, a gain of 0.25 or 1,
  /// and no cap (tangentWeight 1), each worse on some of them.
  ///
  /// The constant weight before (measured on the bundled head, dB at 0.75 / 1.5 / 3.5 /
  /// 7 / 10 bits per vertex): 0.5: 61.7 / 67.3 / 75.8 / 84.9 / 92.2; 0.25: 61.9 / 67.5 /
  /// 76.1 / 87.3 / 94.5; 0.125: 61.7 / 67.1 / 75.9 / 87.5 / 95.2; on the bunny's remesh
  /// (0.75 / 1.5 / 2.5 / 3.5 / 5) 1: 73.4 / 78.3 / 82.3 / 86.6 / 90.1; 0.25: 75.9 / 81.2
  /// / 86.0 / 90.7 / 95.6; 0.0625: 72.2 / 77.4 / 82.8 / 87.8 / 94.9.
  double tangentWeight = 0.25;
  /// The smallest tangential weight, (0, tangentWeight].
  double tangentFloor = 1.0 / 16;
  /// Tangential weight per unit of bend, >= 0 (0: tangentWeight everywhere).
  double bendGain = 0.5;
  /// Measure Compressed::psnrSurface (one sampled surface distance, about as long as
  /// the encoding on large meshes); NaN when off. PSNR targets measure it anyway.
  bool measureSurface = true;
  /// The sampled surface distance behind the surface PSNR (the CLI's --samples and
  /// --seed). A PSNR target measures it at every step of its search: fewer samples
  /// search faster, with a coarser measure.
  DistanceOptions distance;
};

/// What the RMS of a PSNR is taken over.
enum class PsnrMeasure {
  /// The sampled symmetric distance between the two surfaces (surfaceDistance with
  /// CodecOptions::distance, by default 100,000 samples a side plus every vertex), what
  /// docs/COMPRESSION.md reports: sliding along the surface costs nothing.
  Surface,
  /// The distance between corresponding vertices: fast, and counts tangential
  /// error in full.
  Vertices,
};

/// Where to cut the stream: its whole length, a size, or the shortest prefix that
/// reaches a PSNR.
struct RateTarget {
  enum class Kind { Whole, Bytes, Psnr };
  Kind kind = Kind::Whole;
  double value = 0;                            ///< bytes (of the whole file), or dB
  PsnrMeasure measure = PsnrMeasure::Surface;  ///< for Kind::Psnr
  static RateTarget whole() { return {}; }
  static RateTarget bytes(double n) { return {Kind::Bytes, n}; }
  static RateTarget psnr(double dB, PsnrMeasure m = PsnrMeasure::Surface) {
    return {Kind::Psnr, dB, m};
  }
  /// Bits per vertex of the finest level, as bytes for a surface of `vertices`.
  static RateTarget bitsPerVertex(double b, long long vertices) {
    return {Kind::Bytes, b * static_cast<double>(vertices) / 8};
  }
};

/// What compress() made.
struct Compressed {
  std::vector<std::uint8_t> bytes;  ///< the .osz file
  std::size_t wholeBytes = 0;       ///< size of the uncut stream
  std::size_t baseBytes = 0;        ///< header and base mesh (before any coefficient)
  double psnrSurface = 0;           ///< of the decode of `bytes` against the input
  double psnrVertices = 0;          ///< the same by corresponding vertices
  int planes = 0;                   ///< bit planes in the uncut stream
};

/// Encodes the surface `d` (the analysis of `finest` by `bank`) and cuts the stream
/// at `target`. `finest` (canonical order) is the reference of the PSNR. Throws
/// Error when the target cannot be met: a size below the header and base mesh, or a
/// PSNR above what the whole stream reaches (raise precision).
Compressed compress(const FilterBank& bank, const Decomposition& d, const Points& finest,
                    const RateTarget& target = {}, const CodecOptions& options = {});

struct DecodeOptions {
  /// Refuse streams whose finest level has more triangles than this (the decoder
  /// allocates the whole hierarchy; a few bytes can describe a huge mesh).
  long long maxFaces = 1LL << 24;
};

/// A decoded stream.
struct Decompressed {
  TriMesh mesh;  ///< level J, canonical order (hierarchy.h)
  Scheme scheme = Scheme::Loop;
  WaveletOptions wavelets;
  int levels = 0;
  bool cut = false;       ///< the bytes end before the stream does
  bool complete = false;  ///< every bit plane was decoded
  int planes = 0, planesDecoded = 0;
};

/// Decodes a .osz stream or any prefix of one that holds its header and base mesh.
/// Throws Error, starting with `name`, for anything else.
Decompressed decompress(const std::uint8_t* data, std::size_t size, const std::string& name,
                        const DecodeOptions& options = {});

/// 20 log10(diagonal / RMS) over corresponding rows; +inf for identical points.
double psnr(const Points& decoded, const Points& reference, double diagonal);
/// 20 log10(1 / rmsRelative) of surfaceDistance(decoded, reference, options) (the
/// reference's diagonal); +inf for identical surfaces.
double surfacePsnr(const TriMesh& decoded, const TriMesh& reference,
                   const DistanceOptions& options = {});

}  // namespace osdmra
