// osdmra: the command-line front end. Thin: every computation is a library call;
// this file parses arguments, reads and writes files, times the work, and prints
// a human summary (or, with --json, one JSON object on stdout). Errors are
// osdmra::Error from anywhere below, printed as "osdmra: <message>" with exit 1.
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <queue>
#include <sstream>

#include "args.h"
#include "json.h"
#include "osdmra/mra/approximation.h"
#include "osdmra/base/bundled_data.h"
#include "osdmra/geometry/distance.h"
#include "osdmra/base/error.h"
#include "osdmra/mra/filter_bank.h"
#include "osdmra/mra/gram.h"
#include "osdmra/mesh/io.h"
#include "osdmra/mra/mra_file.h"
#include "osdmra/subdivision/recovery.h"
#include "osdmra/remesh/remesh.h"
#include "osdmra/subdivision/shapes.h"
#include "osdmra/mra/truncation.h"

namespace osdmra::cli {
namespace {

using Clock = std::chrono::steady_clock;
double seconds(Clock::time_point since) {
  return std::chrono::duration<double>(Clock::now() - since).count();
}

const char* kUsage = R"(osdmra: wavelet multiresolution analysis of subdivision surfaces
(Lounsbery, DeRose and Warren 1993) on OpenSubdiv.

usage: osdmra <command> [options]

commands:
  info IN                      topology of a mesh, and its subdivision connectivity
                               (levels, base mesh) found from connectivity alone
  subdivide BASE --levels J -o OUT [--scheme loop|linear] [--displace A --seed N]
                               refine a base mesh J times (a test surface when
                               displaced by noise at every level)
  analyze IN -o OUT.mra [--levels J] [--scheme loop|linear]
                 [--wavelets lazy|quasi|pre] [--rings R] [--remesh ...]
                               decompose a surface with subdivision connectivity (any
                               vertex and face order) into base mesh + wavelet details;
                               any other mesh with --remesh [--base-faces N] (then
                               --levels J is the remesh's; see remesh)
  synthesize IN.mra -o OUT [--level j] [--keep F | --epsilon E] [--importance scaled|plain]
                               rebuild the surface (or its level-j approximation),
                               optionally from the most important coefficients only
  lod IN (--epsilon E | --budget N | --keep F) -o OUT [--scheme S] [--rings R]
                 [--importance scaled|plain] [--exact] [--samples N --seed S]
                               crack-free adaptive mesh from the most important
                               coefficients, on the truncated surface (Loop: limit
                               positions and normals), with its errors; the
                               coefficients of vertices the mesh has anyway are kept
                               too (no extra triangle) unless --exact; --remesh as
                               for analyze (its distance reported apart)
  remesh IN --base-faces N --levels J -o OUT [--feature-angle A]
                               any manifold triangle mesh (any genus, boundaries) to
                               subdivision connectivity: a base of about N faces
                               (default 300) split J times (default 5), positions
                               on the input; reports the distance to the input and
                               any flipped, zero-area or crossing triangles left,
                               with a warning on stderr (and in the JSON) if any
                               are, if the result is over 1% of the diagonal from
                               the input somewhere, or if the base has more faces
                               than asked (it keeps tips of protrusions)
  sweep IN --csv OUT.csv [--plot OUT.png] [--points K] [lod's options]
                               error against triangle count over the whole range
  mask IN --level j --vertex i [--scheme loop|linear]
                               subdivision and inner-product masks around a vertex
                               of level j over the base mesh IN (paper, Fig. 4, 5)
  orthogonality BASE --level j [--scheme S] [--max-rings R]
                               how close lazy, quasi (r = 0..R) and pre-wavelets of
                               level j over BASE are to orthogonal
  shape NAME -o OUT            write a built-in base mesh (tetrahedron, octahedron,
                               icosahedron, torus, genus2, genus3, disc, cylinder,
                               valences)
  demo [IN] [--out DIR] [--remesh ...]
                               the paper's example on the bundled scanned head (or IN,
                               remeshed first with --remesh as for analyze): analyse
                               and rebuild it, levels of detail of 4,054, 12,310 and
                               16,098 triangles, their errors, error-against-triangles
                               sweeps and plots, all written to DIR (default out/)

common options:
  --json        print a JSON summary on stdout instead of text
  --progress    report progress on stderr (default when stderr is a terminal)
  --quiet       no progress
  -h, --help    help for a command

Meshes: .obj, .off, .ply (ascii or binary). Errors name the file, the line or
element, and what is wrong; the exit status is then 1 and no output is written.
)";

struct Common {
  bool json = false;
  Progress progress;
};

Common common(const Args& args) {
  Common c;
  c.json = args.has("json");
  const bool show = args.has("progress") || (!args.has("quiet") && isatty(STDERR_FILENO));
  if (show)
    c.progress = [](const char* stage, double fraction) {
      std::fprintf(stderr, "\r%-12s %3d%%%s", stage, static_cast<int>(fraction * 100 + 0.5),
                   fraction >= 1.0 ? "\n" : "");
      std::fflush(stderr);
    };
  return c;
}

const std::set<std::string> kCommonFlags = {"json", "progress", "quiet", "help", "h"};
std::set<std::string> flags(std::set<std::string> extra = {}) {
  extra.insert(kCommonFlags.begin(), kCommonFlags.end());
  return extra;
}

WaveletOptions waveletOptions(const Args& args) {
  WaveletOptions w;
  const std::string kind = args.get("wavelets", "quasi");
  if (kind == "lazy")
    w.kind = WaveletKind::Lazy;
  else if (kind == "quasi")
    w.kind = WaveletKind::Quasi;
  else if (kind == "pre")
    w.kind = WaveletKind::Pre;
  else
    throw Error("--wavelets must be lazy, quasi or pre, got '" + kind + "'");
  w.rings = static_cast<int>(args.integer("rings", kDefaultRings, 0, 8));
  if (w.kind != WaveletKind::Quasi) w.rings = 0;
  return w;
}

// Topology summary shared by info and the other commands' JSON.
Json topologyJson(const TriMesh& mesh, const Connectivity& c) {
  const int loops = c.numBoundaryLoops(), components = c.numComponents();
  const int chi = c.eulerCharacteristic();
  int vmin = 1 << 30, vmax = 0;
  for (int v = 0; v < c.numVertices(); ++v) {
    vmin = std::min(vmin, c.valence(v));
    vmax = std::max(vmax, c.valence(v));
  }
  return Json::object()
      .add("vertices", static_cast<int>(mesh.V.rows()))
      .add("faces", static_cast<int>(mesh.F.rows()))
      .add("edges", c.numEdges())
      .add("components", components)
      .add("boundary_loops", loops)
      .add("euler_characteristic", chi)
      .add("genus", (2 * components - chi - loops) / 2)
      .add("valence_min", vmin)
      .add("valence_max", vmax)
      .add("bbox_diagonal", boundingBoxDiagonal(mesh.V));
}

int cmdInfo(const std::vector<std::string>& argv) {
  Args args("info", argv, {}, flags());
  args.expectPositional(1, "one input mesh: osdmra info IN");
  const Common opt = common(args);
  const std::string in = args.positional()[0];
  const TriMesh mesh = readValidMesh(in);
  const Connectivity c(mesh.F, static_cast<int>(mesh.V.rows()));
  Json j = topologyJson(mesh, c);
  const auto t0 = Clock::now();
  const Recovery r = recoverSubdivision(mesh.F, static_cast<int>(mesh.V.rows()));
  const double tRecover = seconds(t0);
  const std::string structure = describe(r);
  j.add("levels", r.levels).add("structure", structure);
  if (r.levels > 0) {
    const TriMesh base{Points::Zero(r.numBaseVertices, 3), r.baseFaces, Points()};
    const Connectivity bc(r.baseFaces, r.numBaseVertices);
    j.add("base", topologyJson(base, bc).add("arbitrary_choice", r.arbitraryChoice));
  }
  if (!r.stopReason.empty()) j.add("next_level_fails_because", r.stopReason);
  j.add("recover_seconds", tRecover);
  if (opt.json) {
    std::cout << Json::object().add("file", in).add("mesh", j).str() << "\n";
    return 0;
  }
  const int components = c.numComponents(), loops = c.numBoundaryLoops();
  std::cout << in << ": " << mesh.V.rows() << " vertices, " << mesh.F.rows() << " faces, "
            << c.numEdges() << " edges\n"
            << "  components " << components << ", boundary loops " << loops << ", genus "
            << (2 * components - c.eulerCharacteristic() - loops) / 2 << "\n"
            << "  bounding-box diagonal " << boundingBoxDiagonal(mesh.V) << "\n"
            << "  " << structure << "\n";
  if (r.levels > 0 && !r.stopReason.empty())
    std::cout << "  (one level further down fails: " << r.stopReason << ")\n";
  return 0;
}

int cmdSubdivide(const std::vector<std::string>& argv) {
  Args args("subdivide", argv, {"levels", "scheme", "displace", "seed", "output"}, flags());
  args.expectPositional(1, "one base mesh: osdmra subdivide BASE --levels J -o OUT");
  const Common opt = common(args);
  const std::string in = args.positional()[0], out = args.require("output");
  const int J = static_cast<int>(args.integer("levels", -1, 0, 15));
  if (J < 0) throw Error("subdivide: missing required option --levels");
  const Scheme scheme = parseScheme(args.get("scheme", "loop"));
  const double amplitude = args.real("displace", 0.0, 0.0, 1e6);
  const long long seed = args.integer("seed", 1, 0, (1LL << 62));
  const TriMesh base = readValidMesh(in);
  const auto t0 = Clock::now();
  const TriMesh surface = subdivide(base, J, scheme, amplitude, static_cast<std::uint64_t>(seed));
  writeMesh(out, surface);
  const double t = seconds(t0);
  if (opt.json) {
    std::cout << Json::object()
                     .add("command", "subdivide")
                     .add("input", in)
                     .add("output", out)
                     .add("scheme", schemeName(scheme))
                     .add("levels", J)
                     .add("displace", amplitude)
                     .add("seed", seed)
                     .add("vertices", static_cast<int>(surface.V.rows()))
                     .add("faces", static_cast<int>(surface.F.rows()))
                     .add("seconds", t)
                     .str()
              << "\n";
  } else {
    std::cout << "wrote " << out << ": " << surface.V.rows() << " vertices, " << surface.F.rows()
              << " faces (" << J << " " << schemeName(scheme) << " levels over " << in << ")\n";
  }
  return 0;
}

// The surface of `mesh` in canonical form, with its level count given or found.
DistanceOptions distanceOptions(const Args& args) {
  DistanceOptions o;
  o.samples = static_cast<int>(args.integer("samples", 100000, 0, 100000000));
  o.seed = static_cast<std::uint64_t>(args.integer("seed", 1, 0, 1LL << 62));
  return o;
}

// An input surface brought to subdivision connectivity by remesh() (--remesh), with
// what that cost and how far the result is from the input: reported apart from the
// truncation error, which is measured against the remeshed surface.
struct Remeshed {
  bool used = false;
  int requestedBaseFaces = 0;
  int droppedVertices = 0;
  int inputVertices = 0, inputFaces = 0;
  Remeshing result;
  SurfaceDistance distance;
  double seconds = 0;
};

RemeshOptions remeshOptions(const Args& args) {
  RemeshOptions o;
  o.baseFaces = static_cast<int>(args.integer("base-faces", o.baseFaces, 4, 1 << 24));
  o.levels = static_cast<int>(args.integer("levels", o.levels, 0, 8));
  o.featureAngle = args.real("feature-angle", o.featureAngle, 0.0, 180.0);
  return o;
}

// What a user should know about a remeshing before relying on it: defects the
// clean-up left, and a result far from the input somewhere (docs/REMESH.md).
constexpr double kFarRemesh = 0.01;  // of the bounding-box diagonal
std::vector<std::string> remeshWarnings(const Remeshed& r) {
  std::vector<std::string> out;
  const Remeshing& x = r.result;
  if (x.flippedTriangles + x.degenerateTriangles > 0 || x.selfIntersections > 0)
    out.push_back(std::to_string(x.flippedTriangles) + " flipped, " +
                  std::to_string(x.degenerateTriangles) + " zero-area triangles and " +
                  std::to_string(x.selfIntersections) +
                  " crossing pairs are left; another --base-faces or --levels may avoid them");
  const int baseFaces = static_cast<int>(x.base.F.rows());
  if (baseFaces > r.requestedBaseFaces)
    out.push_back("the base has " + std::to_string(baseFaces) + " faces, more than the " +
                  std::to_string(r.requestedBaseFaces) +
                  " asked for: no other vertex could go without changing the topology or "
                  "flattening the tip of a protrusion");
  if (r.distance.hausdorffRelative > kFarRemesh) {
    char buf[320];
    std::snprintf(buf, sizeof buf,
                  "the remeshed surface is %.2f%% of the bounding-box diagonal from the input "
                  "at its farthest (over %.0f%%): raise --levels for finer sampling, or "
                  "--base-faces if thin or protruding parts of the input are missed",
                  100 * r.distance.hausdorffRelative, 100 * kFarRemesh);
    out.push_back(buf);
  }
  return out;
}

Remeshed remeshFile(const std::string& in, const Args& args, const Common& opt) {
  Remeshed r;
  TriMesh mesh = readMesh(in);
  r.droppedVertices = removeUnreferencedVertices(mesh);
  validate(mesh, in);
  r.inputVertices = static_cast<int>(mesh.V.rows());
  r.inputFaces = static_cast<int>(mesh.F.rows());
  const auto t0 = Clock::now();
  try {
    const RemeshOptions options = remeshOptions(args);
    r.requestedBaseFaces = options.baseFaces;
    r.result = remesh(mesh, options, opt.progress);
  } catch (const Error& e) {
    throw Error(in + ": " + e.what());
  }
  r.seconds = seconds(t0);
  r.distance = surfaceDistance(r.result.mesh, mesh, distanceOptions(args));
  r.used = true;
  for (const std::string& w : remeshWarnings(r))
    std::fprintf(stderr, "osdmra: warning: %s: %s\n", in.c_str(), w.c_str());
  return r;
}

Json remeshJson(const Remeshed& r) {
  Json warnings = Json::array();
  for (const std::string& w : remeshWarnings(r)) warnings.push(w);
  return Json::object()
      .add("input_vertices", r.inputVertices)
      .add("input_faces", r.inputFaces)
      .add("unreferenced_vertices_dropped", r.droppedVertices)
      .add("feature_edges", r.result.featureEdges)
      .add("base_vertices", static_cast<int>(r.result.base.V.rows()))
      .add("base_faces", static_cast<int>(r.result.base.F.rows()))
      .add("faces", static_cast<int>(r.result.mesh.F.rows()))
      .add("snapped_samples", r.result.snappedSamples)
      .add("flipped_triangles", r.result.flippedTriangles)
      .add("degenerate_triangles", r.result.degenerateTriangles)
      .add("self_intersections", r.result.selfIntersections)
      .add("rms_relative", r.distance.rmsRelative)
      .add("hausdorff_relative", r.distance.hausdorffRelative)
      .add("seconds", r.seconds)
      .add("warnings", warnings);
}

void printRemesh(const std::string& in, const Remeshed& r) {
  std::printf(
      "%s: remeshed %d faces to %d over a base of %d faces (%d feature edges) in %.2f s; "
      "distance to the input: RMS %.3g, Hausdorff %.3g of the bounding-box diagonal; "
      "%d flipped, %d zero-area triangles, %lld crossing pairs\n",
      in.c_str(), r.inputFaces, static_cast<int>(r.result.mesh.F.rows()),
      static_cast<int>(r.result.base.F.rows()), r.result.featureEdges, r.seconds,
      r.distance.rmsRelative, r.distance.hausdorffRelative, r.result.flippedTriangles,
      r.result.degenerateTriangles, r.result.selfIntersections);
}

// The surface a command works on: the file itself, or its remeshing with --remesh.
TriMesh readSurface(const std::string& in, const Args& args, const Common& opt, Remeshed& r) {
  if (!args.has("remesh")) return readValidMesh(in);
  r = remeshFile(in, args, opt);
  return r.result.mesh;
}

CanonicalSurface surfaceOf(const TriMesh& mesh, const Args& args, const std::string& in) {
  const int J = static_cast<int>(args.integer("levels", -1, 1, 15));
  try {
    return canonicalSurface(mesh, J);
  } catch (const Error& e) {
    throw Error(in + ": " + e.what());
  }
}

// Largest |d^j_m| of a level (0 for a level without coefficients).
double maxDetail(const Points& d) {
  return d.rows() ? d.rowwise().norm().maxCoeff() : 0.0;
}

Json levelsJson(const Hierarchy& h, const Decomposition& d) {
  Json levels = Json::array();
  for (int j = 0; j < d.levels; ++j) {
    const double maxNorm = maxDetail(d.details[j]);
    levels.push(Json::object()
                    .add("level", j)
                    .add("vertices", h.numVertices(j + 1))
                    .add("coefficients", static_cast<int>(d.details[j].rows()))
                    .add("max_detail_norm", maxNorm));
  }
  return levels;
}

int cmdAnalyze(const std::vector<std::string>& argv) {
  Args args("analyze", argv,
            {"levels", "scheme", "wavelets", "rings", "output", "base-faces", "feature-angle",
             "samples", "seed"},
            flags({"remesh"}));
  args.expectPositional(1, "one input surface: osdmra analyze IN -o OUT.mra");
  const Common opt = common(args);
  const std::string in = args.positional()[0], out = args.require("output");
  const Scheme scheme = parseScheme(args.get("scheme", "loop"));
  const WaveletOptions w = waveletOptions(args);
  const auto t0 = Clock::now();
  Remeshed remeshed;
  const TriMesh mesh = readSurface(in, args, opt, remeshed);
  const double tRead = seconds(t0);
  const auto tr = Clock::now();
  const CanonicalSurface surface = surfaceOf(mesh, args, in);
  const Hierarchy& h = surface.hierarchy;
  const double tRecover = seconds(tr);
  const auto t1 = Clock::now();
  const FilterBank bank = makeFilterBank(h, scheme, w, opt.progress);
  const double tPre = seconds(t1);
  const auto t2 = Clock::now();
  Decomposition d = analyze(bank, surface.V, opt.progress);
  d.inputOrder = surface.inputOrder;
  d.inputFaces = surface.inputFaces;
  const double tAnalysis = seconds(t2);
  const auto t3 = Clock::now();
  const Points back = synthesize(bank, d, d.levels);
  const double tSynthesis = seconds(t3);
  const double diag = boundingBoxDiagonal(mesh.V);
  const double error = (back - surface.V).cwiseAbs().maxCoeff() / (diag > 0 ? diag : 1.0);
  writeMra(out, d);
  if (opt.json) {
    Json j = Json::object();
    if (remeshed.used) j.add("remesh", remeshJson(remeshed));
    std::cout << j.add("command", "analyze")
                     .add("input", in)
                     .add("output", out)
                     .add("scheme", schemeName(scheme))
                     .add("wavelets", waveletKindName(w.kind))
                     .add("rings", w.rings)
                     .add("levels", d.levels)
                     .add("base_vertices", static_cast<int>(d.base.rows()))
                     .add("base_faces", static_cast<int>(d.baseFaces.rows()))
                     .add("vertices", static_cast<int>(mesh.V.rows()))
                     .add("faces", static_cast<int>(mesh.F.rows()))
                     .add("per_level", levelsJson(h, d))
                     .add("local_solves", static_cast<long long>(bank.stats.localSolves))
                     .add("reconstruction_error", error)
                     .add("structure", describe(surface.recovery))
                     .add("reordered", !surface.inputOrder.empty())
                     .add("seconds", Json::object()
                                         .add("read", tRead)
                                         .add("recover", tRecover)
                                         .add("precompute", tPre)
                                         .add("analysis", tAnalysis)
                                         .add("synthesis", tSynthesis))
                     .str()
              << "\n";
    return 0;
  }
  if (remeshed.used) printRemesh(in, remeshed);
  std::printf("%s: %d vertices, %d faces = %d %s levels over a base of %d vertices, %d faces\n",
              in.c_str(), static_cast<int>(mesh.V.rows()), static_cast<int>(mesh.F.rows()),
              d.levels, schemeName(scheme), static_cast<int>(d.base.rows()),
              static_cast<int>(d.baseFaces.rows()));
  std::printf("wavelets: %s", waveletKindName(w.kind));
  if (w.kind == WaveletKind::Quasi) std::printf(" (r = %d rings)", w.rings);
  std::printf(", %lld distinct neighbourhoods solved\n", bank.stats.localSolves);
  std::printf("  level  coefficients  max |d|\n");
  for (int j = 0; j < d.levels; ++j)
    std::printf("  %5d  %12d  %.6g\n", j, static_cast<int>(d.details[j].rows()),
                maxDetail(d.details[j]));
  std::printf(
      "time: read %.3f s, recover structure %.3f s, precompute %.3f s, analysis %.3f s, "
      "synthesis %.3f s\n",
      tRead, tRecover, tPre, tAnalysis, tSynthesis);
  std::printf("reconstruction error (max abs / bbox diagonal): %.3g\n", error);
  std::printf("wrote %s\n", out.c_str());
  return 0;
}

int cmdSynthesize(const std::vector<std::string>& argv) {
  Args args("synthesize", argv, {"level", "output", "keep", "epsilon", "importance"}, flags());
  args.expectPositional(1, "one coefficient file: osdmra synthesize IN.mra -o OUT");
  const Common opt = common(args);
  const std::string in = args.positional()[0], out = args.require("output");
  if (args.has("keep") && args.has("epsilon"))
    throw Error("synthesize: give --keep or --epsilon, not both");
  const auto t0 = Clock::now();
  Decomposition d = readMra(in);
  const int level = static_cast<int>(args.integer("level", d.levels, 0, d.levels));
  const Hierarchy h(d.baseFaces, static_cast<int>(d.base.rows()), d.levels);
  const FilterBank bank = makeFilterBank(h, d.scheme, d.wavelets, opt.progress);
  // Truncation as lossy compression: keep the most important coefficients only.
  const bool truncated = args.has("keep") || args.has("epsilon");
  long long total = 0, kept = 0;
  double l2 = 0.0;
  if (truncated) {
    const std::string how = args.get("importance", "scaled");
    if (how != "scaled" && how != "plain")
      throw Error("synthesize: --importance must be scaled or plain, got '" + how + "'");
    const auto imp =
        importance(d, bank.norms, how == "plain" ? Importance::Plain : Importance::Scaled);
    for (const auto& l : imp) total += l.size();
    const KeepMask keep =
        args.has("keep")
            ? keepLargest(imp, static_cast<long long>(std::llround(
                                   args.real("keep", 1.0, 0.0, 1.0) * static_cast<double>(total))))
            : keepAbove(imp, args.real("epsilon", 0.0, 0.0, 1e300));
    kept = countKept(keep);
    const Decomposition t = truncate(d, keep);
    l2 = l2Distance(h, d.scheme, synthesize(bank, t, d.levels), synthesize(bank, d, d.levels));
    d = t;
  }
  TriMesh mesh;
  mesh.V = synthesize(bank, d, level, opt.progress);
  mesh.F = h.faces(level);
  if (level == d.levels && !d.inputOrder.empty()) {
    // Back to the input's own vertex numbering and faces.
    Points V(mesh.V.rows(), 3);
    for (Eigen::Index i = 0; i < mesh.V.rows(); ++i) V.row(d.inputOrder[i]) = mesh.V.row(i);
    mesh.V = std::move(V);
    if (d.inputFaces.rows()) mesh.F = d.inputFaces;
  }
  writeMesh(out, mesh);
  const double t = seconds(t0);
  const double diag = boundingBoxDiagonal(mesh.V);
  // RMS over the parameter domain: every base triangle has area 1.
  const double rms = l2 / std::sqrt(static_cast<double>(d.baseFaces.rows()));
  if (opt.json) {
    Json j = Json::object()
                 .add("command", "synthesize")
                 .add("input", in)
                 .add("output", out)
                 .add("level", level)
                 .add("levels", d.levels)
                 .add("scheme", schemeName(d.scheme))
                 .add("vertices", static_cast<int>(mesh.V.rows()))
                 .add("faces", static_cast<int>(mesh.F.rows()));
    if (truncated)
      j.add("coefficients", total)
          .add("kept", kept)
          .add("l2_error", l2)
          .add("rms_parametric_error_relative", diag > 0 ? rms / diag : 0.0);
    std::cout << j.add("seconds", t).str() << "\n";
  } else {
    std::cout << "wrote " << out << ": level " << level << " of " << d.levels << ", "
              << mesh.V.rows() << " vertices, " << mesh.F.rows() << " faces (" << t << " s)\n";
    if (truncated)
      std::printf(
          "kept %lld of %lld coefficients; L2 error %.6g (parametric RMS %.3g of the "
          "bounding-box diagonal)\n",
          kept, total, l2, diag > 0 ? rms / diag : 0.0);
  }
  return 0;
}

// Everything lod and sweep need: the canonical surface, its filter bank, its
// decomposition and the approximator, built once.
struct Analysed {
  CanonicalSurface surface;
  std::unique_ptr<FilterBank> bank;
  std::unique_ptr<Decomposition> d;
  std::unique_ptr<Approximator> approx;
  double seconds = 0;
  Remeshed remeshed;  ///< when the input went through --remesh
};

Analysed analysed(const TriMesh& mesh, const std::string& in, int levels, Scheme scheme,
                  const WaveletOptions& w, const ApproximationOptions& options,
                  const Progress& progress) {
  const auto t0 = Clock::now();
  Analysed a{[&] {
               try {
                 return canonicalSurface(mesh, levels);
               } catch (const Error& e) {
                 throw Error(in + ": " + e.what());
               }
             }(),
             nullptr,
             nullptr,
             nullptr,
             0,
             {}};
  a.bank = std::make_unique<FilterBank>(makeFilterBank(a.surface.hierarchy, scheme, w, progress));
  a.d = std::make_unique<Decomposition>(analyze(*a.bank, a.surface.V, progress));
  a.approx = std::make_unique<Approximator>(*a.bank, *a.d, options);
  a.seconds = seconds(t0);
  return a;
}

Analysed analysed(const std::string& in, const Args& args, const Common& opt) {
  const Scheme scheme = parseScheme(args.get("scheme", "loop"));
  const WaveletOptions w = waveletOptions(args);
  const std::string how = args.get("importance", "scaled");
  if (how != "scaled" && how != "plain")
    throw Error("--importance must be scaled or plain, got '" + how + "'");
  ApproximationOptions options;
  options.importance = how == "plain" ? Importance::Plain : Importance::Scaled;
  options.saturate = !args.has("exact");
  Remeshed remeshed;
  const TriMesh mesh = readSurface(in, args, opt, remeshed);
  Analysed a = analysed(mesh, in, static_cast<int>(args.integer("levels", -1, 1, 15)), scheme, w,
                        options, opt.progress);
  a.remeshed = std::move(remeshed);
  return a;
}

// The numbers reported with every level of detail.
struct LodReport {
  int triangles;
  long long selected, kept, total;
  double l2, l2Relative, rmsRelative, hausdorffRelative, extractSeconds;
};

LodReport report(const Analysed& a, const Approximation& x, double extractSeconds,
                 const DistanceOptions& dist) {
  const TriMesh& full = a.approx->fullResolution();
  const double diag = boundingBoxDiagonal(full.V);
  const double l2 = a.approx->l2Error(x);
  const SurfaceDistance sd = surfaceDistance(x.mesh, full, dist);
  // Parametric RMS: every base triangle has area 1.
  const double rmsParam = l2 / std::sqrt(static_cast<double>(a.d->baseFaces.rows()));
  return {x.triangles(),  x.selected,           x.kept,        x.total, l2, rmsParam / diag,
          sd.rmsRelative, sd.hausdorffRelative, extractSeconds};
}

Json reportJson(const LodReport& r) {
  return Json::object()
      .add("triangles", r.triangles)
      .add("coefficients_selected", r.selected)
      .add("coefficients_kept", r.kept)
      .add("coefficients", r.total)
      .add("l2_error", r.l2)
      .add("l2_rms_relative", r.l2Relative)
      .add("rms_relative", r.rmsRelative)
      .add("hausdorff_relative", r.hausdorffRelative)
      .add("extract_seconds", r.extractSeconds);
}

// Error against triangle count: kept counts spaced geometrically from none to all,
// so the whole range of triangle counts is covered, coarse end included.
struct SweepTable {
  std::string csv;
  Json rows = Json::array();
  int count = 0;
};

SweepTable sweepTable(const Analysed& a, int points, const DistanceOptions& dist,
                      const Progress& progress) {
  const long long total = a.approx->numCoefficients();
  std::vector<long long> counts{0};
  for (int i = 0; i < points - 1; ++i) {
    const double t = static_cast<double>(i) / (points - 2);
    counts.push_back(std::llround(std::pow(static_cast<double>(std::max<long long>(total, 1)), t)));
  }
  counts.back() = total;
  counts.erase(std::unique(counts.begin(), counts.end()), counts.end());
  SweepTable out;
  out.csv =
      "triangles,coefficients_kept,coefficients,l2_error,l2_rms_relative,rms_relative,"
      "hausdorff_relative,extract_seconds\n";
  for (std::size_t i = 0; i < counts.size(); ++i) {
    if (progress) progress("sweep", double(i) / counts.size());
    const auto t0 = Clock::now();
    const Approximation x = a.approx->keepCount(counts[i]);
    const LodReport r = report(a, x, seconds(t0), dist);
    char line[512];
    std::snprintf(line, sizeof line, "%d,%lld,%lld,%.9g,%.9g,%.9g,%.9g,%.6f\n", r.triangles, r.kept,
                  r.total, r.l2, r.l2Relative, r.rmsRelative, r.hausdorffRelative,
                  r.extractSeconds);
    out.csv += line;
    out.rows.push(reportJson(r));
  }
  if (progress) progress("sweep", 1.0);
  out.count = static_cast<int>(counts.size());
  return out;
}

// Writes `text` to `path` through a temporary file and a rename.
void writeTextFile(const std::string& path, const std::string& text) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream f(tmp, std::ios::binary);
    f << text;
    if (!f) {
      std::remove(tmp.c_str());
      throw Error(path + ": cannot write");
    }
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    std::remove(tmp.c_str());
    throw Error(path + ": cannot write");
  }
}

