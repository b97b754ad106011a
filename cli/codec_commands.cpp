// compress and decompress: the progressive geometry codec (osdmra/codec/codec.h)
// from the command line.
#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <iterator>
#include <limits>
#include <optional>

#include "commands.h"
#include "common.h"
#include "osdmra/base/file.h"
#include "osdmra/codec/codec.h"
#include "osdmra/mesh/io.h"
#include "report.h"

namespace osdmra::cli {
namespace {

// --psnr, --bits-per-vertex or --bytes (at most one); the whole stream otherwise.
RateTarget rateTarget(const Args& args, long long vertices) {
  const int given = args.has("psnr") + args.has("bits-per-vertex") + args.has("bytes");
  if (given > 1) throw Error("compress: give at most one of --psnr, --bits-per-vertex and --bytes");
  if (args.has("psnr")) {
    const std::string how = args.get("psnr-measure", "surface");
    if (how != "surface" && how != "vertices")
      throw Error("compress: --psnr-measure must be surface or vertices, got '" + how + "'");
    return RateTarget::psnr(args.real("psnr", 0, 1, 300),
                            how == "surface" ? PsnrMeasure::Surface : PsnrMeasure::Vertices);
  }
  if (args.has("bits-per-vertex"))
    return RateTarget::bitsPerVertex(args.real("bits-per-vertex", 0, 1e-6, 1e6), vertices);
  if (args.has("bytes"))
    return RateTarget::bytes(static_cast<double>(args.integer("bytes", 0, 1, 1LL << 40)));
  return RateTarget::whole();
}

CodecOptions codecOptions(const Args& args) {
  CodecOptions o;
  o.precision = args.real("precision", o.precision, 1e-9, 0.5);
  readCodecWeights(args, o);
  o.distance = distanceOptions(args);
  return o;
}

std::vector<std::uint8_t> readBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path + ": cannot open");
  std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)),
                                  std::istreambuf_iterator<char>());
  if (in.bad()) throw Error(path + ": read error");
  return bytes;
}

double bitsPerVertex(std::size_t bytes, long long vertices) {
  return 8.0 * static_cast<double>(bytes) / static_cast<double>(vertices);
}

const char* choiceCriterion(const RateTarget& target) {
  switch (target.kind) {
    case RateTarget::Kind::Bytes:
      return "psnr at the size asked";
    case RateTarget::Kind::Psnr:
      return "bytes at the psnr asked";
    default:
      return "whole stream bytes";
  }
}

void printChoice(const CodingSchemeChoice& c, const RateTarget& target) {
  const bool loop = c.scheme == Scheme::Loop;
  if (target.kind == RateTarget::Kind::Bytes)
    std::printf("scheme %s: %.2f dB at this size, the other's %.2f (--scheme forces one)\n",
                schemeName(c.scheme), loop ? c.loopPsnr : c.linearPsnr,
                loop ? c.linearPsnr : c.loopPsnr);
  else if ((loop ? c.linearBytes : c.loopBytes) == 0)  // the other not searched
    std::printf(
        "scheme %s: its stream at this PSNR is %zu bytes; the other's does not reach the "
        "PSNR at that length (--scheme forces one)\n",
        schemeName(c.scheme), loop ? c.loopBytes : c.linearBytes);
  else
    std::printf("scheme %s: its %s is %zu bytes, the other's %zu (--scheme forces one)\n",
                schemeName(c.scheme),
                target.kind == RateTarget::Kind::Psnr ? "stream at this PSNR" : "whole stream",
                loop ? c.loopBytes : c.linearBytes, loop ? c.linearBytes : c.loopBytes);
}

Json choiceJson(const CodingSchemeChoice& c, const RateTarget& target) {
  Json j = Json::object().add("criterion", choiceCriterion(target));
  if (target.kind == RateTarget::Kind::Bytes)
    return j.add("loop_psnr", c.loopPsnr).add("linear_psnr", c.linearPsnr);
  // null for a scheme not searched (short of the PSNR at the other's length).
  const auto size = [](std::size_t b) {
    return b ? static_cast<double>(b) : std::numeric_limits<double>::quiet_NaN();
  };
  if (target.kind == RateTarget::Kind::Psnr)
    return j.add("loop_bytes", size(c.loopBytes)).add("linear_bytes", size(c.linearBytes));
  return j.add("loop_whole_bytes", static_cast<long long>(c.loopBytes))
      .add("linear_whole_bytes", static_cast<long long>(c.linearBytes));
}

}  // namespace

