// Benchmarks of the issues beyond the filter bank, each beside its peer in the same
// run:
//   recovery of subdivision connectivity against reading the same mesh from an ASCII
//   OBJ file (2,097,152 faces, shuffled vertex and face order);
//   remeshing a 40,962-vertex surface without subdivision connectivity (J = 5 over
//   about 300 base faces) beside meshoptimizer simplifying it to the same base size;
//   re-extraction of a level of detail from an analysed surface (Approximator::budget)
//   against meshoptimizer's simplifier (meshopt_simplify) at the same triangle counts,
//   on a semi-regular input of 524,288 faces: the bundled head refined twice more by
//   Loop subdivision. The sampled RMS and Hausdorff errors of both against the input
//   are reported as counters (computed once, outside the timed loop).
#include <benchmark/benchmark.h>
#include <meshoptimizer.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <random>

#include "allocator.h"
#include "meshopt_peer.h"
#include "osdmra/base/bundled_data.h"
#include "osdmra/geometry/distance.h"
#include "osdmra/mesh/io.h"
#include "osdmra/pipeline.h"
#include "osdmra/remesh/remesh.h"
#include "osdmra/subdivision/recovery.h"
#include "osdmra/subdivision/shapes.h"
#include "run_benchmarks.h"

using namespace osdmra;