// Error against triangle count, log-log, drawn by gnuplot (Debian: gnuplot-nox).
void plotSweep(const std::string& csv, const std::string& png, const std::string& title,
               const std::string& scheme) {
  if (std::system("command -v gnuplot >/dev/null 2>&1") != 0)
    throw Error("--plot needs gnuplot (apt-get install gnuplot-nox); the CSV was written");
  const std::string tmp = png + ".tmp.png", script = png + ".gp";
  std::ostringstream gp;
  gp << "set terminal pngcairo size 900,600 noenhanced font 'sans,11'\n"
     << "set output '" << tmp << "'\n"
     << "set datafile separator ','\n"
     << "set key autotitle columnhead top right\n"
     << "set logscale xy\n"
     << "set grid\n"
     << "set xlabel 'triangles'\n"
     << "set ylabel 'error / bounding-box diagonal'\n"
     << "set title '" << title << " (" << scheme
     << "): error against triangle count; all coefficients kept is exact and off the scale'\n"
     << "plot '" << csv
     << "' using 1:($5>1e-12?$5:NaN) with linespoints title 'parametric L2 (RMS)', "
     << "'' using 1:($6>1e-12?$6:NaN) with linespoints title 'sampled RMS', "
     << "'' using 1:($7>1e-12?$7:NaN) with linespoints title 'Hausdorff'\n";
  writeTextFile(script, gp.str());
  const int rc = std::system(("gnuplot '" + script + "' 2>/dev/null").c_str());
  std::remove(script.c_str());
  if (rc != 0 || std::rename(tmp.c_str(), png.c_str()) != 0) {
    std::remove(tmp.c_str());
    throw Error(png + ": gnuplot could not draw the plot");
  }
}

