// osdmra_bench: osdmra's layers against OpenSubdiv on displaced octahedra, J = 5..9.
//
// A layer benchmark: each stage below the pipeline (hierarchy, connectivity, the
// filter bank's precomputation, analysis, synthesis) is timed alone, beside
// OpenSubdiv's own stages, so it builds them itself. The pipeline as the front ends
// use it (osdmra/pipeline.h) is timed in lod_bench.cpp.
//
// Inputs: osdmra::subdivide(shapes::octahedron(), J, scheme, 0.02, seed 3), built
// once per (J, scheme) and kept in static storage; nothing of the setup is timed.
// Benchmarks run grouped by J and the caches only hold the current J, so memory
// stays at one level's worth.
//
//   Hierarchy/J:j                  osdmra::Hierarchy construction (as of this writing: an
//                                  unrefined refiner for the base's edges, then osdmra's
//                                  own split of every level's faces and edges; the P^j
//                                  and Connectivity are built lazily); destruction untimed
//   Refinement/<scheme>/J:j        Hierarchy::prepareRefinement() of a fresh hierarchy of
//                                  that scheme only (built untimed): its P^j, j < J (Loop
//                                  written from the split topology, as OpenSubdiv's masks
//                                  give them; OsdInterpolate is the baseline)
//   Connectivity/J:j               Hierarchy::connectivity(j) for j = 0..J on a fresh
//                                  hierarchy (built untimed): the lazily built adjacency
//   OsdRefine/J:j                  Far::TopologyRefinerFactory::Create + RefineUniform(J),
//                                  Loop, VTX_BOUNDARY_EDGE_ONLY, default UniformOptions
//   OsdRefineFull/J:j              the same with fullTopologyInLastLevel = true
//   OsdInterpolate/J:j             PrimvarRefinerReal<double>::Interpolate of xyz, levels 1..J
//   Precompute/<scheme>/<w>/J:j    makeFilterBank on a fresh Hierarchy, built untimed: a
//                                  Hierarchy caches what it builds on first use (P^j in
//                                  earlier versions, Connectivity now), so a reused one
//                                  would hide that cost
//   Analyze/<scheme>/<w>/J:j       analyze(bank, V) on a warmed-up hierarchy and bank
//   Synthesize/<scheme>/<w>/J:j    synthesize(bank, d, J), likewise
//
// Times are CPU time of the process (Google Benchmark's default; rates use it too),
// so time-slicing by other load on the machine does not count. Counters per run:
// J, vertices (n_J), time_per_vertex (seconds / n_J), items_per_second (vertices / s).
// Select with --benchmark_filter=REGEX, e.g. 'Analyze/loop/quasi_r1' or 'J:9$'.
#include <benchmark/benchmark.h>
#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "osdmra/mra/filter_bank.h"
#include "osdmra/subdivision/hierarchy.h"
#include "osdmra/subdivision/shapes.h"

namespace {

namespace Far = OpenSubdiv::Far;
namespace Sdc = OpenSubdiv::Sdc;
using namespace osdmra;

constexpr int kMinLevel = 5, kMaxLevel = 9;
constexpr double kDisplace = 0.02;
constexpr std::uint64_t kSeed = 3;
// Default --benchmark_min_time (seconds; at least one iteration always runs). Set
// as a flag default rather than with MinTime(), which would add it to every name.
constexpr const char* kMinTimeFlag = "--benchmark_min_time=0.2";

const TriMesh& baseMesh() {
  static const TriMesh base = shapes::octahedron();
  return base;
}

// ---- OpenSubdiv baseline -------------------------------------------------------

Far::TopologyRefiner* createOsdRefiner() {
  const TriMesh& base = baseMesh();
  static const std::vector<int> vertsPerFace(static_cast<std::size_t>(base.F.rows()), 3);
  Far::TopologyDescriptor desc;
  desc.numVertices = static_cast<int>(base.V.rows());
  desc.numFaces = static_cast<int>(base.F.rows());
  desc.numVertsPerFace = vertsPerFace.data();
  desc.vertIndicesPerFace = base.F.data();
  Sdc::Options options;
  options.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_EDGE_ONLY);
  using Factory = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;
  return Factory::Create(desc, Factory::Options(Sdc::SCHEME_LOOP, options));
}

// The primvar Far interpolates: one xyz position.
struct Xyz {
  double x, y, z;
  void Clear() { x = y = z = 0.0; }
  void AddWithWeight(const Xyz& s, double w) {
    x += w * s.x;
    y += w * s.y;
    z += w * s.z;
  }
};

// ---- Per-J caches ----------------------------------------------------------------

struct BankKey {
  int J = -1;
  Scheme scheme = Scheme::Loop;
  WaveletKind kind = WaveletKind::Lazy;
  int rings = 0;
  bool operator==(const BankKey& o) const {
    return J == o.J && scheme == o.scheme && kind == o.kind && rings == o.rings;
  }
};

