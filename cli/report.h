// How the osdmra tool reports what the library computed: the JSON objects and the
// one-line text summaries that several commands share.
#pragma once

#include <string>

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
  double extractSeconds = 0;
};
LodReport lodReport(const AnalysedSurface& a, const Approximation& x, double extractSeconds,
                    const DistanceOptions& distance);
Json lodJson(const LodReport& r);

}  // namespace osdmra::cli