int cmdLod(const std::vector<std::string>& argv) {
  Args args("lod", argv,
            {"levels", "scheme", "wavelets", "rings", "output", "epsilon", "budget", "keep",
             "importance", "samples", "seed", "base-faces", "feature-angle"},
            flags({"exact", "remesh"}));
  args.expectPositional(
      1, "one input surface: osdmra lod IN (--epsilon E | --budget N | --keep F) -o OUT");
  const Common opt = common(args);
  const std::string in = args.positional()[0], out = args.require("output");
  const int modes = args.has("epsilon") + args.has("budget") + args.has("keep");
  if (modes != 1) throw Error("lod: give exactly one of --epsilon, --budget and --keep");
  meshFormatFromPath(out);  // refuse a bad output name before the work
  const Analysed a = analysed(in, args, opt);
  const auto t0 = Clock::now();
  const Approximation x =
      args.has("budget") ? a.approx->budget(args.integer("budget", 0, 1, 1LL << 40))
      : args.has("keep") ? a.approx->keepFraction(args.real("keep", 0, 0, 1))
                         : a.approx->keepAbove(args.real("epsilon", 0, 0, 1e300));
  const double tExtract = seconds(t0);
  writeMesh(out, x.mesh);
  const LodReport r = report(a, x, tExtract, distanceOptions(args));
  if (opt.json) {
    Json j = Json::object();
    if (a.remeshed.used) j.add("remesh", remeshJson(a.remeshed));
    std::cout << j.add("command", "lod")
                     .add("input", in)
                     .add("output", out)
                     .add("scheme", schemeName(a.bank->scheme))
                     .add("rings", a.bank->wavelets.rings)
                     .add("structure", describe(a.surface.recovery))
                     .add("input_triangles",
                          static_cast<int>(a.surface.hierarchy.numFaces(a.d->levels)))
                     .add("analysis_seconds", a.seconds)
                     .add("lod", reportJson(r))
                     .str()
              << "\n";
    return 0;
  }
  if (a.remeshed.used) printRemesh(in, a.remeshed);
  std::printf("%s: %s\n", in.c_str(), describe(a.surface.recovery).c_str());
  std::printf("wrote %s: %d triangles (of %d), %lld of %lld coefficients kept\n", out.c_str(),
              r.triangles, a.surface.hierarchy.numFaces(a.d->levels), r.kept, r.total);
  std::printf(
      "errors relative to the bounding-box diagonal: parametric L2 (RMS) %.3g, sampled "
      "RMS %.3g, Hausdorff %.3g\n",
      r.l2Relative, r.rmsRelative, r.hausdorffRelative);
  std::printf("time: analysis %.3f s, extraction %.3f s\n", a.seconds, tExtract);
  return 0;
}