namespace {

TriMesh shuffled(const TriMesh& m, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  const int n = static_cast<int>(m.V.rows());
  std::vector<int> perm(n), order(m.F.rows());
  for (int i = 0; i < n; ++i) perm[i] = i;
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
  std::shuffle(perm.begin(), perm.end(), rng);
  std::shuffle(order.begin(), order.end(), rng);
  TriMesh out{Points(n, 3), Faces(m.F.rows(), 3), Points()};
  for (int i = 0; i < n; ++i) out.V.row(perm[i]) = m.V.row(i);
  for (Eigen::Index f = 0; f < m.F.rows(); ++f)
    for (int c = 0; c < 3; ++c) out.F(f, c) = perm[m.F(order[f], (c + f) % 3)];
  return out;
}

// The level-9 displaced octahedron, shuffled, written once as ASCII OBJ.
const std::string& level9File() {
  static const std::string path = [] {
    const std::string p =
        (std::filesystem::temp_directory_path() / "osdmra-bench-oct9-shuffled.obj").string();
    writeMesh(p, shuffled(subdivide(shapes::octahedron(), 9, Scheme::Loop, 0.02, 3), 5));
    return p;
  }();
  return path;
}

void bmReadObj(benchmark::State& state) {
  const std::string& path = level9File();
  for (auto _ : state) benchmark::DoNotOptimize(readMesh(path));
  state.counters["faces"] = 2097152;
}

// Everything from the face list: the counting sort of corners, the labelling and the
// exact check of every round, down to the base mesh.
void bmRecover(benchmark::State& state) {
  static const TriMesh mesh = readMesh(level9File());
  for (auto _ : state) {
    const Recovery r = recoverSubdivision(mesh.F, static_cast<int>(mesh.V.rows()));
    if (r.levels != 9) state.SkipWithError("recovery did not find 9 levels");
    benchmark::DoNotOptimize(r);
  }
  state.counters["faces"] = 2097152;
}

// The semi-regular input of the level-of-detail comparison, with its analysis.
struct LodInput {
  TriMesh mesh;
  std::unique_ptr<AnalysedSurface> surface;
  std::vector<float> positions;  // for meshoptimizer
  std::vector<unsigned> indices;
  const Approximator& approx() const { return surface->approximator(); }
};

// The bundled head (6 levels), refined by Loop subdivision to `levels` (>= 6).
LodInput& lodInput(Scheme scheme, int levels = 8) {
  static std::unique_ptr<LodInput> cache[2][16];
  std::unique_ptr<LodInput>& c = cache[scheme == Scheme::Loop ? 0 : 1][levels];
  if (!c) {
    c = std::make_unique<LodInput>();
    const TriMesh head = readValidMesh(bundledDataPath());
    const Hierarchy h6 = Hierarchy::fromCanonical(head.F, static_cast<int>(head.V.rows()), 6);
    Hierarchy h(h6.faces(0), h6.numVertices(0), levels);
    Points V = head.V;
    for (int j = 6; j < levels; ++j) V = h.refinement(Scheme::Loop, j) * V;
    c->mesh = TriMesh{V, h.faces(levels), Points()};
    AnalysisOptions options;
    options.levels = levels;
    options.scheme = scheme;
    options.wavelets = {WaveletKind::Quasi, kDefaultRings};
    c->surface = std::make_unique<AnalysedSurface>(c->mesh, options);
    c->approx().triangleCounts();  // once per surface, timed by bmApproximatorSetup
    for (Eigen::Index i = 0; i < V.rows(); ++i)
      for (int k = 0; k < 3; ++k) c->positions.push_back(static_cast<float>(V(i, k)));
    for (Eigen::Index f = 0; f < c->mesh.F.rows(); ++f)
      for (int k = 0; k < 3; ++k) c->indices.push_back(static_cast<unsigned>(c->mesh.F(f, k)));
  }
  return *c;
}

void errorCounters(benchmark::State& state, const TriMesh& approx, const TriMesh& reference) {
  DistanceOptions o;
  o.samples = 100000;
  const SurfaceDistance d = surfaceDistance(approx, reference, o);
  state.counters["triangles"] = static_cast<double>(approx.F.rows());
  state.counters["rms_rel"] = d.rmsRelative;
  state.counters["hausdorff_rel"] = d.hausdorffRelative;
}

void bmOsdmraLod(benchmark::State& state, Scheme scheme, long long triangles) {
  const LodInput& in = lodInput(scheme);
  Approximation a;
  for (auto _ : state) {
    a = in.approx().budget(triangles);
    benchmark::DoNotOptimize(a);
  }
  // Against the input itself (polyhedral: the full-resolution surface is the input).
  errorCounters(state, a.mesh, in.mesh);
}

// The same with the vertices fitted by least squares (--placement fit) and importance
// in the surface's metric: the approximator is replaced for the run, then restored.
void bmOsdmraLodFit(benchmark::State& state, Scheme scheme, long long triangles) {
  LodInput& in = lodInput(scheme);
  ApproximationOptions o;
  o.placement = Placement::Fit;
  o.surfaceMetric = true;
  in.surface->setApproximation(o);
  in.approx().triangleCounts();
  Approximation a;
  for (auto _ : state) {
    a = in.approx().budget(triangles);
    benchmark::DoNotOptimize(a);
  }
  errorCounters(state, a.mesh, in.mesh);
  in.surface->setApproximation({});
  in.approx().triangleCounts();
}

// The same with --placement levels: every level's closest fit is made once, before the
// timed extractions (its time is the prepare_s counter), and looked up per extraction.
void bmOsdmraLodLevels(benchmark::State& state, Scheme scheme, long long triangles) {
  LodInput& in = lodInput(scheme);
  ApproximationOptions o;
  o.placement = Placement::Levels;
  in.surface->setApproximation(o);
  in.approx().triangleCounts();
  const auto t0 = std::chrono::steady_clock::now();
  in.approx().prepare();
  const double prepare =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  Approximation a;
  for (auto _ : state) {
    a = in.approx().budget(triangles);
    benchmark::DoNotOptimize(a);
  }
  errorCounters(state, a.mesh, in.mesh);
  state.counters["prepare_s"] = prepare;
  in.surface->setApproximation({});
  in.approx().triangleCounts();
}

// What an analysed surface costs once before its first budget: the approximator (one
// sort of the coefficients, the full-resolution reference, limit stencils for Loop)
// and the triangle count of every prefix of the importance order.
void bmApproximatorSetup(benchmark::State& state, Scheme scheme) {
  // Replaces the approximator the extraction benchmarks use by an identical one.
  LodInput& in = lodInput(scheme);
  for (auto _ : state) {
    in.surface->setApproximation({});
    benchmark::DoNotOptimize(in.approx().triangleCounts().back());
  }
}

void bmMeshopt(benchmark::State& state, long long triangles) {
  const LodInput& in = lodInput(Scheme::Linear);
  std::vector<unsigned> out(in.indices.size());
  std::size_t count = 0;
  for (auto _ : state) {
    float error = 0;
    count = meshopt_simplify(out.data(), in.indices.data(), in.indices.size(), in.positions.data(),
                             in.positions.size() / 3, 3 * sizeof(float),
                             static_cast<std::size_t>(3 * triangles), 1.0f, 0, &error);
    benchmark::DoNotOptimize(out.data());
  }
  TriMesh m{in.mesh.V, Faces(static_cast<Eigen::Index>(count / 3), 3), Points()};
  for (std::size_t i = 0; i < count; ++i) m.F(static_cast<Eigen::Index>(i / 3), i % 3) = out[i];
  errorCounters(state, m, in.mesh);
}

}  // namespace

// docs/LOD.md's table: the paper's three budgets on the bundled head, both schemes
// and meshoptimizer at the same counts, errors against the full-resolution surface.
int printTable() {
  std::printf("| method | budget | triangles | sampled RMS | Hausdorff |\n|---|---|---|---|---|\n");
  for (long long budget : {4054LL, 12310LL, 16098LL}) {
    for (Scheme s : {Scheme::Loop, Scheme::Linear}) {
      const LodInput& in = lodInput(s, 6);
      const Approximation a = in.approx().budget(budget);
      DistanceOptions o;
      const SurfaceDistance d = surfaceDistance(a.mesh, in.approx().fullResolution(), o);
      std::printf("| osdmra %s | %lld | %d | %.3e | %.3e |\n", schemeName(s), budget, a.triangles(),
                  d.rmsRelative, d.hausdorffRelative);
    }
    const LodInput& in = lodInput(Scheme::Linear, 6);
    std::vector<unsigned> out(in.indices.size());
    float error = 0;
    const std::size_t count =
        meshopt_simplify(out.data(), in.indices.data(), in.indices.size(), in.positions.data(),
                         in.positions.size() / 3, 3 * sizeof(float),
                         static_cast<std::size_t>(3 * budget), 1.0f, 0, &error);
    TriMesh m{in.mesh.V, Faces(static_cast<Eigen::Index>(count / 3), 3), Points()};
    for (std::size_t i = 0; i < count; ++i) m.F(static_cast<Eigen::Index>(i / 3), i % 3) = out[i];
    const SurfaceDistance d = surfaceDistance(m, in.mesh, DistanceOptions());
    std::printf("| meshoptimizer | %lld | %d | %.3e | %.3e |\n", budget,
                static_cast<int>(m.F.rows()), d.rmsRelative, d.hausdorffRelative);
  }
  return 0;
}

