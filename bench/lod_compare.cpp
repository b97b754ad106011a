// Levels of detail side by side (issue 14): osdmra with each selection and placement,
// both schemes, against meshoptimizer's simplifier and, when built with CGAL, CGAL's
// Garland-Heckbert edge collapse, on the same inputs at the same triangle budgets.
//
//   osdmra_lod_compare IN... [--samples N] [--budgets B,B,...]
//   osdmra_lod_compare --scans SCAN... [--samples N]   (any mesh, as lod --remesh takes it)
//
// Each IN must have subdivision connectivity (a remesh). Budgets: the paper's (4,054,
// 12,310, 16,098 triangles) and 1%, 3%, 10% of each input's triangles, or the list
// given. Prints one markdown row per input, budget and method: the triangles made,
// the sampled symmetric RMS and Hausdorff distances (osdmra/geometry/distance.h,
// relative to the reference's bounding-box diagonal) to the input mesh and, for Loop,
// also to its limit surface (the surface osdmra's Loop levels of detail approximate),
// and the time of one extraction or simplification (osdmra: Approximator::budget on a
// surface analysed once; its one-time set-up is printed per configuration). The row
// "osdmra remeshed" is the input remeshed again for each budget (remeshedRows).
#include <meshoptimizer.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include "osdmra/geometry/distance.h"
#include "osdmra/mesh/io.h"
#include "osdmra/pipeline.h"
#include "stopwatch.h"

#ifdef OSDMRA_HAVE_CGAL
// CGAL's Garland-Heckbert quadrics copy Eigen 4x4 matrices that GCC 12 believes may be
// uninitialised (in CGAL's and Eigen's code, not ours); warnings are errors here.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/Count_stop_predicate.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/GarlandHeckbert_plane_policies.h>
#include <CGAL/Surface_mesh_simplification/edge_collapse.h>
#endif

using namespace osdmra;