int cmdSweep(const std::vector<std::string>& argv) {
  Args args("sweep", argv,
            {"levels", "scheme", "wavelets", "rings", "csv", "plot", "points", "importance",
             "samples", "seed", "base-faces", "feature-angle"},
            flags({"exact", "remesh"}));
  args.expectPositional(1, "one input surface: osdmra sweep IN --csv OUT.csv [--plot OUT.png]");
  const Common opt = common(args);
  const std::string in = args.positional()[0], csv = args.require("csv");
  const std::string plot = args.get("plot");
  const int points = static_cast<int>(args.integer("points", 24, 2, 1000));
  const Analysed a = analysed(in, args, opt);
  const SweepTable t = sweepTable(a, points, distanceOptions(args), opt.progress);
  writeTextFile(csv, t.csv);
  if (!plot.empty())
    plotSweep(csv, plot, std::filesystem::path(in).filename().string(), schemeName(a.bank->scheme));
  if (opt.json) {
    Json j = Json::object();
    if (a.remeshed.used) j.add("remesh", remeshJson(a.remeshed));
    std::cout << j.add("command", "sweep")
                     .add("input", in)
                     .add("csv", csv)
                     .add("plot", plot)
                     .add("rows", t.rows)
                     .str()
              << "\n";
  } else {
    if (a.remeshed.used) printRemesh(in, a.remeshed);
    std::printf("wrote %s (%d levels of detail)%s%s\n", csv.c_str(), t.count,
                plot.empty() ? "" : " and ", plot.c_str());
  }
  return 0;
}

