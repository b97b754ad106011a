#include <cmath>
#include <cstdio>
#include <iostream>
#include <map>
#include <queue>

#include "commands.h"
#include "common.h"
#include "osdmra/mesh/io.h"
#include "osdmra/mra/element_gram.h"
#include "osdmra/mra/gram.h"
#include "osdmra/mra/mra_file.h"
#include "osdmra/mra/truncation.h"
#include "osdmra/mra/wavelets.h"
#include "report.h"

namespace osdmra::cli {
namespace {

void printAnalysis(const std::string& in, const std::string& out, const LoadedSurface& s,
                   const AnalysedSurface& a, double tRead, double tSynthesis, double error) {
  const Decomposition& d = a.decomposition();
  const WaveletOptions& w = a.bank().wavelets;
  if (s.remeshing) printRemesh(in, *s.remeshing);
  std::printf("%s: %d vertices, %d faces = %d %s levels over a base of %d vertices, %d faces\n",
              in.c_str(), static_cast<int>(s.mesh.V.rows()), static_cast<int>(s.mesh.F.rows()),
              d.levels, schemeName(d.scheme), static_cast<int>(d.base.rows()),
              static_cast<int>(d.baseFaces.rows()));
  std::printf("wavelets: %s", waveletKindName(w.kind));
  if (w.kind == WaveletKind::Quasi) std::printf(" (r = %d rings)", w.rings);
  std::printf(", %lld distinct neighbourhoods solved\n", a.bank().stats.localSolves);
  std::printf("  level  coefficients  max |d|\n");
  for (int j = 0; j < d.levels; ++j)
    std::printf("  %5d  %12d  %.6g\n", j, static_cast<int>(d.details[j].rows()),
                maxDetail(d.details[j]));
  const AnalysisTimes& t = a.times();
  std::printf(
      "time: read %.3f s, recover structure %.3f s, precompute %.3f s, analysis %.3f s, "
      "synthesis %.3f s\n",
      tRead, t.recover, t.precompute, t.analysis, tSynthesis);
  std::printf("reconstruction error (max abs / bbox diagonal): %.3g\n", error);
  std::printf("wrote %s\n", out.c_str());
}

}  // namespace

int cmdAnalyze(const Argv& argv) {
  Args args(
      "analyze", argv,
      withRemeshOptions({"levels", "scheme", "wavelets", "rings", "output", "samples", "seed"}),
      flags({"remesh"}));
  args.expectPositional(1, "one input surface: osdmra analyze IN -o OUT.mra");
  const Common opt = common(args);
  const std::string in = args.positional()[0], out = args.require("output");
  AnalysisOptions options = analysisOptions(args);
  options.approximator = false;
  const auto t0 = Clock::now();
  const LoadedSurface s = loadInput(in, args, opt);
  const double tRead = seconds(t0);
  const AnalysedSurface a(s.mesh, options, in, opt.progress);
  const Decomposition& d = a.decomposition();
  const auto t3 = Clock::now();
  const Points back = synthesize(a.bank(), d, d.levels);
  const double tSynthesis = seconds(t3);
  const double diag = boundingBoxDiagonal(s.mesh.V);
  const double error =
      (back - a.canonicalPositions()).cwiseAbs().maxCoeff() / (diag > 0 ? diag : 1.0);
  writeMra(out, d);
  if (!opt.json) {
    printAnalysis(in, out, s, a, tRead, tSynthesis, error);
    return 0;
  }
  const AnalysisTimes& t = a.times();
  Json j = startJson(s);
  std::cout << j.add("command", "analyze")
                   .add("input", in)
                   .add("output", out)
                   .add("scheme", schemeName(d.scheme))
                   .add("wavelets", waveletKindName(d.wavelets.kind))
                   .add("rings", d.wavelets.rings)
                   .add("levels", d.levels)
                   .add("base_vertices", static_cast<int>(d.base.rows()))
                   .add("base_faces", static_cast<int>(d.baseFaces.rows()))
                   .add("vertices", static_cast<int>(s.mesh.V.rows()))
                   .add("faces", static_cast<int>(s.mesh.F.rows()))
                   .add("per_level", levelsJson(a.hierarchy(), d))
                   .add("local_solves", static_cast<long long>(a.bank().stats.localSolves))
                   .add("reconstruction_error", error)
                   .add("structure", describe(*a.recovery()))
                   .add("reordered", !d.inputOrder.empty())
                   .add("seconds", Json::object()
                                       .add("read", tRead)
                                       .add("recover", t.recover)
                                       .add("precompute", t.precompute)
                                       .add("analysis", t.analysis)
                                       .add("synthesis", tSynthesis))
                   .str()
            << "\n";
  return 0;
}

int cmdSynthesize(const Argv& argv) {
  Args args("synthesize", argv, {"level", "output", "keep", "epsilon", "importance"}, flags());
  args.expectPositional(1, "one coefficient file: osdmra synthesize IN.mra -o OUT");
  const Common opt = common(args);
  const std::string in = args.positional()[0], out = args.require("output");
  if (args.has("keep") && args.has("epsilon"))
    throw Error("synthesize: give --keep or --epsilon, not both");
  const auto t0 = Clock::now();
  const AnalysedSurface a(readMra(in), false, opt.progress);
  Decomposition d = a.decomposition();
  const int level = static_cast<int>(args.integer("level", d.levels, 0, d.levels));
  // Truncation as lossy compression: keep the most important coefficients only.
  const bool truncated = args.has("keep") || args.has("epsilon");
  long long total = 0, kept = 0;
  double l2 = 0.0;
  if (truncated) {
    const std::string how = args.get("importance", "scaled");
    if (how != "scaled" && how != "plain")
      throw Error("synthesize: --importance must be scaled or plain, got '" + how + "'");
    const auto imp =
        importance(d, a.bank().norms, how == "plain" ? Importance::Plain : Importance::Scaled);
    for (const auto& l : imp) total += l.size();
    const KeepMask keep =
        args.has("keep")
            ? keepLargest(imp, static_cast<long long>(std::llround(
                                   args.real("keep", 1.0, 0.0, 1.0) * static_cast<double>(total))))
            : keepAbove(imp, args.real("epsilon", 0.0, 0.0, 1e300));
    kept = countKept(keep);
    const Decomposition t = truncate(d, keep);
    l2 = l2Distance(a.hierarchy(), d.scheme, synthesize(a.bank(), t, d.levels),
                    synthesize(a.bank(), d, d.levels));
    d = t;
  }
  const TriMesh mesh = a.reconstruct(d, level, opt.progress);
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

namespace {

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

}  // namespace

int cmdMask(const Argv& argv) {
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

int cmdOrthogonality(const Argv& argv) {
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
  kinds.push_back({"fixed", {WaveletKind::Fixed, 0}});
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

}  // namespace osdmra::cli
