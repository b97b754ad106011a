// osdmra_profile: runs one osdmra operation on the displaced octahedron of level J a
// few times, for a profiler. The setup (inputs, and a fresh Hierarchy before every
// precompute) is kept out of the profile through perf's control FIFO:
//
//   mkfifo /tmp/ctl
//   PERF_CTL_FIFO=/tmp/ctl perf record -g -D -1 --control=fifo:/tmp/ctl -o OUT.data
//       -- build-bench/bench/osdmra_profile analyze 9 loop quasi 1 5   (one line)
//
// usage: osdmra_profile hierarchy|precompute|analyze|synthesize|budget|levels J
//                       [loop|linear] [lazy|quasi|fixed] [rings] [repetitions] [triangles]
// Prints the wall time of every repetition. Without PERF_CTL_FIFO it only times.
// `budget` re-extracts a level of detail of `triangles` (default a quarter of the
// finest level's faces) with the library's default approximation options, the
// approximator and its triangle counts made once outside the profile.
// `levels` breaks a Loop analysis down by level instead: the time of the P_old solve
// (solveOldBlock) and of the whole analysisStep, the fastest over the repetitions,
// and the BiCGSTAB iteration count per coordinate with solveOldBlock's settings.
#include <Eigen/IterativeLinearSolvers>
#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "osdmra/base/error.h"
#include "osdmra/mra/approximation.h"
#include "osdmra/mra/filter_bank.h"
#include "osdmra/subdivision/shapes.h"

namespace {

using namespace osdmra;

// Enables or disables perf's counters through its control FIFO, if there is one.
class PerfControl {
 public:
  PerfControl() {
    if (const char* path = std::getenv("PERF_CTL_FIFO")) fifo_ = std::fopen(path, "w");
  }
  ~PerfControl() {
    if (fifo_) std::fclose(fifo_);
  }
  void enable() { send("enable\n"); }
  void disable() { send("disable\n"); }