// Ring distance from `v` at one level, up to `radius`.
std::map<int, int> ringDistances(const Connectivity& c, int v, int radius) {
  std::map<int, int> dist{{v, 0}};
  std::queue<int> q;
  q.push(v);
  while (!q.empty()) {
    const int u = q.front();
    q.pop();
    if (dist[u] >= radius) continue;
    for (int w : c.ring(u))
      if (!dist.count(w)) {
        dist[w] = dist[u] + 1;
        q.push(w);
      }
  }
  return dist;
}

int cmdMask(const std::vector<std::string>& argv) {
  Args args("mask", argv, {"scheme", "level", "vertex"}, flags());
  args.expectPositional(1, "one base mesh: osdmra mask IN --level j --vertex i");
  const Common opt = common(args);
  const std::string in = args.positional()[0];
  const Scheme scheme = parseScheme(args.get("scheme", "loop"));
  const int j = static_cast<int>(args.integer("level", 0, 0, 8));
  const TriMesh base = readValidMesh(in);
  const Hierarchy h(base.F, static_cast<int>(base.V.rows()), j + 1);
  const int n = h.numVertices(j);
  const int v = static_cast<int>(args.integer("vertex", -1, 0, n - 1));
  if (v < 0) throw Error("mask: missing required option --vertex");
  const Connectivity& c = h.connectivity(j);
  // Subdivision mask (paper Fig. 4): the row of P^{j+1} for v's child, on level j.
  const SparseMatrix& P = h.refinement(scheme, j);
  // Inner-product mask (paper Fig. 5): row v of I^j, scaled so that the polyhedral
  // mask has the valence at the centre (times 6 * 4^j).
  ElementGram elements(scheme);
  LocalGram local(c, j, elements);
  const auto row = local.column(v);
  const double scale = 6.0 * std::ldexp(1.0, 2 * j);
  const auto dist = ringDistances(c, v, 8);
  Json sub = Json::array(), inner = Json::array();
  for (SparseMatrix::InnerIterator it(P, v); it; ++it)
    sub.push(Json::object()
                 .add("vertex", static_cast<int>(it.col()))
                 .add("ring", dist.count(static_cast<int>(it.col()))
                                  ? dist.at(static_cast<int>(it.col()))
                                  : -1)
                 .add("weight", it.value()));
  for (auto [k, value] : row)
    inner.push(Json::object()
                   .add("vertex", k)
                   .add("ring", dist.count(k) ? dist.at(k) : -1)
                   .add("value", value)
                   .add("scaled", value * scale));
  if (opt.json) {
    std::cout << Json::object()
                     .add("command", "mask")
                     .add("input", in)
                     .add("scheme", schemeName(scheme))
                     .add("level", j)
                     .add("vertex", v)
                     .add("valence", c.valence(v))
                     .add("boundary", c.isBoundaryVertex(v))
                     .add("subdivision_mask", sub)
                     .add("inner_product_mask", inner)
                     .add("inner_product_scale", scale)
                     .str()
              << "\n";
    return 0;
  }
  std::printf("%s, %s scheme, level %d, vertex %d (valence %d%s)\n", in.c_str(), schemeName(scheme),
              j, v, c.valence(v), c.isBoundaryVertex(v) ? ", boundary" : "");
  std::printf("subdivision mask (weights of level-%d vertices in the new position of %d):\n", j, v);
  for (SparseMatrix::InnerIterator it(P, v); it; ++it)
    std::printf("  ring %d  vertex %6d  %.17g\n",
                dist.count(static_cast<int>(it.col())) ? dist.at(static_cast<int>(it.col())) : -1,
                static_cast<int>(it.col()), it.value());
  std::printf("inner-product mask <phi_%d, phi_k> (value, and x 6*4^%d):\n", v, j);
  for (auto [k, value] : row)
    std::printf("  ring %d  vertex %6d  %.17g  %.12g\n", dist.count(k) ? dist.at(k) : -1, k, value,
                value * scale);
  return 0;
}

