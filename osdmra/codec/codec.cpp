#include "osdmra/codec/codec.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <future>
#include <limits>

#include "osdmra/base/error.h"
#include "osdmra/codec/local_frames.h"
#include "osdmra/codec/range_coder.h"
#include "osdmra/codec/zerotree.h"
#include "osdmra/geometry/distance.h"

namespace osdmra {

namespace {

// ---- Quantisation ------------------------------------------------------------------

// World units of one quantisation step of the normal component of level j: the
// weighted value v = x * gain^(J-1-j) is quantised with the step, so x's step is
// step / gain^(J-1-j). Both sides compute it from the header's f32 values.
double normalStep(const OszHeader& h, int j) {
  return static_cast<double>(h.step) / std::pow(static_cast<double>(h.levelGain), h.levels - 1 - j);
}

// The weight of the tangential components of edge e, from how much the coarser surface
// bends there (CodecOptions::bendGain).
double tangentWeight(const OszHeader& h, const LocalFrames& f, Eigen::Index e) {
  const double w = static_cast<double>(h.bendGain) * f.bend[e];
  return std::clamp(w, static_cast<double>(h.tangentFloor), static_cast<double>(h.tangentWeight));
}

// World units of one step of each component of edge e, in the frames f, where the
// normal component's step is `normal` (normalStep, once per level).
std::array<double, 3> componentSteps(double normal, const OszHeader& h, const LocalFrames& f,
                                     Eigen::Index e) {
  const double tangential = normal / tangentWeight(h, f, e);
  return {normal, tangential, tangential};
}

// The detail vectors of level j from per-component values in steps (row e, component
// c at 3e + c), in the frames of c^j.
Points detailsFromSteps(const OszHeader& h, int j, const LocalFrames& frames,
                        const std::vector<double>& steps) {
  Points local(frames.normal.rows(), 3);
  const double normal = normalStep(h, j);
  for (Eigen::Index e = 0; e < local.rows(); ++e) {
    const std::array<double, 3> unit = componentSteps(normal, h, frames, e);
    for (int c = 0; c < 3; ++c) local(e, c) = steps[3 * static_cast<std::size_t>(e) + c] * unit[c];
  }
  return toWorld(frames, local);
}

// Level j's coefficients as integers of steps in the frames of the decoder's c^j.
std::vector<std::int32_t> quantiseLevel(const OszHeader& h, int j, const LocalFrames& frames,
                                        const Points& detail) {
  const Points local = toLocal(frames, detail);
  std::vector<std::int32_t> q(3 * static_cast<std::size_t>(local.rows()));
  const double limit = std::ldexp(1.0, kMaxPlanes) - 1, normal = normalStep(h, j);
  for (Eigen::Index e = 0; e < local.rows(); ++e) {
    const std::array<double, 3> unit = componentSteps(normal, h, frames, e);
    for (int c = 0; c < 3; ++c) {
      const double v = std::trunc(local(e, c) / unit[c]);  // dead zone around 0 (SPIHT's)
      if (!(std::abs(v) <= limit))
        throw Error("compress: a coefficient of level " + std::to_string(j) +
                    " is too large for the quantisation step; lower the precision");
      q[3 * static_cast<std::size_t>(e) + c] = static_cast<std::int32_t>(v);
    }
  }
  return q;
}

// ---- The base mesh ------------------------------------------------------------------

// Origin and step of the base positions: the step matches a weight of gain^J (one
// level coarser than level 0), as fine as 30 bits of the base's extent allow.
void chooseBaseQuantiser(OszHeader& h, const Points& base) {
  const Eigen::RowVector3d lo = base.colwise().minCoeff(), hi = base.colwise().maxCoeff();
  for (int i = 0; i < 3; ++i) h.baseOrigin[i] = std::nextafter(static_cast<float>(lo[i]), -1e30f);
  const double extent = std::max((hi - lo).maxCoeff(), 1e-30) * 1.001 + 1e-30;
  double step = h.step / std::pow(static_cast<double>(h.levelGain), h.levels);
  step = std::max(step, extent / std::ldexp(1.0, 30));
  h.baseStep = static_cast<float>(step);
  h.baseBits = 1;
  while (h.baseBits < 31 && std::ldexp(1.0, h.baseBits) * h.baseStep <= extent + 2.0 * h.baseStep)
    ++h.baseBits;
}

std::vector<std::int64_t> quantiseBase(const OszHeader& h, const Points& base) {
  std::vector<std::int64_t> k(3 * static_cast<std::size_t>(base.rows()));
  const std::int64_t top = (std::int64_t{1} << h.baseBits) - 1;
  for (Eigen::Index v = 0; v < base.rows(); ++v)
    for (int i = 0; i < 3; ++i) {
      const double x = (base(v, i) - h.baseOrigin[i]) / h.baseStep;
      k[3 * v + i] = std::clamp<std::int64_t>(std::llround(x), 0, top);
    }
  return k;
}

Points dequantiseBase(const OszHeader& h, const std::vector<std::int64_t>& k) {
  Points base(static_cast<Eigen::Index>(k.size() / 3), 3);
  for (Eigen::Index v = 0; v < base.rows(); ++v)
    for (int i = 0; i < 3; ++i)
      base(v, i) = static_cast<double>(h.baseOrigin[i]) +
                   static_cast<double>(k[3 * v + i]) * static_cast<double>(h.baseStep);
  return base;
}

std::vector<std::uint8_t> encodeBase(const OszHeader& h, const Faces& F,
                                     const std::vector<std::int64_t>& k) {
  RangeEncoder enc;
  const int ib = baseIndexBits(h.baseVertices);
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int i = 0; i < 3; ++i) enc.encodeBits(static_cast<std::uint32_t>(F(f, i)), ib);
  for (std::int64_t v : k) enc.encodeBits(static_cast<std::uint32_t>(v), h.baseBits);
  return enc.finish();
}

struct BaseMesh {
  Faces faces;
  std::vector<std::int64_t> coordinates;
};

BaseMesh decodeBase(const OszHeader& h, const std::vector<std::uint8_t>& bytes,
                    const std::string& name) {
  RangeDecoder dec(bytes.data(), bytes.size());
  const int ib = baseIndexBits(h.baseVertices);
  BaseMesh b;
  b.faces.resize(h.baseFaces, 3);  // bounded by the chunk's size (readOsz)
  for (int f = 0; f < h.baseFaces; ++f)
    for (int i = 0; i < 3; ++i) {
      const std::uint32_t v = dec.decodeBits(ib);
      if (v >= static_cast<std::uint32_t>(h.baseVertices))
        throw Error(name + ": base face " + std::to_string(f) + " names vertex " +
                    std::to_string(v) + " of " + std::to_string(h.baseVertices));
      b.faces(f, i) = static_cast<int>(v);
    }
  b.coordinates.resize(3 * static_cast<std::size_t>(h.baseVertices));
  for (std::int64_t& v : b.coordinates) v = dec.decodeBits(h.baseBits);
  if (dec.exhausted()) throw Error(name + ": the base mesh is shorter than its counts");
  return b;
}

// ---- Both directions -----------------------------------------------------------------

// c^J from the base and every level's values in steps (what reconstruct() gives).
Points rebuild(const FilterBank& bank, const OszHeader& h, Points c,
               const std::vector<std::vector<double>>& steps) {
  for (int j = 0; j < h.levels; ++j)
    c = synthesisStep(bank, j, c,
                      detailsFromSteps(h, j, edgeFrames(*bank.hierarchy, j, c), steps[j]));
  return c;
}

// Per level, whether each wavelet's coefficient (three steps) is nonzero.
std::vector<std::vector<char>> nonzeroWavelets(const std::vector<std::vector<double>>& steps) {
  std::vector<std::vector<char>> nonzero(steps.size());
  for (std::size_t j = 0; j < steps.size(); ++j) {
    nonzero[j].assign(steps[j].size() / 3, 0);
    for (std::size_t i = 0; i < steps[j].size(); ++i)
      if (steps[j][i] != 0) nonzero[j][i / 3] = 1;
  }
  return nonzero;
}

// The zerotree of the first `size` bytes of coefficient data.
ZerotreeState decodeCoefficients(const EdgeTree& tree, const OszHeader& h,
                                 const std::vector<std::uint8_t>& data, std::size_t size) {
  RangeDecoder dec(data.data(), std::min(size, data.size()));
  return decodeZerotree(tree, h.topPlane, dec);
}

// The decode of the first `size` bytes of coefficient data.
Points decodePrefix(const FilterBank& bank, const EdgeTree& tree, const OszHeader& h,
                    const Points& base, const std::vector<std::uint8_t>& data, std::size_t size) {
  return rebuild(bank, h, base, reconstruct(decodeCoefficients(tree, h, data, size)));
}

OszHeader makeHeader(const FilterBank& bank, const Points& finest, const CodecOptions& o) {
  const Hierarchy& hier = *bank.hierarchy;
  if (hier.levels() < 1) throw Error("compress: the surface needs at least one level of detail");
  if (!(o.precision > 0) || !(o.levelGain >= 1 && o.levelGain <= 4) ||
      !(o.tangentWeight > 0 && o.tangentWeight <= 1) ||
      !(o.tangentFloor > 0 && o.tangentFloor <= o.tangentWeight) ||
      !(o.bendGain >= 0 && o.bendGain <= 1e6))
    throw Error(
        "compress: CodecOptions out of range (precision > 0, levelGain in [1, 4], "
        "tangentWeight in (0, 1], tangentFloor in (0, tangentWeight], bendGain in [0, 1e6])");
  OszHeader h;
  h.scheme = bank.scheme;
  h.wavelets = bank.wavelets;
  h.levels = hier.levels();
  h.baseVertices = hier.numVertices(0);
  h.baseFaces = hier.numFaces(0);
  h.step = static_cast<float>(o.precision * std::max(boundingBoxDiagonal(finest), 1e-30));
  h.levelGain = static_cast<float>(o.levelGain);
  h.tangentWeight = static_cast<float>(o.tangentWeight);
  h.tangentFloor = static_cast<float>(o.tangentFloor);
  h.bendGain = static_cast<float>(o.bendGain);
  return h;
}

// The uncut stream.
struct Encoding {
  OszFile file;
  Points base;  ///< c^0 as the decoder has it
  EdgeTree tree;
};

Encoding encode(const FilterBank& bank, const Decomposition& d, const Points& finest,
                const CodecOptions& o) {
  const Hierarchy& hier = *bank.hierarchy;
  Encoding out;
  OszHeader& h = out.file.header;
  h = makeHeader(bank, finest, o);
  chooseBaseQuantiser(h, d.base);
  const std::vector<std::int64_t> k = quantiseBase(h, d.base);
  out.file.base = encodeBase(h, hier.faces(0), k);
  out.base = dequantiseBase(h, k);
  // Closed loop: each level in the frames of the c^j the decoder will have.
  QuantisedLevels q(h.levels);
  Points c = out.base;
  for (int j = 0; j < h.levels; ++j) {
    const LocalFrames frames = edgeFrames(hier, j, c);  // once for both directions
    q[j] = quantiseLevel(h, j, frames, d.details[j]);
    std::vector<double> steps(q[j].size());
    std::transform(q[j].begin(), q[j].end(), steps.begin(), reconstructed);
    c = synthesisStep(bank, j, c, detailsFromSteps(h, j, frames, steps));
  }
  h.topPlane = topPlane(q);
  out.tree = edgeTree(hier);
  RangeEncoder enc;
  encodeZerotree(out.tree, q, h.topPlane, enc);
  out.file.coefficients = enc.finish();
  return out;
}

// A decoded prefix and its PSNR by the target's measure.
struct Measured {
  std::size_t bytes = 0;
  Points decoded;
  double quality = 0;
};

// The coefficient bytes to keep for the target. For a PSNR target, `kept` receives
// the decode and PSNR of the cut, measured on the way (the search's last success).
std::size_t cutFor(const FilterBank& bank, const Encoding& e, const Points& finest,
                   const RateTarget& target, const DistanceOptions& distance, Measured& kept) {
  const std::size_t all = e.file.coefficients.size(), baseBytes = e.file.base.size();
  if (target.kind == RateTarget::Kind::Whole) return all;
  if (target.kind == RateTarget::Kind::Bytes) {
    if (!(target.value >= static_cast<double>(oszSize(baseBytes, 0))))
      throw Error("compress: " + std::to_string(static_cast<long long>(target.value)) +
                  " bytes cannot hold the header and base mesh (" +
                  std::to_string(oszSize(baseBytes, 0)) + " bytes)");
    std::size_t lo = 0, hi = all;  // largest cut whose file fits
    while (lo < hi) {
      const std::size_t mid = lo + (hi - lo + 1) / 2;
      if (static_cast<double>(oszSize(baseBytes, mid)) <= target.value)
        lo = mid;
      else
        hi = mid - 1;
    }
    return lo;
  }
  const double diagonal = boundingBoxDiagonal(finest);
  const TriMesh reference{finest, bank.hierarchy->faces(bank.hierarchy->levels()), Points()};
  const auto measure = [&](std::size_t n) {
    Measured m;
    m.bytes = n;
    m.decoded = decodePrefix(bank, e.tree, e.file.header, e.base, e.file.coefficients, n);
    m.quality = target.measure == PsnrMeasure::Vertices
                    ? psnr(m.decoded, finest, diagonal)
                    : surfacePsnr(TriMesh{m.decoded, reference.F, Points()}, reference, distance);
    return m;
  };
  kept = measure(all);
  if (kept.quality < target.value)
    throw Error("compress: the whole stream reaches " + std::to_string(kept.quality) +
                " dB, below the target " + std::to_string(target.value) +
                " dB; raise the precision");
  std::size_t lo = 0, hi = all;  // smallest cut that reaches the target
  while (lo < hi) {
    const std::size_t mid = lo + (hi - lo) / 2;
    Measured m = measure(mid);
    if (m.quality >= target.value) {
      hi = mid;
      kept = std::move(m);  // hi is always the last cut that reached it
    } else {
      lo = mid + 1;
    }
  }
  return lo;
}

}  // namespace

