#include "common.h"

#include <unistd.h>

#include <cstdio>

namespace osdmra::cli {

double seconds(Clock::time_point since) {
  return std::chrono::duration<double>(Clock::now() - since).count();
}

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

std::set<std::string> flags(std::set<std::string> extra) {
  static const std::set<std::string> kCommonFlags = {"json", "progress", "quiet", "help", "h"};
  extra.insert(kCommonFlags.begin(), kCommonFlags.end());
  return extra;
}

WaveletOptions waveletOptions(const Args& args) {
  WaveletOptions w;
  w.kind = parseWaveletKind(args.get("wavelets", "quasi"));
  w.rings = static_cast<int>(args.integer("rings", kDefaultRings, 0, 8));
  if (w.kind != WaveletKind::Quasi) w.rings = 0;
  return w;
}

InputOptions inputOptions(const Args& args, bool levelsOfDetail) {
  InputOptions o;
  o.remesh = args.has("remesh");
  if (o.remesh) o.remeshing = remeshOptions(args, levelsOfDetail);
  o.minComponentFaces = static_cast<int>(args.integer("min-component-faces", 0, 0, 1 << 30));
  o.distance = distanceOptions(args);
  return o;
}

AnalysisOptions analysisOptions(const Args& args, const AnalysisDefaults& defaults) {
  AnalysisOptions o;
  o.levels = static_cast<int>(args.integer("levels", -1, 1, 15));
  o.scheme = parseScheme(args.get("scheme", defaults.scheme));
  o.wavelets = waveletOptions(args);
  const std::string how = args.get("importance", "scaled");
  if (how != "scaled" && how != "plain")
    throw Error("--importance must be scaled or plain, got '" + how + "'");
  o.approximation.importance = how == "plain" ? Importance::Plain : Importance::Scaled;
  o.approximation.saturate = !args.has("exact");
  o.approximation.selection = parseSelection(args.get("selection", "rd"));
  o.approximation.placement = parsePlacement(args.get("placement", defaults.placement));
  const std::string metric = args.get("metric", "domain");
  if (metric != "domain" && metric != "surface")
    throw Error("--metric must be domain or surface, got '" + metric + "'");
  o.approximation.surfaceMetric = metric == "surface";
  return o;
}

LoadedSurface loadInput(const std::string& in, const Args& args, const Common& opt) {
  return loadInput(in, inputOptions(args), opt);
}

LoadedSurface loadInput(const std::string& in, const InputOptions& input, const Common& opt) {
  LoadedSurface s = loadSurface(in, input, opt.progress);
  if (s.remeshing) printRemeshWarnings(in, *s.remeshing);
  return s;
}

void printRemeshWarnings(const std::string& in, const RemeshReport& r) {
  for (const std::string& w : r.warnings)
    std::fprintf(stderr, "osdmra: warning: %s: %s\n", in.c_str(), withFlagNames(w).c_str());
}

}  // namespace osdmra::cli