int cmdOrthogonality(const std::vector<std::string>& argv) {
  Args args("orthogonality", argv, {"scheme", "level", "max-rings"}, flags());
  args.expectPositional(1, "one base mesh: osdmra orthogonality BASE --level j");
  const Common opt = common(args);
  const std::string in = args.positional()[0];
  const Scheme scheme = parseScheme(args.get("scheme", "loop"));
  const int j = static_cast<int>(args.integer("level", 1, 0, 6));
  const int maxRings = static_cast<int>(args.integer("max-rings", 4, 0, 8));
  const TriMesh base = readValidMesh(in);
  const Hierarchy h(base.F, static_cast<int>(base.V.rows()), j + 1);
  std::vector<std::pair<std::string, WaveletOptions>> kinds = {{"lazy", {WaveletKind::Lazy, 0}}};
  for (int r = 0; r <= maxRings; ++r)
    kinds.push_back({"quasi r=" + std::to_string(r), {WaveletKind::Quasi, r}});
  if (h.numVertices(j + 1) <= kMaxPreWaveletVertices)
    kinds.push_back({"pre", {WaveletKind::Pre, 0}});
  Json rows = Json::array();
  if (!opt.json)
    std::printf(
        "%s, %s, level %d -> %d (%d wavelets)\n"
        "wavelets      worst |<psi,phi>|/(|psi||phi|)   mean of per-wavelet worst   worst inside "
        "S\n",
        in.c_str(), schemeName(scheme), j, j + 1, h.numVertices(j + 1) - h.numVertices(j));
  for (const auto& [name, w] : kinds) {
    Hierarchy fresh(base.F, static_cast<int>(base.V.rows()), j + 1);
    const auto alphas = waveletCorrections(fresh, scheme, w);
    const OrthogonalityStats o = orthogonality(fresh, scheme, j, alphas[j]);
    if (opt.json)
      rows.push(Json::object()
                    .add("wavelets", waveletKindName(w.kind))
                    .add("rings", w.kind == WaveletKind::Quasi ? w.rings : -1)
                    .add("worst", o.worst)
                    .add("mean", o.mean)
                    .add("worst_inside_support", o.worstInside));
    else
      std::printf("%-12s  %28.3e   %25.3e   %14.1e\n", name.c_str(), o.worst, o.mean,
                  o.worstInside);
  }
  if (opt.json)
    std::cout << Json::object()
                     .add("command", "orthogonality")
                     .add("input", in)
                     .add("scheme", schemeName(scheme))
                     .add("level", j)
                     .add("rows", rows)
                     .str()
              << "\n";
  return 0;
}

