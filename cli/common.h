// What every osdmra command shares: the common options (--json, --progress,
// --quiet), the mapping from command-line options to the library's option structs,
// and the surface a command works on (the pipeline's input, osdmra/pipeline.h).
#pragma once

#include <chrono>
#include <set>
#include <string>
#include <vector>

#include "args.h"
#include "osdmra/pipeline.h"

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
DistanceOptions distanceOptions(const Args& args);
RemeshOptions remeshOptions(const Args& args);
/// --remesh and its options, with the distance options of the command.
InputOptions inputOptions(const Args& args);
/// --levels, --scheme, --wavelets, --rings, --importance, --exact.
AnalysisOptions analysisOptions(const Args& args);

/// loadSurface() on the command's input, with --remesh when given; remeshing
/// warnings go to stderr as they come.
LoadedSurface loadInput(const std::string& in, const Args& args, const Common& opt);

}  // namespace osdmra::cli
