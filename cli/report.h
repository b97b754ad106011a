// How the osdmra tool reports what the library computed: the JSON objects and the
// one-line text summaries that several commands share.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "json.h"
#include "osdmra/mesh/connectivity.h"
#include "osdmra/pipeline.h"

namespace osdmra::cli {

/// Vertices, faces, edges, components, boundary loops, genus, valences, diagonal.
Json topologyJson(const TriMesh& mesh, const Connectivity& c);

/// A remeshing: sizes, defects left, distance to the input, time, warnings.
Json remeshJson(const RemeshReport& r);
void printRemesh(const std::string& in, const RemeshReport& r);

/// A command's JSON object, starting with its input's remeshing when there was one.
Json startJson(const LoadedSurface& s);

/// Per level: vertices, coefficients and the largest |d^j_m|.
Json levelsJson(const Hierarchy& h, const Decomposition& d);
/// Largest |d^j_m| of a level (0 for a level without coefficients).
double maxDetail(const Points& d);

/// The numbers reported with every level of detail.
struct LodReport {
  int triangles = 0;
  long long selected = 0, kept = 0, total = 0;
  LodErrors errors;
  /// With --remesh: the distances to the input as given (repaired), which a level of
  /// detail made by another tool from the same file would be measured against.
  std::optional<SurfaceDistance> toInput;
  double extractSeconds = 0;
  std::vector<std::string> warnings;
};
/// With `loaded` (what `a` analyses) remeshed, also the distances to its input; with
/// a budget, a warning when the mesh is over it.
LodReport lodReport(const AnalysedSurface& a, const Approximation& x, double extractSeconds,
                    const DistanceOptions& distance, const LoadedSurface* loaded = nullptr,
                    long long budget = -1);
Json lodJson(const LodReport& r);

/// The base sizes `lod --remesh --budget` tried (lodForBudget): an array of objects
/// (base faces asked and made, levels, triangles, its crossing pairs, RMS to the
/// input, seconds, kept).
Json baseTrialsJson(const BudgetLod& b);
void printBaseTrials(const BudgetLod& b);

}  // namespace osdmra::cli