struct Cache {
  int J = -1;
  std::unique_ptr<Hierarchy> hierarchy;
  std::optional<TriMesh> surface[2];  // by scheme: displaced octahedron at level J
  std::unique_ptr<Far::TopologyRefiner> osdRefiner;
  std::vector<Xyz> osdPoints;  // every level's xyz, level 0 first
  // One filter bank at a time (benchmarks are registered grouped by configuration).
  BankKey bankKey;
  std::optional<FilterBank> bank;
  std::optional<Decomposition> decomposition;
};

Cache& cache() {
  static Cache c;
  return c;
}

Cache& cacheFor(int J) {
  Cache& c = cache();
  if (c.J != J) {
    c = Cache();
    c.J = J;
  }
  return c;
}

int schemeIndex(Scheme s) {
  return s == Scheme::Loop ? 0 : 1;
}

const Hierarchy& hierarchy(int J) {
  Cache& c = cacheFor(J);
  if (!c.hierarchy)
    c.hierarchy =
        std::make_unique<Hierarchy>(baseMesh().F, static_cast<int>(baseMesh().V.rows()), J);
  return *c.hierarchy;
}

const TriMesh& surface(int J, Scheme scheme) {
  Cache& c = cacheFor(J);
  auto& s = c.surface[schemeIndex(scheme)];
  if (!s) s = subdivide(baseMesh(), J, scheme, kDisplace, kSeed);
  return *s;
}

// Filter bank and decomposition of the level-J surface. One analysis is run here, so
// whatever the hierarchy builds on first use (P^j in earlier versions) is cached
// before Analyze/Synthesize are timed.
const FilterBank& bank(const BankKey& key) {
  Cache& c = cacheFor(key.J);
  if (!c.bank || !(c.bankKey == key)) {
    c.decomposition.reset();
    c.bank.reset();
    const Hierarchy& h = hierarchy(key.J);
    WaveletOptions w;
    w.kind = key.kind;
    w.rings = key.rings;
    c.bank = makeFilterBank(h, key.scheme, w);
    c.decomposition = analyze(*c.bank, surface(key.J, key.scheme).V);
    c.bankKey = key;
  }
  return *c.bank;
}

const Decomposition& decomposition(const BankKey& key) {
  bank(key);
  return *cache().decomposition;
}

Far::TopologyRefiner& osdRefiner(int J) {
  Cache& c = cacheFor(J);
  if (!c.osdRefiner) {
    c.osdRefiner.reset(createOsdRefiner());
    c.osdRefiner->RefineUniform(Far::TopologyRefiner::UniformOptions(J));
    c.osdPoints.resize(static_cast<std::size_t>(c.osdRefiner->GetNumVerticesTotal()));
    const Points& V = baseMesh().V;
    for (Eigen::Index v = 0; v < V.rows(); ++v)
      c.osdPoints[static_cast<std::size_t>(v)] = Xyz{V(v, 0), V(v, 1), V(v, 2)};
  }
  return *c.osdRefiner;
}

// ---- Counters ----------------------------------------------------------------------

