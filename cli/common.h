// What every osdmra command shares: the common options (--json, --progress,
// --quiet), the mapping from command-line options to the library's option structs,
// and the surface a command works on (the pipeline's input, osdmra/pipeline.h).
#pragma once

#include <algorithm>
#include <chrono>
#include <set>
#include <string>
#include <vector>

#include "args.h"
#include "osdmra/pipeline.h"
#include "remesh_flags.h"

namespace osdmra::cli {

using Clock = std::chrono::steady_clock;
double seconds(Clock::time_point since);

/// --json and the progress reporter that --progress / --quiet / a terminal choose.
struct Common {
  bool json = false;
  Progress progress;
};
Common common(const Args& args);

/// The flags every command takes, plus `extra`.
std::set<std::string> flags(std::set<std::string> extra = {});

WaveletOptions waveletOptions(const Args& args);
/// --remesh and its options, with the distance options of the command; for the levels
/// of detail (lod, sweep, demo) with their defaults (remeshOptions' levelsOfDetail).
InputOptions inputOptions(const Args& args, bool levelsOfDetail = false);
/// What a command takes where its options say nothing.
struct AnalysisDefaults {
  const char* scheme = "loop";
  const char* placement = "surface";
};
/// Levels of detail (lod, sweep) are measured against the input mesh, which the
/// polyhedral scheme interpolates and Loop's limit surface only approximates; `lod`
/// extracts once, so it can afford the closest fit (a few seconds on 300,000 faces),
/// and `sweep` extracts many times, so it fits each level once (levels). On the bunny
/// and the elephant at 1-10% of their triangles (docs/LOD.md) these defaults came
/// 2.6-4.1x closer to the scan than Loop on the truncated surface.
constexpr AnalysisDefaults kLodDefaults{"linear", "closest"};
constexpr AnalysisDefaults kSweepDefaults{"linear", "levels"};
/// --levels, --scheme, --wavelets, --rings, --importance, --exact, --selection,
/// --placement, --metric.
AnalysisOptions analysisOptions(const Args& args, const AnalysisDefaults& defaults = {});
/// The codec's weights in `o` from --tangent-weight, --tangent-floor (by default the
/// smaller of its own and the weight), --bend-gain and --level-gain (compress and the
/// codec's bench, which links none of the front end's sources: inline).
inline void readCodecWeights(const Args& args, CodecOptions& o) {
  o.tangentWeight = args.real("tangent-weight", o.tangentWeight, 1e-3, 1);
  o.tangentFloor =
      args.real("tangent-floor", std::min(o.tangentFloor, o.tangentWeight), 1e-3, o.tangentWeight);
  o.bendGain = args.real("bend-gain", o.bendGain, 0, 1e6);
  o.levelGain = args.real("level-gain", o.levelGain, 1, 4);
}

/// loadSurface() on the command's input, with --remesh when given; remeshing
/// warnings go to stderr as they come.
LoadedSurface loadInput(const std::string& in, const Args& args, const Common& opt);
/// The same with input options the command has adjusted.
LoadedSurface loadInput(const std::string& in, const InputOptions& input, const Common& opt);
/// A remeshing's warnings on stderr, with the library's option names as the CLI's flags.
void printRemeshWarnings(const std::string& in, const RemeshReport& r);

}  // namespace osdmra::cli
