// The remesher's command-line options (--base-faces, --levels, --feature-angle,
// --max-faces, --smoothing-sweeps, --stages, --retriangulation) and those of the
// distance it reports (--samples, --seed), read the same way by the tool and the
// viewer.
#pragma once

#include <set>
#include <string>

#include "args.h"
#include "osdmra/geometry/distance.h"
#include "osdmra/remesh/remesh.h"

namespace osdmra::cli {

// A command's own valued options with the remesher's (read by remeshOptions, and
// --min-component-faces by inputOptions), so that every command that remeshes takes
// all of them.
inline std::set<std::string> withRemeshOptions(std::set<std::string> own) {
  own.insert({"base-faces", "feature-angle", "min-component-faces", "max-faces", "smoothing-sweeps",
              "stages", "retriangulation"});
  return own;
}

// --stages mesh|vertex (RemeshOptions::stagesPerVertex); `fallback` is the command's
// default: vertex for the levels of detail (lod, sweep, the viewer), mesh elsewhere.
inline bool stagesPerVertex(const Args& args, const std::string& fallback) {
  const std::string s = args.get("stages", fallback);
  if (s != "mesh" && s != "vertex")
    throw Error("--stages: expected mesh or vertex, got '" + s + "'");
  return s == "vertex";
}

// --retriangulation shape|error (RemeshOptions::retriangulateByError); `fallback` as
// for --stages.
inline bool retriangulateByError(const Args& args, const std::string& fallback) {
  const std::string s = args.get("retriangulation", fallback);
  if (s != "shape" && s != "error")
    throw Error("--retriangulation: expected shape or error, got '" + s + "'");
  return s == "error";
}

inline RemeshOptions remeshOptions(const Args& args) {
  RemeshOptions o;
  o.baseFaces = static_cast<int>(args.integer("base-faces", o.baseFaces, 4, 1 << 24));
  o.levels = static_cast<int>(args.integer("levels", o.levels, 0, 8));
  o.featureAngle = args.real("feature-angle", o.featureAngle, 0.0, 180.0);
  o.maxFaces = args.integer("max-faces", o.maxFaces, 0, 1LL << 40);
  o.smoothingSweeps =
      static_cast<int>(args.integer("smoothing-sweeps", o.smoothingSweeps, 0, 1000));
  o.stagesPerVertex = stagesPerVertex(args, "mesh");
  o.retriangulateByError = retriangulateByError(args, "shape");
  return o;
}

inline DistanceOptions distanceOptions(const Args& args) {
  DistanceOptions o;
  o.samples = static_cast<int>(args.integer("samples", o.samples, 0, 100000000));
  o.seed = static_cast<std::uint64_t>(args.integer("seed", 1, 0, 1LL << 62));
  return o;
}

}  // namespace osdmra::cli
