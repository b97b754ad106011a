// meshoptimizer's simplifier as the peer of the remeshing benchmarks: the same input
// simplified to the same base size (a coarse mesh only, no parameterisation and no
// remeshed surface).
#pragma once

#include <benchmark/benchmark.h>
#include <meshoptimizer.h>

#include <vector>

#include "osdmra/mesh/mesh.h"

namespace osdmra::bench {

inline void bmMeshoptToFaces(benchmark::State& state, const TriMesh& m, int faces) {
  std::vector<float> positions;
  std::vector<unsigned> indices, out(3 * m.F.rows());
  for (Eigen::Index i = 0; i < m.V.rows(); ++i)
    for (int k = 0; k < 3; ++k) positions.push_back(static_cast<float>(m.V(i, k)));
  for (Eigen::Index f = 0; f < m.F.rows(); ++f)
    for (int k = 0; k < 3; ++k) indices.push_back(static_cast<unsigned>(m.F(f, k)));
  std::size_t count = 0;
  for (auto _ : state) {
    float error = 0;
    count = meshopt_simplify(out.data(), indices.data(), indices.size(), positions.data(),
                             positions.size() / 3, 3 * sizeof(float), 3 * faces, 1.0f, 0, &error);
    benchmark::DoNotOptimize(out.data());
  }
  state.counters["faces"] = static_cast<double>(count / 3);
}

}  // namespace osdmra::bench
