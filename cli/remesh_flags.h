// The remesher's command-line options (--base-faces, --levels, --feature-angle,
// --max-faces, --smoothing-sweeps, --stages, --retriangulation, --skinny-where-flat,
// --cap-angle, --base-splits, --grid-refinement)
// and those of the
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
              "stages", "retriangulation", "skinny-where-flat", "cap-angle", "base-splits",
              "grid-refinement"});
  return own;
}

// --stages auto|vertex|mesh (RemeshOptions::stages: auto is perVertexElseMeshWide);
// `fallback` is the command's default (remeshOptions).
inline StageRelaxation stageRelaxation(const Args& args, const std::string& fallback) {
  const std::string s = args.get("stages", fallback);
  if (s == "auto") return StageRelaxation::perVertexElseMeshWide;
  if (s == "vertex") return StageRelaxation::perVertex;
  if (s == "mesh") return StageRelaxation::meshWide;
  throw Error("--stages: expected auto, vertex or mesh, got '" + s + "'");
}

// --retriangulation shape|error (RemeshOptions::retriangulateByError); `fallback` as
// for --stages.
inline bool retriangulateByError(const Args& args, const std::string& fallback) {
  const std::string s = args.get("retriangulation", fallback);
  if (s != "shape" && s != "error")
    throw Error("--retriangulation: expected shape or error, got '" + s + "'");
  return s == "error";
}

// An option that is on unless the command line says --NAME off.
inline bool onOff(const Args& args, const std::string& name) {
  const std::string value = args.get(name, "on");
  if (value != "on" && value != "off")
    throw Error("--" + name + ": expected on or off, got '" + value + "'");
  return value == "on";
}

// `levelsOfDetail`: for lod, sweep, demo and the viewer, whose coarsest level is the
// base: --stages and --retriangulation default to vertex and error (the base as close
// to the input as the remesher can make it; docs/LOD.md), elsewhere to auto and shape.
inline RemeshOptions remeshOptions(const Args& args, bool levelsOfDetail = false) {
  RemeshOptions o;
  o.baseFaces = static_cast<int>(args.integer("base-faces", o.baseFaces, 4, 1 << 24));
  o.levels = static_cast<int>(args.integer("levels", o.levels, 0, 8));
  o.featureAngle = args.real("feature-angle", o.featureAngle, 0.0, 180.0);
  o.maxFaces = args.integer("max-faces", o.maxFaces, 0, 1LL << 40);
  o.smoothingSweeps =
      static_cast<int>(args.integer("smoothing-sweeps", o.smoothingSweeps, 0, 1000));
  o.stages = stageRelaxation(args, levelsOfDetail ? "vertex" : "auto");
  o.retriangulateByError = retriangulateByError(args, levelsOfDetail ? "error" : "shape");
  // 0 (none) for every command: lod's budget search reads it for its second trial over
  // the whole budget instead, where it defaults to BudgetSearchOptions' fraction.
  o.skinnyWhereFlat = args.real("skinny-where-flat", 0.0, 0.0, 1.0);
  o.capAngle = args.real("cap-angle", o.capAngle, 0.0, 180.0);
  o.splitFoldingFaces = onOff(args, "base-splits");
  o.refineGrid = onOff(args, "grid-refinement");
  return o;
}

inline DistanceOptions distanceOptions(const Args& args) {
  DistanceOptions o;
  o.samples = static_cast<int>(args.integer("samples", o.samples, 0, 100000000));
  o.seed = static_cast<std::uint64_t>(args.integer("seed", 1, 0, 1LL << 62));
  return o;
}

}  // namespace osdmra::cli