int cmdRemesh(const std::vector<std::string>& argv) {
  Args args("remesh", argv, {"base-faces", "levels", "feature-angle", "output", "samples", "seed"},
            flags());
  args.expectPositional(1, "one input mesh: osdmra remesh IN --base-faces N --levels J -o OUT");
  const Common opt = common(args);
  const std::string in = args.positional()[0], out = args.require("output");
  meshFormatFromPath(out);  // refuse a bad output name before the work
  const Remeshed r = remeshFile(in, args, opt);
  writeMesh(out, r.result.mesh);
  if (opt.json) {
    std::cout << remeshJson(r)
                     .add("command", "remesh")
                     .add("input", in)
                     .add("output", out)
                     .add("levels", static_cast<int>(args.integer("levels", 5, 0, 8)))
                     .str()
              << "\n";
    return 0;
  }
  if (r.droppedVertices > 0)
    std::printf("%s: dropped %d unreferenced vertices\n", in.c_str(), r.droppedVertices);
  printRemesh(in, r);
  std::printf("wrote %s\n", out.c_str());
  return 0;
}

int cmdShape(const std::vector<std::string>& argv) {
  Args args("shape", argv, {"output"}, flags());
  args.expectPositional(1, "a shape name: osdmra shape NAME -o OUT");
  const std::string out = args.require("output");
  const TriMesh mesh = shapes::byName(args.positional()[0]);
  writeMesh(out, mesh);
  if (args.has("json"))
    std::cout << Json::object()
                     .add("command", "shape")
                     .add("shape", args.positional()[0])
                     .add("output", out)
                     .add("vertices", static_cast<int>(mesh.V.rows()))
                     .add("faces", static_cast<int>(mesh.F.rows()))
                     .str()
              << "\n";
  else
    std::cout << "wrote " << out << ": " << mesh.V.rows() << " vertices, " << mesh.F.rows()
              << " faces\n";
  return 0;
}

