#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <sstream>

#include "commands.h"
#include "common.h"
#include "osdmra/base/bundled_data.h"
#include "osdmra/base/file.h"
#include "osdmra/mesh/io.h"
#include "report.h"

namespace osdmra::cli {
namespace {

// Error against triangle count: kept counts spaced geometrically from none to all,
// so the whole range of triangle counts is covered, coarse end included.
struct SweepTable {
  std::string csv;
  Json rows = Json::array();
  int count = 0;
};

SweepTable sweepTable(const AnalysedSurface& a, int points, const DistanceOptions& dist,
                      const Progress& progress) {
  const long long total = a.approximator().numCoefficients();
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
    const Approximation x = a.approximator().keepCount(counts[i]);
    const LodReport r = lodReport(a, x, seconds(t0), dist);
    char line[512];
    std::snprintf(line, sizeof line, "%d,%lld,%lld,%.9g,%.9g,%.9g,%.9g,%.6f\n", r.triangles, r.kept,
                  r.total, r.errors.l2, r.errors.l2RmsRelative, r.errors.rmsRelative,
                  r.errors.hausdorffRelative, r.extractSeconds);
    out.csv += line;
    out.rows.push(lodJson(r));
  }
  if (progress) progress("sweep", 1.0);
  out.count = static_cast<int>(counts.size());
  return out;
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

}  // namespace

int cmdLod(const Argv& argv) {
  Args args("lod", argv,
            withRemeshOptions({"levels", "scheme", "wavelets", "rings", "output", "epsilon",
                               "budget", "keep", "importance", "selection", "placement", "metric",
                               "samples", "seed"}),
            flags({"exact", "remesh"}));
  args.expectPositional(
      1, "one input surface: osdmra lod IN (--epsilon E | --budget N | --keep F) -o OUT");
  const Common opt = common(args);
  const std::string in = args.positional()[0], out = args.require("output");
  const int modes = args.has("epsilon") + args.has("budget") + args.has("keep");
  if (modes != 1) throw Error("lod: give exactly one of --epsilon, --budget and --keep");
  meshFormatForWriting(out);  // refuse a bad output name before the work
  const AnalysisOptions options = analysisOptions(args, kLodDefaults);
  const long long budget = args.has("budget") ? args.integer("budget", 0, 1, 1LL << 40) : -1;
  const InputOptions input = inputOptions(args, true);
  // With --remesh and a budget, the base is measured rather than guessed: lodForBudget
  // remeshes over the budget (five times: as asked; with skinny faces where flat; with
  // those and flips towards the input; and the first two again with the input's vertices
  // removed in order of the error each removal makes), over a half, a quarter and a
  // sixteenth of it (and cuts the input's own hierarchy, where it has one) and keeps the
  // closest level of detail, unless --base-faces fixes the base (and --levels the levels).
  std::optional<BudgetLod> searched;
  std::optional<LoadedSurface> loaded;
  std::optional<AnalysedSurface> analysed;
  Approximation x;
  double tExtract = 0;
  if (input.remesh && budget > 0 && !args.has("base-faces")) {
    BudgetSearchOptions search;
    search.levelsForEachBase = !args.has("levels");
    search.stagesPerVertex = input.remeshing.stages == StageRelaxation::perVertex;
    search.retriangulateByError = input.remeshing.retriangulateByError;
    if (args.has("skinny-where-flat")) search.skinnyWhereFlat = input.remeshing.skinnyWhereFlat;
    searched = lodForBudget(in, budget, input, options, search, opt.progress);
    if (searched->surface.remeshing) printRemeshWarnings(in, *searched->surface.remeshing);
    x = std::move(searched->lod);
    tExtract = searched->extractSeconds;
  } else {
    loaded = loadInput(in, input, opt);
    analysed.emplace(loaded->mesh, analysisOptionsFor(*loaded, options), in, opt.progress);
    const Approximator& approx = analysed->approximator();
    const auto t0 = Clock::now();
    x = budget > 0         ? approx.budget(budget)
        : args.has("keep") ? approx.keepFraction(args.real("keep", 0, 0, 1))
                           : approx.keepAbove(args.real("epsilon", 0, 0, 1e300));
    tExtract = seconds(t0);
  }
  const LoadedSurface& s = searched ? searched->surface : *loaded;
  const AnalysedSurface& a = searched ? *searched->analysed : *analysed;
  writeMesh(out, x.mesh);
  const LodReport r = lodReport(a, x, tExtract, distanceOptions(args), &s, budget);
  for (const std::string& w : r.warnings)
    std::fprintf(stderr, "osdmra: warning: %s: %s\n", in.c_str(), w.c_str());
  if (opt.json) {
    Json j = startJson(s);
    std::cout << j.add("command", "lod")
                     .add("input", in)
                     .add("output", out)
                     .add("scheme", schemeName(a.bank().scheme))
                     .add("rings", a.bank().wavelets.rings)
                     .add("structure", describe(*a.recovery()))
                     .add("input_triangles", a.hierarchy().numFaces(a.levels()))
                     .add("analysis_seconds", a.times().total())
                     .add("lod", lodJson(r))
                     .add("base_trials", searched ? baseTrialsJson(*searched) : Json::array())
                     .str()
              << "\n";
    return 0;
  }
  if (s.remeshing) printRemesh(in, *s.remeshing);
  if (searched) printBaseTrials(*searched);
  std::printf("%s: %s\n", in.c_str(), describe(*a.recovery()).c_str());
  std::printf("wrote %s: %d triangles (of %d), %lld of %lld coefficients kept\n", out.c_str(),
              r.triangles, a.hierarchy().numFaces(a.levels()), r.kept, r.total);
  std::printf(
      "errors relative to the bounding-box diagonal: parametric L2 (RMS) %.3g, sampled "
      "RMS %.3g, Hausdorff %.3g\n",
      r.errors.l2RmsRelative, r.errors.rmsRelative, r.errors.hausdorffRelative);
  if (r.toInput)
    std::printf("to the input before remeshing: sampled RMS %.3g, Hausdorff %.3g\n",
                r.toInput->rmsRelative, r.toInput->hausdorffRelative);
  std::printf("time: analysis %.3f s, extraction %.3f s\n", a.times().total(), tExtract);
  return 0;
}

int cmdSweep(const Argv& argv) {
  Args args(
      "sweep", argv,
      withRemeshOptions({"levels", "scheme", "wavelets", "rings", "csv", "plot", "points",
                         "importance", "selection", "placement", "metric", "samples", "seed"}),
      flags({"exact", "remesh"}));
  args.expectPositional(1, "one input surface: osdmra sweep IN --csv OUT.csv [--plot OUT.png]");
  const Common opt = common(args);
  const std::string in = args.positional()[0], csv = args.require("csv");
  const std::string plot = args.get("plot");
  const int points = static_cast<int>(args.integer("points", 24, 2, 1000));
  const AnalysisOptions options = analysisOptions(args, kSweepDefaults);
  const LoadedSurface s = loadInput(in, inputOptions(args, true), opt);
  const AnalysedSurface a(s.mesh, analysisOptionsFor(s, options), in, opt.progress);
  const SweepTable t = sweepTable(a, points, distanceOptions(args), opt.progress);
  writeTextFile(csv, t.csv);
  if (!plot.empty())
    plotSweep(csv, plot, std::filesystem::path(in).filename().string(),
              schemeName(a.bank().scheme));
  if (opt.json) {
    Json j = startJson(s);
    std::cout << j.add("command", "sweep")
                     .add("input", in)
                     .add("csv", csv)
                     .add("plot", plot)
                     .add("rows", t.rows)
                     .str()
              << "\n";
  } else {
    if (s.remeshing) printRemesh(in, *s.remeshing);
    std::printf("wrote %s (%d levels of detail)%s%s\n", csv.c_str(), t.count,
                plot.empty() ? "" : " and ", plot.c_str());
  }
  return 0;
}

namespace {

// What every scheme's run of the demo shares.
struct DemoSetup {
  std::string in, stem;
  std::filesystem::path outDir;
  DistanceOptions distance;
  int points = 16;
  bool gnuplot = false;
  WaveletOptions wavelets;
  bool json = false;
  Progress progress;
};

// The introduction of errors.md: what was analysed, how errors are measured, and the
// remeshing when there was one; then the table's header.
std::string demoIntroduction(const DemoSetup& setup, bool bundled, const LoadedSurface& s) {
  std::ostringstream md;
  // Recovery alone (no hierarchy): the analyses build their own.
  const std::string structure =
      describe(recoverSubdivision(s.mesh.F, static_cast<int>(s.mesh.V.rows())));
  md << "# Levels of detail of " << (bundled ? "the bundled head" : "`" + setup.in + "`") << "\n\n"
     << "`osdmra demo`: `" << std::filesystem::path(setup.in).filename().string() << "`, "
     << s.mesh.F.rows() << " triangles" << (s.remeshing ? " after remeshing" : "") << ", "
     << structure << "; quasi-wavelets with r = " << setup.wavelets.rings
     << "; importance |d| ||psi||, coefficients chosen by error removed per triangle added "
     << "(rate-distortion order). Errors are relative to the "
     << "bounding-box diagonal of the full-resolution surface: the exact parametric L2 error as "
     << "an RMS over the domain, and the sampled symmetric RMS and Hausdorff distances ("
     << setup.distance.samples << " samples per surface plus all vertices, seed "
     << setup.distance.seed << ").\n\n";
  if (s.remeshing) {
    const RemeshReport& r = *s.remeshing;
    char line[400];
    std::snprintf(line, sizeof line,
                  "Remeshing (reported apart from the truncation, which is measured against the "
                  "remeshed surface): %d input faces to %d over a base of %d, distance to the "
                  "input RMS %.3e and Hausdorff %.3e of its diagonal, %.2f s.\n\n",
                  r.inputFaces, static_cast<int>(r.result.mesh.F.rows()),
                  static_cast<int>(r.result.base.F.rows()), r.distance.rmsRelative,
                  r.distance.hausdorffRelative, r.seconds);
    md << line;
  }
  md << "| scheme | budget | triangles | coefficients kept | parametric L2 (RMS) | sampled RMS "
        "| Hausdorff | extraction (s) |\n|---|---|---|---|---|---|---|---|\n";
  return md.str();
}

// The paper's three levels of detail of one analysis: written, measured, tabulated.
Json demoBudgets(const DemoSetup& setup, const AnalysedSurface& a, std::ostringstream& md) {
  const long long budgets[] = {4054, 12310, 16098};
  const char* scheme = schemeName(a.bank().scheme);
  Json lods = Json::array();
  for (long long budget : budgets) {
    const auto t1 = Clock::now();
    const Approximation x = a.approximator().budget(budget);
    const LodReport r = lodReport(a, x, seconds(t1), setup.distance);
    const std::filesystem::path file = setup.outDir / (setup.stem + "-" + std::string(scheme) +
                                                       "-" + std::to_string(budget) + ".obj");
    writeMesh(file.string(), x.mesh);
    char row[512];
    std::snprintf(row, sizeof row,
                  "| %s | %lld | %d | %lld of %lld | %.3e | %.3e | %.3e | %.3f |\n", scheme, budget,
                  r.triangles, r.kept, r.total, r.errors.l2RmsRelative, r.errors.rmsRelative,
                  r.errors.hausdorffRelative, r.extractSeconds);
    md << row;
    lods.push(lodJson(r).add("budget", budget).add("file", file.string()));
    if (!setup.json)
      std::printf("  budget %5lld: %5d triangles, RMS %.2e, Hausdorff %.2e -> %s\n", budget,
                  r.triangles, r.errors.rmsRelative, r.errors.hausdorffRelative,
                  file.string().c_str());
  }
  return lods;
}

// One scheme: analyse, rebuild, the three levels of detail, the sweep and its plot.
Json demoScheme(const DemoSetup& setup, const TriMesh& mesh, Scheme scheme,
                std::ostringstream& md) {
  AnalysisOptions options;
  options.scheme = scheme;
  options.wavelets = setup.wavelets;
  const AnalysedSurface a(mesh, options, setup.in, setup.progress);
  const auto t0 = Clock::now();
  const Points back = synthesize(a.bank(), a.decomposition(), a.levels());
  const double tS = seconds(t0);
  const double err =
      (back - a.canonicalPositions()).cwiseAbs().maxCoeff() / boundingBoxDiagonal(mesh.V);
  if (!setup.json)
    std::printf(
        "\n%s: analysis %.3f s, synthesis %.3f s, reconstruction error %.2g of the "
        "diagonal\n",
        schemeName(scheme), a.times().total(), tS, err);
  const Json lods = demoBudgets(setup, a, md);
  const SweepTable t = sweepTable(a, setup.points, setup.distance, setup.progress);
  const std::string base = (setup.outDir / ("sweep-" + std::string(schemeName(scheme)))).string();
  writeTextFile(base + ".csv", t.csv);
  if (setup.gnuplot)
    plotSweep(base + ".csv", base + ".png", std::filesystem::path(setup.in).filename().string(),
              schemeName(scheme));
  if (!setup.json)
    std::printf("  error against triangles: %s.csv%s\n", base.c_str(),
                setup.gnuplot ? (" and " + base + ".png").c_str() : " (no gnuplot: no plot)");
  return Json::object()
      .add("scheme", schemeName(scheme))
      .add("rings", setup.wavelets.rings)
      .add("analysis_seconds", a.times().total())
      .add("synthesis_seconds", tS)
      .add("reconstruction_error", err)
      .add("per_level", levelsJson(a.hierarchy(), a.decomposition()))
      .add("lods", lods)
      .add("sweep_csv", base + ".csv");
}

}  // namespace

// The paper's section 4 on the bundled head: analyse and rebuild it with both
// schemes, extract the levels of detail of the paper's Figure 8 (4,054, 12,310 and
// 16,098 triangles), measure their errors, sweep the whole range, and write it all
// to --out (default out/).
int cmdDemo(const Argv& argv) {
  Args args("demo", argv,
            withRemeshOptions({"rings", "out", "samples", "seed", "points", "levels"}),
            flags({"remesh"}));
  if (args.positional().size() > 1)
    throw Error("demo: at most one input mesh (default: the bundled head)");
  if (args.has("levels") && !args.has("remesh"))
    throw Error("demo: --levels sets the remeshing's levels; it needs --remesh");
  const Common opt = common(args);
  const bool bundled = args.positional().empty();
  DemoSetup setup;
  setup.in = bundled ? bundledDataPath() : args.positional()[0];
  setup.stem = bundled ? "igea" : std::filesystem::path(setup.in).stem().string();
  setup.outDir = args.get("out", "out");
  setup.distance = distanceOptions(args);
  setup.points = static_cast<int>(args.integer("points", 16, 2, 1000));
  setup.gnuplot = std::system("command -v gnuplot >/dev/null 2>&1") == 0;
  setup.wavelets.rings = static_cast<int>(args.integer("rings", kDefaultRings, 0, 8));
  setup.json = opt.json;
  setup.progress = opt.progress;

  const LoadedSurface s = loadInput(setup.in, inputOptions(args, true), opt);
  std::filesystem::create_directories(setup.outDir);
  std::ostringstream md;
  md << demoIntroduction(setup, bundled, s);
  if (!opt.json) {
    if (s.remeshing) printRemesh(setup.in, *s.remeshing);
    std::printf("%s: %d vertices, %d faces\n", setup.in.c_str(), static_cast<int>(s.mesh.V.rows()),
                static_cast<int>(s.mesh.F.rows()));
  }
  Json runs = Json::array();
  for (Scheme scheme : {Scheme::Loop, Scheme::Linear})
    runs.push(demoScheme(setup, s.mesh, scheme, md));
  const std::string table = (setup.outDir / "errors.md").string();
  writeTextFile(table, md.str());
  if (opt.json) {
    Json j = startJson(s);
    std::cout << j.add("command", "demo")
                     .add("input", setup.in)
                     .add("out", setup.outDir.string())
                     .add("table", table)
                     .add("runs", runs)
                     .str()
              << "\n";
  } else {
    std::printf("\nerror table: %s\nall outputs in %s/\n", table.c_str(),
                setup.outDir.string().c_str());
  }
  return 0;
}

}  // namespace osdmra::cli