void report(benchmark::State& state, int J) {
  const double n = hierarchy(J).numVertices(J);
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * n));
  state.counters["J"] = J;
  state.counters["vertices"] = n;
  // (n per iteration) / time, inverted: seconds per finest-level vertex (the console
  // prints it with an SI prefix, e.g. 35.2ns; JSON holds seconds).
  state.counters["time_per_vertex"] = benchmark::Counter(
      n, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

// ---- Benchmarks ----------------------------------------------------------------------

void bmHierarchy(benchmark::State& state, int J) {
  const TriMesh& base = baseMesh();
  for (auto _ : state) {
    auto h = std::make_unique<Hierarchy>(base.F, static_cast<int>(base.V.rows()), J);
    benchmark::DoNotOptimize(h.get());
    state.PauseTiming();
    h.reset();
    state.ResumeTiming();
  }
  report(state, J);
}

void bmOsdRefine(benchmark::State& state, int J, bool fullTopology) {
  for (auto _ : state) {
    std::unique_ptr<Far::TopologyRefiner> r(createOsdRefiner());
    Far::TopologyRefiner::UniformOptions uniform(J);
    uniform.fullTopologyInLastLevel = fullTopology;
    r->RefineUniform(uniform);
    benchmark::DoNotOptimize(r.get());
    state.PauseTiming();
    r.reset();
    state.ResumeTiming();
  }
  report(state, J);
}

void bmOsdInterpolate(benchmark::State& state, int J) {
  const Far::TopologyRefiner& r = osdRefiner(J);
  std::vector<Xyz>& points = cache().osdPoints;
  const Far::PrimvarRefinerReal<double> primvar(r);
  for (auto _ : state) {
    Xyz* src = points.data();
    for (int level = 1; level <= J; ++level) {
      Xyz* dst = src + r.GetLevel(level - 1).GetNumVertices();
      primvar.Interpolate(level, src, dst);
      src = dst;
    }
    benchmark::DoNotOptimize(points.data());
    benchmark::ClobberMemory();
  }
  report(state, J);
}

void bmRefinement(benchmark::State& state, int J, Scheme scheme) {
  const TriMesh& base = baseMesh();
  for (auto _ : state) {
    state.PauseTiming();
    auto h = std::make_unique<Hierarchy>(base.F, static_cast<int>(base.V.rows()), J, scheme);
    state.ResumeTiming();
    h->prepareRefinement();
    benchmark::DoNotOptimize(&h->refinement(scheme, J - 1));
    state.PauseTiming();
    h.reset();
    state.ResumeTiming();
  }
  report(state, J);
}

void bmConnectivity(benchmark::State& state, int J) {
  const TriMesh& base = baseMesh();
  for (auto _ : state) {
    state.PauseTiming();
    auto h = std::make_unique<Hierarchy>(base.F, static_cast<int>(base.V.rows()), J);
    state.ResumeTiming();
    for (int j = 0; j <= J; ++j) benchmark::DoNotOptimize(&h->connectivity(j));
    state.PauseTiming();
    h.reset();
    state.ResumeTiming();
  }
  report(state, J);
}

void bmPrecompute(benchmark::State& state, BankKey key) {
  const TriMesh& base = baseMesh();
  WaveletOptions w;
  w.kind = key.kind;
  w.rings = key.rings;
  for (auto _ : state) {
    state.PauseTiming();
    auto h = std::make_unique<Hierarchy>(base.F, static_cast<int>(base.V.rows()), key.J);
    state.ResumeTiming();
    std::optional<FilterBank> b = makeFilterBank(*h, key.scheme, w);
    benchmark::DoNotOptimize(b->alpha.data());
    state.PauseTiming();
    b.reset();
    h.reset();
    state.ResumeTiming();
  }
  report(state, key.J);
}

void bmAnalyze(benchmark::State& state, BankKey key) {
  const FilterBank& b = bank(key);
  const Points& V = surface(key.J, key.scheme).V;
  for (auto _ : state) {
    Decomposition d = analyze(b, V);
    benchmark::DoNotOptimize(d.base.data());
  }
  report(state, key.J);
}

void bmSynthesize(benchmark::State& state, BankKey key) {
  const FilterBank& b = bank(key);
  const Decomposition& d = decomposition(key);
  for (auto _ : state) {
    Points c = synthesize(b, d, key.J);
    benchmark::DoNotOptimize(c.data());
  }
  report(state, key.J);
}

std::string waveletName(WaveletKind kind, int rings) {
  if (kind == WaveletKind::Lazy) return "lazy";
  return std::string(waveletKindName(kind)) + "_r" + std::to_string(rings);
}

template <class Fn>
void add(const std::string& name, Fn&& fn) {
  benchmark::RegisterBenchmark(name.c_str(), std::forward<Fn>(fn))->Unit(benchmark::kMillisecond);
}

void registerAll() {
  struct W {
    WaveletKind kind;
    int rings;
  };
  const W wavelets[] = {{WaveletKind::Lazy, 0},
                        {WaveletKind::Quasi, 0},
                        {WaveletKind::Quasi, 1},
                        {WaveletKind::Quasi, 2}};
  for (int J = kMinLevel; J <= kMaxLevel; ++J) {
    const std::string level = "/J:" + std::to_string(J);
    add("Hierarchy" + level, [J](benchmark::State& s) { bmHierarchy(s, J); });
    add("Connectivity" + level, [J](benchmark::State& s) { bmConnectivity(s, J); });
    for (Scheme scheme : {Scheme::Loop, Scheme::Linear})
      add(std::string("Refinement/") + schemeName(scheme) + level,
          [J, scheme](benchmark::State& s) { bmRefinement(s, J, scheme); });
    add("OsdRefine" + level, [J](benchmark::State& s) { bmOsdRefine(s, J, false); });
    add("OsdRefineFull" + level, [J](benchmark::State& s) { bmOsdRefine(s, J, true); });
    add("OsdInterpolate" + level, [J](benchmark::State& s) { bmOsdInterpolate(s, J); });
    for (Scheme scheme : {Scheme::Loop, Scheme::Linear}) {
      const std::string sn = std::string("/") + schemeName(scheme);
      for (const W& w : wavelets) {
        const BankKey key{J, scheme, w.kind, w.rings};
        const std::string config = sn + "/" + waveletName(w.kind, w.rings) + level;
        add("Precompute" + config, [key](benchmark::State& s) { bmPrecompute(s, key); });
        add("Analyze" + config, [key](benchmark::State& s) { bmAnalyze(s, key); });
        add("Synthesize" + config, [key](benchmark::State& s) { bmSynthesize(s, key); });
      }
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  // Our defaults first, so that the same flag on the command line overrides them.
  std::vector<char*> args{argv[0], const_cast<char*>(kMinTimeFlag)};
  for (int i = 1; i < argc; ++i) args.push_back(argv[i]);
  int n = static_cast<int>(args.size());
  args.push_back(nullptr);
  benchmark::Initialize(&n, args.data());
  if (benchmark::ReportUnrecognizedArguments(n, args.data())) return 1;
  benchmark::AddCustomContext("osdmra_input", "subdivide(octahedron, J, scheme, 0.02, seed 3)");
  registerAll();
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