double psnr(const Points& decoded, const Points& reference, double diagonal) {
  if (decoded.rows() != reference.rows() || reference.rows() == 0)
    throw Error("psnr: the surfaces have different vertex counts");
  const double rms = std::sqrt((decoded - reference).rowwise().squaredNorm().mean());
  if (rms == 0) return std::numeric_limits<double>::infinity();
  return 20 * std::log10(diagonal / rms);
}

double surfacePsnr(const TriMesh& decoded, const TriMesh& reference,
                   const DistanceOptions& options) {
  const SurfaceDistance d = surfaceDistance(decoded, reference, options);
  if (d.rmsRelative == 0) return std::numeric_limits<double>::infinity();
  return -20 * std::log10(d.rmsRelative);
}

Compressed compress(const FilterBank& bank, const Decomposition& d, const Points& finest,
                    const RateTarget& target, const CodecOptions& options) {
  if (!bank.hierarchy || finest.rows() != bank.hierarchy->numVertices(bank.hierarchy->levels()))
    throw Error("compress: the reference surface does not match the filter bank's hierarchy");
  Encoding e = encode(bank, d, finest, options);
  Compressed out;
  out.wholeBytes = oszSize(e.file.base.size(), e.file.coefficients.size());
  out.baseBytes = oszSize(e.file.base.size(), 0);
  out.planes = e.file.header.topPlane + 1;
  Measured kept;
  const std::size_t keep = cutFor(bank, e, finest, target, options.distance, kept);
  // A PSNR search has decoded the cut already (and measured it by its measure).
  const bool searched = target.kind == RateTarget::Kind::Psnr && kept.bytes == keep;
  const Points c =
      searched ? std::move(kept.decoded)
               : decodePrefix(bank, e.tree, e.file.header, e.base, e.file.coefficients, keep);
  const Faces& F = bank.hierarchy->faces(bank.hierarchy->levels());
  out.psnrVertices = psnr(c, finest, boundingBoxDiagonal(finest));
  if (!options.measureSurface)
    out.psnrSurface = std::numeric_limits<double>::quiet_NaN();
  else if (searched && target.measure == PsnrMeasure::Surface)
    out.psnrSurface = kept.quality;
  else
    out.psnrSurface =
        surfacePsnr(TriMesh{c, F, Points()}, TriMesh{finest, F, Points()}, options.distance);
  e.file.coefficients.resize(keep);
  out.bytes = writeOsz(e.file);
  return out;
}