// A bumpy closed surface of 40,962 vertices without subdivision connectivity in its
// order (shuffled), the size of the remesher's target (a 35,000-vertex scan in 30 s).
const TriMesh& remeshInput() {
  static const TriMesh m = shuffled(subdivide(shapes::icosahedron(), 6, Scheme::Loop, 0.02, 4), 9);
  return m;
}

void bmRemesh(benchmark::State& state) {
  RemeshOptions o;
  o.baseFaces = 300;
  o.levels = 5;
  Remeshing r;
  for (auto _ : state) {
    r = remesh(remeshInput(), o);
    benchmark::DoNotOptimize(r);
  }
  DistanceOptions d;
  d.samples = 100000;
  const SurfaceDistance sd = surfaceDistance(r.mesh, remeshInput(), d);
  state.counters["base_faces"] = static_cast<double>(r.base.F.rows());
  state.counters["faces"] = static_cast<double>(r.mesh.F.rows());
  state.counters["rms_rel"] = sd.rmsRelative;
  state.counters["hausdorff_rel"] = sd.hausdorffRelative;
}

// The peer: meshoptimizer simplifying the same mesh to the same base size, which
// gives a coarse mesh but no parameterisation and no remeshed surface.
void bmMeshoptToBase(benchmark::State& state) {
  bench::bmMeshoptToFaces(state, remeshInput(), 300);
}

int main(int argc, char** argv) {
  // As the command line and the viewer, where levels of detail are extracted: both peers
  // then run on memory the process keeps (without it, faulting in each extraction's
  // fresh arrays took 15-25 of its 38-57 ms at 131,072 triangles; meshoptimizer's time
  // did not move). docs/BENCHMARKS.md.
  osdmra::cli::keepFreedMemory();
  if (argc > 1 && std::string(argv[1]) == "--table") return printTable();
  benchmark::RegisterBenchmark("Recovery/ReadAsciiObj/faces:2097152", bmReadObj)
      ->Unit(benchmark::kMillisecond)
      ->UseRealTime()
      ->Iterations(5);
  // Wall time: recovery runs its passes on every core.
  benchmark::RegisterBenchmark("Recovery/Recover/faces:2097152", bmRecover)
      ->Unit(benchmark::kMillisecond)
      ->UseRealTime()
      ->Iterations(5);
  benchmark::RegisterBenchmark("Remesh/Remesh/vertices:40962", bmRemesh)
      ->Unit(benchmark::kMillisecond)
      ->Iterations(3);
  benchmark::RegisterBenchmark("Remesh/MeshoptSimplifyToBase/vertices:40962", bmMeshoptToBase)
      ->Unit(benchmark::kMillisecond)
      ->Iterations(3);
  for (Scheme scheme : {Scheme::Linear, Scheme::Loop})
    benchmark::RegisterBenchmark(
        (std::string("Lod/ApproximatorSetup/") + schemeName(scheme)).c_str(), bmApproximatorSetup,
        scheme)
        ->Unit(benchmark::kMillisecond)
        ->Iterations(3);
  for (long long t : {26214LL, 52428LL, 131072LL}) {
    benchmark::RegisterBenchmark(("Lod/OsdmraLinear/triangles:" + std::to_string(t)).c_str(),
                                 bmOsdmraLod, Scheme::Linear, t)
        ->Unit(benchmark::kMillisecond)
        ->Iterations(3);
    benchmark::RegisterBenchmark(("Lod/OsdmraLoop/triangles:" + std::to_string(t)).c_str(),
                                 bmOsdmraLod, Scheme::Loop, t)
        ->Unit(benchmark::kMillisecond)
        ->Iterations(3);
    benchmark::RegisterBenchmark(("Lod/OsdmraLinearFit/triangles:" + std::to_string(t)).c_str(),
                                 bmOsdmraLodFit, Scheme::Linear, t)
        ->Unit(benchmark::kMillisecond)
        ->Iterations(3);
    benchmark::RegisterBenchmark(("Lod/OsdmraLinearLevels/triangles:" + std::to_string(t)).c_str(),
                                 bmOsdmraLodLevels, Scheme::Linear, t)
        ->Unit(benchmark::kMillisecond)
        ->Iterations(3);
    benchmark::RegisterBenchmark(("Lod/MeshoptSimplify/triangles:" + std::to_string(t)).c_str(),
                                 bmMeshopt, t)
        ->Unit(benchmark::kMillisecond)
        ->Iterations(3);
  }
  return bench::runBenchmarks(argc, argv);
}
