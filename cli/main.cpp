// osdmra: the command-line front end. Thin: every computation is a library call;
// this file parses arguments, reads and writes files, times the work, and prints
// a human summary (or, with --json, one JSON object on stdout). Errors are
// osdmra::Error from anywhere below, printed as "osdmra: <message>" with exit 1.
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <queue>
#include <sstream>

#include "args.h"
#include "json.h"
#include "osdmra/error.h"
#include "osdmra/filter_bank.h"
#include "osdmra/gram.h"
#include "osdmra/io.h"
#include "osdmra/mra_file.h"
#include "osdmra/recovery.h"
#include "osdmra/shapes.h"
#include "osdmra/truncation.h"

#ifndef OSDMRA_DATA_DIR
#define OSDMRA_DATA_DIR ""
#endif
#ifndef OSDMRA_INSTALL_DATA_DIR
#define OSDMRA_INSTALL_DATA_DIR ""
#endif

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
                 [--wavelets lazy|quasi|pre] [--rings R]
                               decompose a surface with subdivision connectivity (any
                               vertex and face order) into base mesh + wavelet details
  synthesize IN.mra -o OUT [--level j] [--keep F | --epsilon E] [--importance scaled|plain]
                               rebuild the surface (or its level-j approximation),
                               optionally from the most important coefficients only
  mask IN --level j --vertex i [--scheme loop|linear]
                               subdivision and inner-product masks around a vertex
                               of level j over the base mesh IN (paper, Fig. 4, 5)
  orthogonality BASE --level j [--scheme S] [--max-rings R]
                               how close lazy, quasi (r = 0..R) and pre-wavelets of
                               level j over BASE are to orthogonal
  shape NAME -o OUT            write a built-in base mesh (tetrahedron, octahedron,
                               icosahedron, torus, genus2, genus3, disc, cylinder,
                               valences)
  demo                         analyse and rebuild the bundled scanned head

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
  const Recovery r = recoverSubdivision(c);
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
  Args args("analyze", argv, {"levels", "scheme", "wavelets", "rings", "output"}, flags());
  args.expectPositional(1, "one input surface: osdmra analyze IN -o OUT.mra");
  const Common opt = common(args);
  const std::string in = args.positional()[0], out = args.require("output");
  const Scheme scheme = parseScheme(args.get("scheme", "loop"));
  const WaveletOptions w = waveletOptions(args);
  const auto t0 = Clock::now();
  const TriMesh mesh = readValidMesh(in);
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
    std::cout << Json::object()
                     .add("command", "analyze")
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

std::string defaultMesh() {
  std::vector<std::string> dirs;
  if (const char* env = std::getenv("OSDMRA_DATA")) dirs.push_back(env);
  dirs.push_back(OSDMRA_DATA_DIR);
  dirs.push_back(OSDMRA_INSTALL_DATA_DIR);
  for (const std::string& d : dirs) {
    if (d.empty()) continue;
    const std::filesystem::path p = std::filesystem::path(d) / "igea-oct6.obj";
    if (std::filesystem::exists(p)) return p.string();
  }
  throw Error(
      "demo: cannot find the bundled mesh igea-oct6.obj (set OSDMRA_DATA to the data/ "
      "directory of the osdmra sources)");
}

int cmdDemo(const std::vector<std::string>& argv) {
  Args args("demo", argv, {"rings"}, flags());
  args.expectPositional(0, "no positional arguments");
  const Common opt = common(args);
  const std::string in = defaultMesh();
  const TriMesh mesh = readValidMesh(in);
  const Hierarchy h = Hierarchy::fromCanonical(mesh.F, static_cast<int>(mesh.V.rows()), 6);
  const double diag = boundingBoxDiagonal(mesh.V);
  Json runs = Json::array();
  if (!opt.json)
    std::printf(
        "%s: %d vertices, %d faces, 6 levels over an octahedron\n\n"
        "scheme  wavelets  precompute   analysis  synthesis  reconstruction error\n",
        in.c_str(), static_cast<int>(mesh.V.rows()), static_cast<int>(mesh.F.rows()));
  for (Scheme scheme : {Scheme::Loop, Scheme::Linear}) {
    WaveletOptions w;
    w.rings = static_cast<int>(args.integer("rings", kDefaultRings, 0, 8));
    const auto t0 = Clock::now();
    const FilterBank bank = makeFilterBank(h, scheme, w, opt.progress);
    const double tPre = seconds(t0);
    const auto t1 = Clock::now();
    const Decomposition d = analyze(bank, mesh.V, opt.progress);
    const double tA = seconds(t1);
    const auto t2 = Clock::now();
    const Points back = synthesize(bank, d, d.levels, opt.progress);
    const double tS = seconds(t2);
    const double err = (back - mesh.V).cwiseAbs().maxCoeff() / diag;
    if (opt.json)
      runs.push(Json::object()
                    .add("scheme", schemeName(scheme))
                    .add("rings", w.rings)
                    .add("precompute_seconds", tPre)
                    .add("analysis_seconds", tA)
                    .add("synthesis_seconds", tS)
                    .add("reconstruction_error", err)
                    .add("per_level", levelsJson(h, d)));
    else
      std::printf("%-7s quasi r=%d  %8.3f s  %7.3f s  %7.3f s  %.3g\n", schemeName(scheme), w.rings,
                  tPre, tA, tS, err);
  }
  if (opt.json)
    std::cout << Json::object().add("command", "demo").add("input", in).add("runs", runs).str()
              << "\n";
  else
    std::printf("\nreconstruction error: max |c - synthesize(analyze(c))| / bbox diagonal\n");
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
  if (command == "orthogonality") return cmdOrthogonality(rest);
  if (command == "shape") return cmdShape(rest);
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