 private:
  void send(const char* command) {
    if (!fifo_) return;
    std::fputs(command, fifo_);
    std::fflush(fifo_);
  }
  std::FILE* fifo_ = nullptr;
};

double msSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

int levels(const TriMesh& base, int J, Scheme scheme, const WaveletOptions& w, int reps) {
  if (scheme != Scheme::Loop) throw Error("levels: only Loop analysis has a P_old solve");
  const Hierarchy h(base.F, static_cast<int>(base.V.rows()), J);
  const Points V = subdivide(base, J, scheme, 0.02, 3).V;
  const FilterBank bank = makeFilterBank(h, scheme, w);
  std::vector<double> solveMs(J, 1e300), stepMs(J, 1e300);
  std::vector<std::array<long, 3>> iterations(J);
  for (int rep = 0; rep < reps; ++rep) {
    Points c = V;
    for (int j = J - 1; j >= 0; --j) {
      const int n = h.numVertices(j);
      const SparseMatrix Pold = h.refinement(scheme, j).topRows(n);
      const Points rhs = c.topRows(n);
      auto t0 = std::chrono::steady_clock::now();
      const Points u = solveOldBlock(Pold, j, rhs);
      solveMs[j] = std::min(solveMs[j], msSince(t0));
      if (rep == 0) {  // the settings of solveOldBlock (filter_bank.cpp)
        Eigen::BiCGSTAB<SparseMatrix, Eigen::DiagonalPreconditioner<double>> solver;
        solver.setTolerance(1e-15);
        solver.setMaxIterations(500);
        solver.compute(Pold);
        for (int k = 0; k < 3; ++k) {
          const Eigen::VectorXd b = rhs.col(k);
          const Eigen::VectorXd x = solver.solve(b);
          iterations[j][k] = static_cast<long>(solver.iterations());
        }
      }
      Points coarse, detail;
      t0 = std::chrono::steady_clock::now();
      analysisStep(bank, j, c, coarse, detail);
      stepMs[j] = std::min(stepMs[j], msSince(t0));
      c = std::move(coarse);
    }
  }
  std::printf(
      "level  n_j        solveOldBlock ms  ns/row/iteration  analysisStep ms  BiCGSTAB iterations "
      "(x, y, z)\n");
  for (int j = J - 1; j >= 0; --j) {
    const long its = iterations[j][0] + iterations[j][1] + iterations[j][2];
    std::printf("%5d  %-9d  %16.2f  %16.1f  %15.2f  %ld, %ld, %ld\n", j, h.numVertices(j),
                solveMs[j], its > 0 ? solveMs[j] * 1e6 / (double(h.numVertices(j)) * its) : 0.0,
                stepMs[j], iterations[j][0], iterations[j][1], iterations[j][2]);
  }
  return 0;
}

int run(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr,
                 "usage: osdmra_profile hierarchy|precompute|analyze|synthesize|budget|levels J "
                 "[loop|linear] [lazy|quasi|fixed] [rings] [repetitions] [triangles]\n");
    return 2;
  }
  const std::string op = argv[1];
  const int J = std::atoi(argv[2]);
  const Scheme scheme = parseScheme(argc > 3 ? argv[3] : "loop");
  WaveletOptions w;
  w.kind = parseWaveletKind(argc > 4 ? argv[4] : "quasi");
  w.rings = argc > 5 ? std::atoi(argv[5]) : 1;
  if (w.kind != WaveletKind::Quasi) w.rings = 0;
  const int reps = argc > 6 ? std::atoi(argv[6]) : 3;

  const TriMesh base = shapes::octahedron();
  const int n0 = static_cast<int>(base.V.rows());
  PerfControl perf;
  using Clock = std::chrono::steady_clock;
  auto report = [&](int rep, Clock::time_point t0) {
    std::printf("%s J=%d rep %d: %.1f ms\n", op.c_str(), J, rep,
                std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
  };

  if (op == "hierarchy" || op == "precompute") {
    for (int rep = 0; rep < reps; ++rep) {
      std::unique_ptr<Hierarchy> h;
      if (op == "precompute") h = std::make_unique<Hierarchy>(base.F, n0, J);
      const auto t0 = Clock::now();
      perf.enable();
      if (op == "hierarchy") {
        h = std::make_unique<Hierarchy>(base.F, n0, J);
      } else {
        const FilterBank bank = makeFilterBank(*h, scheme, w);
        perf.disable();
        report(rep, t0);
        continue;
      }
      perf.disable();
      report(rep, t0);
    }
    return 0;
  }
  if (op == "levels") return levels(base, J, scheme, w, reps);
  if (op != "analyze" && op != "synthesize" && op != "budget")
    throw Error("unknown operation '" + op + "'");
  const Hierarchy h(base.F, n0, J);
  const Points V = subdivide(base, J, scheme, 0.02, 3).V;
  for (int j = 0; j < J; ++j) h.refinement(scheme, j);
  const FilterBank bank = makeFilterBank(h, scheme, w);
  const Decomposition d = analyze(bank, V);
  if (op == "budget") {
    const long long triangles = argc > 7 ? std::atoll(argv[7]) : h.numFaces(J) / 4;
    const Approximator approx(bank, d);
    approx.triangleCounts();
    for (int rep = 0; rep < reps; ++rep) {
      const auto t0 = Clock::now();
      perf.enable();
      const Approximation a = approx.budget(triangles);
      perf.disable();
      report(rep, t0);
      if (rep == 0) std::printf("%d triangles\n", a.triangles());
    }
    return 0;
  }
  for (int rep = 0; rep < reps; ++rep) {
    const auto t0 = Clock::now();
    perf.enable();
    if (op == "analyze") {
      const Decomposition e = analyze(bank, V);
      perf.disable();
    } else {
      const Points c = synthesize(bank, d, J);
      perf.disable();
    }
    report(rep, t0);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "osdmra_profile: %s\n", e.what());
    return 1;
  }
}