int cmdCompress(const Argv& argv) {
  Args args("compress", argv,
            withRemeshOptions({"output", "psnr", "bits-per-vertex", "bytes", "levels", "scheme",
                               "wavelets", "rings", "precision", "tangent-weight", "tangent-floor",
                               "bend-gain", "level-gain", "psnr-measure", "samples", "seed"}),
            flags({"remesh"}));
  args.expectPositional(1, "one input surface: osdmra compress IN -o OUT.osz");
  const Common opt = common(args);
  const std::string in = args.positional()[0], out = args.require("output");
  AnalysisOptions options = analysisOptions(args);
  options.approximator = false;
  options.norms = false;
  // Fixed wavelets by default: within 0.1 dB of quasi-wavelets, and a decoder builds
  // them without a local solve (docs/COMPRESSION.md). --rings asks for quasi-wavelets.
  if (!args.has("wavelets") && !args.has("rings")) options.wavelets = {WaveletKind::Fixed, 0};
  const CodecOptions codec = codecOptions(args);
  const auto t0 = Clock::now();
  const LoadedSurface s = loadInput(in, args, opt);
  const double tRead = seconds(t0);
  // Without --scheme, the one whose stream is better at the rate asked on this surface
  // (the surface keeps its vertices: level J has as many).
  const RateTarget target = rateTarget(args, static_cast<long long>(s.mesh.V.rows()));
  std::optional<CodingSchemeChoice> choice;
  if (!args.has("scheme")) choice = chooseCodingScheme(s.mesh, options, codec, in, target);
  const double tChoose = seconds(t0) - tRead;
  const AnalysedSurface a =
      choice ? std::move(*choice->surface) : AnalysedSurface(s.mesh, options, in, opt.progress);
  const long long vertices = a.hierarchy().numVertices(a.levels());
  const auto t1 = Clock::now();
  const Compressed z = choice ? std::move(*choice->compressed) : compress(a, target, codec);
  const double tEncode = choice ? 0.0 : seconds(t1);
  writeFileAtomically(out, [&](std::ostream& o) {
    o.write(reinterpret_cast<const char*>(z.bytes.data()),
            static_cast<std::streamsize>(z.bytes.size()));
  });
  if (!opt.json) {
    if (s.remeshing) printRemesh(in, *s.remeshing);
    std::printf("%s: %lld vertices, %d %s levels over %d base faces\n", in.c_str(), vertices,
                a.levels(), schemeName(a.bank().scheme), a.hierarchy().numFaces(0));
    std::printf(
        "wrote %s: %zu bytes (%.3f bits per vertex), PSNR %.2f dB (surface distance); whole stream "
        "%zu bytes\n",
        out.c_str(), z.bytes.size(), bitsPerVertex(z.bytes.size(), vertices), z.psnrSurface,
        z.wholeBytes);
    if (choice) printChoice(*choice, target);
    if (choice)
      std::printf("time: read %.3f s, both schemes analysed and coded %.3f s\n", tRead, tChoose);
    else
      std::printf("time: read %.3f s, analysis %.3f s, encoding %.3f s\n", tRead, a.times().total(),
                  tEncode);
    return 0;
  }
  Json j = startJson(s);
  if (choice) j.add("scheme_choice", choiceJson(*choice, target));
  std::cout << j.add("command", "compress")
                   .add("input", in)
                   .add("output", out)
                   .add("scheme", schemeName(a.bank().scheme))
                   .add("wavelets", waveletKindName(a.bank().wavelets.kind))
                   .add("rings", a.bank().wavelets.rings)
                   .add("levels", a.levels())
                   .add("vertices", vertices)
                   .add("faces", a.hierarchy().numFaces(a.levels()))
                   .add("bytes", static_cast<long long>(z.bytes.size()))
                   .add("bits_per_vertex", bitsPerVertex(z.bytes.size(), vertices))
                   .add("psnr", z.psnrSurface)
                   .add("psnr_vertices", z.psnrVertices)
                   .add("whole_bytes", static_cast<long long>(z.wholeBytes))
                   .add("header_and_base_bytes", static_cast<long long>(z.baseBytes))
                   .add("bit_planes", z.planes)
                   .add("seconds", Json::object()
                                       .add("read", tRead)
                                       .add("choose_scheme", tChoose)
                                       .add("analysis", a.times().total())
                                       .add("encode", tEncode))
                   .str()
            << "\n";
  return 0;
}

int cmdDecompress(const Argv& argv) {
  Args args("decompress", argv, {"output", "bytes"}, flags());
  args.expectPositional(1, "one compressed surface: osdmra decompress IN.osz -o OUT");
  const Common opt = common(args);
  const std::string in = args.positional()[0], out = args.require("output");
  meshFormatForWriting(out);  // refuse a bad output name before the work
  const auto t0 = Clock::now();
  std::vector<std::uint8_t> bytes = readBytes(in);
  const std::size_t size = bytes.size();
  if (args.has("bytes"))
    bytes.resize(std::min<std::size_t>(bytes.size(), args.integer("bytes", 0, 0, 1LL << 40)));
  const double tRead = seconds(t0);
  const auto t1 = Clock::now();
  const Decompressed d = decompress(bytes.data(), bytes.size(), in);
  const double tDecode = seconds(t1);
  writeMesh(out, d.mesh);
  const long long vertices = d.mesh.V.rows();
  if (!opt.json) {
    std::printf("%s: %zu of %zu bytes, %d of %d bit planes%s\n", in.c_str(), bytes.size(), size,
                d.planesDecoded, d.planes, d.cut ? " (a prefix)" : "");
    std::printf("wrote %s: %lld vertices, %d faces (%d %s levels); decoding %.3f s\n", out.c_str(),
                vertices, static_cast<int>(d.mesh.F.rows()), d.levels, schemeName(d.scheme),
                tDecode);
    return 0;
  }
  std::cout << Json::object()
                   .add("command", "decompress")
                   .add("input", in)
                   .add("output", out)
                   .add("bytes", static_cast<long long>(bytes.size()))
                   .add("file_bytes", static_cast<long long>(size))
                   .add("bits_per_vertex", bitsPerVertex(bytes.size(), vertices))
                   .add("cut", d.cut)
                   .add("complete", d.complete)
                   .add("bit_planes", d.planes)
                   .add("bit_planes_decoded", d.planesDecoded)
                   .add("scheme", schemeName(d.scheme))
                   .add("wavelets", waveletKindName(d.wavelets.kind))
                   .add("levels", d.levels)
                   .add("vertices", vertices)
                   .add("faces", static_cast<int>(d.mesh.F.rows()))
                   .add("seconds", Json::object().add("read", tRead).add("decode", tDecode))
                   .str()
            << "\n";
  return 0;
}

}  // namespace osdmra::cli