Decompressed decompress(const std::uint8_t* data, std::size_t size, const std::string& name,
                        const DecodeOptions& options) {
  const OszFile f = readOsz(data, size, name, options.maxFaces);
  const OszHeader& h = f.header;
  const BaseMesh b = decodeBase(h, f.base, name);
  TriMesh base{dequantiseBase(h, b.coordinates), b.faces, Points()};
  validate(base, name + ": base mesh");
  const Hierarchy hier(base.F, h.baseVertices, h.levels, h.scheme);
  // The refinement matrices and the filter bank (without the wavelet norms: synthesis
  // needs only alpha), and the zerotree's decoding, each need only the hierarchy's
  // faces and edges: on two cores they run side by side. Local corrections are built
  // level by level, finest first, by whichever thread is free (the zerotree's is
  // once it is decoded, early at low rates).
  FilterBank bank;
  bank.scheme = h.scheme;
  bank.wavelets = h.wavelets;
  bank.hierarchy = &hier;
  bank.alpha.resize(h.levels);
  std::atomic<int> claimed{0};
  const auto takeLevels = [&] {
    for (int k = claimed++; k < h.levels; k = claimed++)
      localCorrections(hier, h.scheme, h.wavelets.kind, h.levels - 1 - k,
                       bank.alpha[h.levels - 1 - k]);
  };
  const bool local = correctionsAreLocal(h.wavelets);
  std::future<void> second = std::async(std::launch::async, [&] {
    hier.prepareRefinement();
    if (local) takeLevels();
  });
  const ZerotreeState state =
      decodeCoefficients(edgeTree(hier), h, f.coefficients, f.coefficients.size());
  if (local) takeLevels();
  second.get();
  const std::vector<std::vector<double>> steps = reconstruct(state);
  // Solved corrections (quasi-wavelets) only for the wavelets the stream made nonzero:
  // at the rates a stream is cut to, most are zero, and their columns add nothing.
  if (!local) bank.alpha = waveletCorrections(hier, h.scheme, h.wavelets, nonzeroWavelets(steps));
  Decompressed out;
  out.mesh.V = rebuild(bank, h, base.V, steps);
  // Finite fields can still multiply out of range (a huge step, a coefficient of
  // 2^29 steps): such a stream cannot be an encoder's.
  if (!out.mesh.V.allFinite())
    throw Error(name + ": the stream decodes to non-finite positions (corrupt quantiser fields)");
  out.mesh.F = hier.faces(h.levels);
  out.scheme = h.scheme;
  out.wavelets = h.wavelets;
  out.levels = h.levels;
  out.cut = f.cut;
  out.complete = state.complete;
  out.planes = h.topPlane + 1;
  out.planesDecoded = state.planesDone;
  return out;
}

}  // namespace osdmra