namespace {

using bench::Clock;
using bench::secondsSince;

struct Row {
  std::string method;
  long long budget = 0;
  int triangles = 0;
  SurfaceDistance input, own;  // own: against the limit surface (Loop only)
  double seconds = 0;
  bool hasOwn = false;
};

TriMesh meshoptSimplify(const TriMesh& m, long long budget, double& seconds) {
  std::vector<float> positions;
  std::vector<unsigned> indices, out(3 * static_cast<std::size_t>(m.F.rows()));
  for (Eigen::Index i = 0; i < m.V.rows(); ++i)
    for (int k = 0; k < 3; ++k) positions.push_back(static_cast<float>(m.V(i, k)));
  for (Eigen::Index f = 0; f < m.F.rows(); ++f)
    for (int k = 0; k < 3; ++k) indices.push_back(static_cast<unsigned>(m.F(f, k)));
  const auto t0 = Clock::now();
  float error = 0;
  const std::size_t count = meshopt_simplify(
      out.data(), indices.data(), indices.size(), positions.data(), positions.size() / 3,
      3 * sizeof(float), static_cast<std::size_t>(3 * budget), 1.0f, 0, &error);
  seconds = secondsSince(t0);
  TriMesh r{m.V, Faces(static_cast<Eigen::Index>(count / 3), 3), Points()};
  for (std::size_t i = 0; i < count; ++i) r.F(static_cast<Eigen::Index>(i / 3), i % 3) = out[i];
  return r;
}

#ifdef OSDMRA_HAVE_CGAL
TriMesh cgalGarlandHeckbert(const TriMesh& m, long long budget, double& seconds) {
  using Kernel = CGAL::Simple_cartesian<double>;
  using SurfaceMesh = CGAL::Surface_mesh<Kernel::Point_3>;
  namespace SMS = CGAL::Surface_mesh_simplification;
  SurfaceMesh sm;
  std::vector<SurfaceMesh::Vertex_index> v;
  for (Eigen::Index i = 0; i < m.V.rows(); ++i)
    v.push_back(sm.add_vertex(Kernel::Point_3(m.V(i, 0), m.V(i, 1), m.V(i, 2))));
  for (Eigen::Index f = 0; f < m.F.rows(); ++f)
    sm.add_face(v[m.F(f, 0)], v[m.F(f, 1)], v[m.F(f, 2)]);
  const auto t0 = Clock::now();
  SMS::GarlandHeckbert_plane_policies<SurfaceMesh, Kernel> policies(sm);
  // CGAL 5.5 stops on an edge count: a closed triangle mesh has 3/2 edges per face.
  SMS::Count_stop_predicate<SurfaceMesh> stop(static_cast<std::size_t>(3 * budget / 2));
  SMS::edge_collapse(
      sm, stop,
      CGAL::parameters::get_cost(policies.get_cost()).get_placement(policies.get_placement()));
  seconds = secondsSince(t0);
  sm.collect_garbage();
  TriMesh r;
  r.V.resize(static_cast<Eigen::Index>(sm.number_of_vertices()), 3);
  for (auto x : sm.vertices()) {
    const auto& p = sm.point(x);
    r.V.row(static_cast<Eigen::Index>(x.idx())) << p.x(), p.y(), p.z();
  }
  r.F.resize(static_cast<Eigen::Index>(sm.number_of_faces()), 3);
  Eigen::Index f = 0;
  for (auto face : sm.faces()) {
    int k = 0;
    for (auto x : CGAL::vertices_around_face(sm.halfedge(face), sm))
      r.F(f, k++) = static_cast<int>(x.idx());
    ++f;
  }
  return r;
}
#pragma GCC diagnostic pop
#endif

struct Config {
  Scheme scheme;
  Selection selection;
  Placement placement;
  bool surfaceMetric = false;
  std::string name() const {
    return std::string("osdmra ") + (scheme == Scheme::Loop ? "loop" : "linear") + " " +
           selectionName(selection) + " " + placementName(placement) +
           (surfaceMetric ? " area" : "");
  }
};

std::vector<long long> budgetsFor(int faces, const std::vector<long long>& given) {
  if (!given.empty()) return given;
  std::vector<long long> b{4054, 12310, 16098};
  for (double p : {0.01, 0.03, 0.10}) b.push_back(std::llround(p * faces));
  std::sort(b.begin(), b.end());
  b.erase(std::unique(b.begin(), b.end()), b.end());
  b.erase(std::remove_if(b.begin(), b.end(), [&](long long x) { return x >= faces; }), b.end());
  return b;
}

void print(const std::string& input, const Row& r) {
  char own[64] = "";
  if (r.hasOwn)
    std::snprintf(own, sizeof own, "%.3e / %.3e", r.own.rmsRelative, r.own.hausdorffRelative);
  std::printf("| %s | %s | %lld | %d | %.3e | %.3e | %s | %.1f |\n", input.c_str(),
              r.method.c_str(), r.budget, r.triangles, r.input.rmsRelative,
              r.input.hausdorffRelative, own, 1e3 * r.seconds);
  std::fflush(stdout);
}

// The remeshings `osdmra lod IN --remesh --budget B` tries on the same input: the input
// remeshed again over bases of the budget (lodForBudget, lod's defaults, without the
// trial of the input's own hierarchy, which is the row "osdmra linear rd closest"),
// which frees the level of detail from the input base's triangle shapes at the cost of
// its hierarchy (the result is not nested in the input's levels) and of four
// remeshings. Its time is all of that.
void remeshedRows(const std::string& path, const std::string& name, const TriMesh& input,
                  const std::vector<long long>& budgets, const DistanceOptions& dist) {
  InputOptions io;
  io.remesh = true;
  RemeshReport repairs;
  const TriMesh repaired = readRemeshInput(path, io, &repairs);
  AnalysisOptions ao;
  ao.scheme = Scheme::Linear;
  ao.approximation.placement = Placement::Closest;
  BudgetSearchOptions search;
  search.inputHierarchy = false;
  for (long long b : budgets) {
    Row r;
    r.method = "osdmra remeshed";
    r.budget = b;
    const auto t0 = Clock::now();
    const BudgetLod lod = lodForBudget(repaired, repairs, path, b, io, ao, search);
    r.seconds = secondsSince(t0);
    r.triangles = lod.lod.triangles();
    r.input = surfaceDistance(lod.lod.mesh, input, dist);
    print(name, r);
  }
}

void compare(const std::string& path, const std::vector<long long>& given,
             const DistanceOptions& dist) {
  const std::string name = path.substr(path.find_last_of('/') + 1);
  const LoadedSurface s = loadSurface(path);
  const TriMesh& input = s.mesh;
  const std::vector<long long> budgets = budgetsFor(static_cast<int>(input.F.rows()), given);
  std::vector<Config> configs;
  for (Scheme scheme : {Scheme::Linear, Scheme::Loop})
    for (auto [sel, pl] : {std::pair{Selection::Importance, Placement::Surface},
                           std::pair{Selection::RateDistortion, Placement::Surface},
                           std::pair{Selection::RateDistortion, Placement::Fit},
                           std::pair{Selection::RateDistortion, Placement::Closest},
                           std::pair{Selection::RateDistortion, Placement::Levels}})
      configs.push_back({scheme, sel, pl});
  for (Scheme scheme : {Scheme::Linear, Scheme::Loop})
    configs.push_back({scheme, Selection::RateDistortion, Placement::Fit, true});
  for (Scheme scheme : {Scheme::Linear, Scheme::Loop}) {
    AnalysisOptions ao;
    ao.scheme = scheme;
    ao.approximator = false;
    AnalysedSurface a(input, ao, path);
    for (const Config& c : configs) {
      if (c.scheme != scheme) continue;
      ApproximationOptions o;
      o.selection = c.selection;
      o.placement = c.placement;
      o.surfaceMetric = c.surfaceMetric;
      const auto t0 = Clock::now();
      a.setApproximation(o);
      a.approximator().triangleCounts();
      a.approximator().prepare();  // Levels: every level's fit, once
      std::fprintf(stderr, "%s: %s: set-up %.3f s\n", name.c_str(), c.name().c_str(),
                   secondsSince(t0));
      for (long long b : budgets) {
        Row r;
        r.method = c.name();
        r.budget = b;
        const auto t1 = Clock::now();
        const Approximation x = a.approximator().budget(b);
        r.seconds = secondsSince(t1);
        r.triangles = x.triangles();
        r.input = surfaceDistance(x.mesh, input, dist);
        if (scheme == Scheme::Loop) {
          r.own = surfaceDistance(x.mesh, a.approximator().fullResolution(), dist);
          r.hasOwn = true;
        }
        print(name, r);
      }
    }
  }
  // A peer simplifier's row: its mesh at the budget, timed by the peer itself.
  auto peer = [&](const char* method, long long b, auto simplify) {
    Row r;
    r.method = method;
    r.budget = b;
    const TriMesh m = simplify(input, b, r.seconds);
    r.triangles = static_cast<int>(m.F.rows());
    r.input = surfaceDistance(m, input, dist);
    print(name, r);
  };
  remeshedRows(path, name, input, budgets, dist);
  for (long long b : budgets) {
    peer("meshoptimizer", b, meshoptSimplify);
#ifdef OSDMRA_HAVE_CGAL
    peer("CGAL Garland-Heckbert", b, cgalGarlandHeckbert);
#endif
  }
}

// A scan as a user gives it to `osdmra lod SCAN --remesh --budget B`: what lod does
// (lodForBudget: remeshed over the budget, twice, a half, a quarter and a sixteenth of it, each
// analysed and cut with lod's defaults, polyhedral, rate-distortion selection, closest
// placement: kLodDefaults in cli/common.h, the closest to the scan kept); the peers simplify the
// scan itself; every mesh is measured against the scan. Budgets: 1%, 3% and 10% of the
// scan's triangles. One row per budget: the base kept, triangles, RMS / Hausdorff of
// each, the ratios, and the times (osdmra: lodForBudget in all, with the kept level of
// detail's extraction in it; the peers: simplification).
void compareScan(const std::string& path, const DistanceOptions& dist) {
  const std::string name = path.substr(path.find_last_of('/') + 1);
  InputOptions io;
  io.remesh = true;
  RemeshReport repairs;
  const TriMesh scan = readRemeshInput(path, io, &repairs);
  const int faces = static_cast<int>(scan.F.rows());
  AnalysisOptions ao;
  ao.scheme = Scheme::Linear;
  ao.approximation.placement = Placement::Closest;
  for (double p : {0.01, 0.03, 0.10}) {
    const long long b = std::llround(p * faces);
    const auto t0 = Clock::now();
    const BudgetLod lod = lodForBudget(scan, repairs, path, b, io, ao);  // the scan read once
    const double prepare = secondsSince(t0);
    const double extract = lod.extractSeconds;
    const Approximation& x = lod.lod;
    // The base kept: a remeshing's, or the scan's own where it has subdivision connectivity.
    const BaseTrial& kept = lod.trials[static_cast<std::size_t>(lod.chosen)];
    char base[48];
    std::snprintf(base, sizeof base, "%d%s", kept.baseFaces,
                  kept.inputHierarchy ? " (the scan's own)" : "");
    const SurfaceDistance ours = surfaceDistance(x.mesh, scan, dist);
    double mSeconds = 0;
    const TriMesh m = meshoptSimplify(scan, b, mSeconds);
    const SurfaceDistance mo = surfaceDistance(m, scan, dist);
    char cgal[96] = "n/a", ratioCgal[16] = "n/a";
#ifdef OSDMRA_HAVE_CGAL
    double cSeconds = 0;
    const TriMesh c = cgalGarlandHeckbert(scan, b, cSeconds);
    const SurfaceDistance gh = surfaceDistance(c, scan, dist);
    std::snprintf(cgal, sizeof cgal, "%d: %.2e / %.2e (%.2f s)", static_cast<int>(c.F.rows()),
                  gh.rmsRelative, gh.hausdorffRelative, cSeconds);
    std::snprintf(ratioCgal, sizeof ratioCgal, "%.2f", ours.rmsRelative / gh.rmsRelative);
#endif
    std::printf(
        "| %s | %d | %lld | %s | %d: %.2e / %.2e (%.1f s, %.2f s) | %d: %.2e / %.2e (%.2f s) "
        "| %s | %.2f | %s |\n",
        name.c_str(), faces, b, base, x.triangles(), ours.rmsRelative, ours.hausdorffRelative,
        prepare, extract, static_cast<int>(m.F.rows()), mo.rmsRelative, mo.hausdorffRelative,
        mSeconds, cgal, ours.rmsRelative / mo.rmsRelative, ratioCgal);
    std::fflush(stdout);
  }
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> inputs;
  std::vector<long long> budgets;
  DistanceOptions dist;
  bool scans = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--scans") {
      scans = true;
    } else if (a == "--samples" && i + 1 < argc) {
      dist.samples = std::atoi(argv[++i]);
    } else if (a == "--budgets" && i + 1 < argc) {
      std::stringstream ss(argv[++i]);
      for (std::string t; std::getline(ss, t, ',');) budgets.push_back(std::atoll(t.c_str()));
    } else {
      inputs.push_back(a);
    }
  }
  if (inputs.empty()) {
    std::fprintf(stderr,
                 "usage: osdmra_lod_compare IN... [--samples N] [--budgets B,B,...]\n"
                 "       osdmra_lod_compare --scans SCAN... [--samples N]\n");
    return 2;
  }
  if (scans) {
    std::printf(
        "| scan | faces | budget | base faces | osdmra lod --remesh: triangles: RMS / Hausdorff "
        "(all, extraction) | meshoptimizer | CGAL Garland-Heckbert | RMS / "
        "meshoptimizer's | RMS / CGAL's |\n|---|---:|---:|---:|---|---|---|---:|---:|\n");
    try {
      for (const std::string& in : inputs) compareScan(in, dist);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "osdmra_lod_compare: %s\n", e.what());
      return 1;
    }
    return 0;
  }
  std::printf(
      "| input | method | budget | triangles | RMS | Hausdorff | to the limit surface: RMS / "
      "Hausdorff | ms |\n|---|---|---|---|---|---|---|---|\n");
  try {
    for (const std::string& in : inputs) compare(in, budgets, dist);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "osdmra_lod_compare: %s\n", e.what());
    return 1;
  }
  return 0;
}