// The paper's section 4 on the bundled head: analyse and rebuild it with both
// schemes, extract the levels of detail of the paper's Figure 8 (4,054, 12,310 and
// 16,098 triangles), measure their errors, sweep the whole range, and write it all
// to --out (default out/).
int cmdDemo(const std::vector<std::string>& argv) {
  Args args("demo", argv,
            {"rings", "out", "samples", "seed", "points", "base-faces", "levels", "feature-angle"},
            flags({"remesh"}));
  if (args.positional().size() > 1)
    throw Error("demo: at most one input mesh (default: the bundled head)");
  if (args.has("levels") && !args.has("remesh"))
    throw Error("demo: --levels sets the remeshing's levels; it needs --remesh");
  const Common opt = common(args);
  const bool bundled = args.positional().empty();
  const std::string in = bundled ? bundledDataPath() : args.positional()[0];
  const std::string stem = bundled ? "igea" : std::filesystem::path(in).stem().string();
  const std::filesystem::path outDir = args.get("out", "out");
  Remeshed remeshed;
  const TriMesh mesh = readSurface(in, args, opt, remeshed);
  std::filesystem::create_directories(outDir);
  const double diag = boundingBoxDiagonal(mesh.V);
  const DistanceOptions dist = distanceOptions(args);
  const int points = static_cast<int>(args.integer("points", 16, 2, 1000));
  const long long budgets[] = {4054, 12310, 16098};
  const bool gnuplot = std::system("command -v gnuplot >/dev/null 2>&1") == 0;
  WaveletOptions w;
  w.rings = static_cast<int>(args.integer("rings", kDefaultRings, 0, 8));

  Json runs = Json::array();
  std::ostringstream md;
  // Recovery alone (no hierarchy): the analyses below build their own.
  const std::string structure =
      describe(recoverSubdivision(mesh.F, static_cast<int>(mesh.V.rows())));
  md << "# Levels of detail of " << (bundled ? "the bundled head" : "`" + in + "`") << "\n\n"
     << "`osdmra demo`: `" << std::filesystem::path(in).filename().string() << "`, "
     << mesh.F.rows() << " triangles" << (remeshed.used ? " after remeshing" : "") << ", "
     << structure << "; quasi-wavelets with r = " << w.rings
     << "; coefficients kept by importance |d| ||psi||. Errors are relative to the "
     << "bounding-box diagonal of the full-resolution surface: the exact parametric L2 error as "
     << "an RMS over the domain, and the sampled symmetric RMS and Hausdorff distances ("
     << dist.samples << " samples per surface plus all vertices, seed " << dist.seed << ").\n\n";
  if (remeshed.used) {
    char line[400];
    std::snprintf(line, sizeof line,
                  "Remeshing (reported apart from the truncation, which is measured against the "
                  "remeshed surface): %d input faces to %d over a base of %d, distance to the "
                  "input RMS %.3e and Hausdorff %.3e of its diagonal, %.2f s.\n\n",
                  remeshed.inputFaces, static_cast<int>(remeshed.result.mesh.F.rows()),
                  static_cast<int>(remeshed.result.base.F.rows()), remeshed.distance.rmsRelative,
                  remeshed.distance.hausdorffRelative, remeshed.seconds);
    md << line;
  }
  md << "| scheme | budget | triangles | coefficients kept | parametric L2 (RMS) | sampled RMS "
        "| Hausdorff | extraction (s) |\n|---|---|---|---|---|---|---|---|\n";
  if (!opt.json) {
    if (remeshed.used) printRemesh(in, remeshed);
    std::printf("%s: %d vertices, %d faces\n", in.c_str(), static_cast<int>(mesh.V.rows()),
                static_cast<int>(mesh.F.rows()));
  }
  for (Scheme scheme : {Scheme::Loop, Scheme::Linear}) {
    const Analysed a = analysed(mesh, in, -1, scheme, w, ApproximationOptions{}, opt.progress);
    const auto t0 = Clock::now();
    const Points back = synthesize(*a.bank, *a.d, a.d->levels);
    const double tS = seconds(t0);
    const double err = (back - a.surface.V).cwiseAbs().maxCoeff() / diag;
    if (!opt.json)
      std::printf(
          "\n%s: analysis %.3f s, synthesis %.3f s, reconstruction error %.2g of the "
          "diagonal\n",
          schemeName(scheme), a.seconds, tS, err);
    Json lods = Json::array();
    for (long long budget : budgets) {
      const auto t1 = Clock::now();
      const Approximation x = a.approx->budget(budget);
      const LodReport r = report(a, x, seconds(t1), dist);
      const std::filesystem::path file = outDir / (stem + "-" + std::string(schemeName(scheme)) +
                                                   "-" + std::to_string(budget) + ".obj");
      writeMesh(file.string(), x.mesh);
      char row[512];
      std::snprintf(row, sizeof row,
                    "| %s | %lld | %d | %lld of %lld | %.3e | %.3e | %.3e | %.3f |\n",
                    schemeName(scheme), budget, r.triangles, r.kept, r.total, r.l2Relative,
                    r.rmsRelative, r.hausdorffRelative, r.extractSeconds);
      md << row;
      lods.push(reportJson(r).add("budget", budget).add("file", file.string()));
      if (!opt.json)
        std::printf("  budget %5lld: %5d triangles, RMS %.2e, Hausdorff %.2e -> %s\n", budget,
                    r.triangles, r.rmsRelative, r.hausdorffRelative, file.string().c_str());
    }
    const SweepTable t = sweepTable(a, points, dist, opt.progress);
    const std::string base = (outDir / ("sweep-" + std::string(schemeName(scheme)))).string();
    writeTextFile(base + ".csv", t.csv);
    if (gnuplot)
      plotSweep(base + ".csv", base + ".png", std::filesystem::path(in).filename().string(),
                schemeName(scheme));
    if (!opt.json)
      std::printf("  error against triangles: %s.csv%s\n", base.c_str(),
                  gnuplot ? (" and " + base + ".png").c_str() : " (no gnuplot: no plot)");
    runs.push(Json::object()
                  .add("scheme", schemeName(scheme))
                  .add("rings", w.rings)
                  .add("analysis_seconds", a.seconds)
                  .add("synthesis_seconds", tS)
                  .add("reconstruction_error", err)
                  .add("per_level", levelsJson(a.surface.hierarchy, *a.d))
                  .add("lods", lods)
                  .add("sweep_csv", base + ".csv"));
  }
  const std::string table = (outDir / "errors.md").string();
  writeTextFile(table, md.str());
  if (opt.json) {
    Json j = Json::object();
    if (remeshed.used) j.add("remesh", remeshJson(remeshed));
    std::cout << j.add("command", "demo")
                     .add("input", in)
                     .add("out", outDir.string())
                     .add("table", table)
                     .add("runs", runs)
                     .str()
              << "\n";
  } else {
    std::printf("\nerror table: %s\nall outputs in %s/\n", table.c_str(), outDir.string().c_str());
  }
  return 0;
}

int dispatch(int argc, char** argv) {
  if (argc < 2) {
    std::cerr << kUsage;
    return 2;
  }
  const std::string command = argv[1];
  std::vector<std::string> rest(argv + 2, argv + argc);
  for (const std::string& a : rest)
    if (a == "--help" || a == "-h") {
      std::cout << kUsage;
      return 0;
    }
  if (command == "--help" || command == "-h" || command == "help") {
    std::cout << kUsage;
    return 0;
  }
  if (command == "--version") {
    std::cout << "osdmra 0.1.0\n";
    return 0;
  }
  if (command == "info") return cmdInfo(rest);
  if (command == "subdivide") return cmdSubdivide(rest);
  if (command == "analyze") return cmdAnalyze(rest);
  if (command == "synthesize") return cmdSynthesize(rest);
  if (command == "mask") return cmdMask(rest);
  if (command == "lod") return cmdLod(rest);
  if (command == "sweep") return cmdSweep(rest);
  if (command == "orthogonality") return cmdOrthogonality(rest);
  if (command == "shape") return cmdShape(rest);
  if (command == "remesh") return cmdRemesh(rest);
  if (command == "demo") return cmdDemo(rest);
  std::cerr << "osdmra: unknown command '" << command << "'\n\n" << kUsage;
  return 2;
}

}  // namespace
}  // namespace osdmra::cli

int main(int argc, char** argv) {
  try {
    return osdmra::cli::dispatch(argc, argv);
  } catch (const osdmra::Error& e) {
    std::cerr << "osdmra: " << e.what() << "\n";
  } catch (const std::bad_alloc&) {
    std::cerr << "osdmra: out of memory\n";
  } catch (const std::exception& e) {
    std::cerr << "osdmra: internal error: " << e.what() << "\n";
  }
  return 1;
}
