// The remesher on the public scans, beside its peer: meshoptimizer simplifying the same
// input to the same base size (a coarse mesh only: no parameterisation, no remeshed
// surface). Time per 100,000 input faces is the figure of issue 13 (at most 5 s at
// J = 5 over 300 base faces). Results in docs/BENCHMARKS.md.
//
//   osdmra_remesh_bench [google benchmark flags]   (scans: $OSDMRA_SCANS, default
//   ../shared/data/scans; every .obj, .off and .ply, read and repaired as `osdmra
//   remesh` does: readRemeshInput())
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "meshopt_peer.h"
#include "osdmra/base/error.h"
#include "osdmra/mesh/mesh.h"
#include "osdmra/pipeline.h"
#include "osdmra/remesh/remesh.h"
#include "run_benchmarks.h"

using namespace osdmra;

namespace {

constexpr int kBaseFaces = 300, kLevels = 5;

void bmRemesh(benchmark::State& state, const TriMesh& m, bool baseCheck) {
  RemeshOptions o;
  o.baseFaces = kBaseFaces;
  o.levels = kLevels;
  o.baseWithoutNewCrossings = baseCheck;
  Remeshing r;
  for (auto _ : state) {
    r = remesh(m, o);
    benchmark::DoNotOptimize(r);
  }
  state.counters["input_faces"] = static_cast<double>(m.F.rows());
  state.counters["base_faces"] = static_cast<double>(r.base.F.rows());
}

}  // namespace

int main(int argc, char** argv) {
  const char* env = std::getenv("OSDMRA_SCANS");
  const std::filesystem::path dir = env ? env : "../shared/data/scans";
  static std::vector<std::pair<std::string, TriMesh>> meshes;
  std::vector<std::filesystem::path> files;
  if (std::filesystem::is_directory(dir))
    for (const auto& e : std::filesystem::directory_iterator(dir)) files.push_back(e.path());
  std::sort(files.begin(), files.end());
  for (const auto& path : files) {
    const std::string ext = path.extension().string();
    if (ext != ".obj" && ext != ".off" && ext != ".ply") continue;
    try {  // what `osdmra remesh` remeshes: polygons as triangles, the input repaired
      meshes.emplace_back(path.stem().string(), readRemeshInput(path.string()));
    } catch (const Error&) {  // not a mesh the remesher takes
    }
  }
  for (const auto& [name, mesh] : meshes) {
    const TriMesh* m = &mesh;
    benchmark::RegisterBenchmark(("Remesh/" + name).c_str(),
                                 [m](benchmark::State& s) { bmRemesh(s, *m, true); })
        ->Unit(benchmark::kMillisecond)
        ->MeasureProcessCPUTime()
        ->UseRealTime()
        ->Iterations(1);
    // The default's cost over the base check (RemeshOptions::baseWithoutNewCrossings).
    benchmark::RegisterBenchmark(("RemeshWithoutBaseCheck/" + name).c_str(),
                                 [m](benchmark::State& s) { bmRemesh(s, *m, false); })
        ->Unit(benchmark::kMillisecond)
        ->MeasureProcessCPUTime()
        ->UseRealTime()
        ->Iterations(1);
    benchmark::RegisterBenchmark(
        ("MeshoptSimplifyToBase/" + name).c_str(),
        [m](benchmark::State& s) { bench::bmMeshoptToFaces(s, *m, kBaseFaces); })
        ->Unit(benchmark::kMillisecond)
        ->Iterations(3);
  }
  return bench::runBenchmarks(argc, argv);
}
