// The clean-up (cleanup.h), the remesher's safety net: given a resampled surface with a
// fold made on purpose (a grid point dragged across its neighbour), it repairs it and
// says how much it moved; given a clean one, it moves nothing.
#include <gtest/gtest.h>

#include "osdmra/mesh/connectivity.h"
#include "osdmra/remesh/cleanup.h"
#include "osdmra/remesh/features.h"
#include "osdmra/remesh/resample.h"
#include "osdmra/remesh/simplify.h"
#include "osdmra/subdivision/shapes.h"

using namespace osdmra;
using namespace osdmra::remeshing;

namespace {

struct Sampled {
  TriMesh input;
  Features features;
  Simplification s;
  Resampled grid;
};

Sampled sampledSphere() {
  Sampled x;
  x.input = subdivide(shapes::icosahedron(), 3, Scheme::Loop);
  x.features = detectFeatures(x.input, 70.0);
  x.s = simplify(x.input, x.features, 60);
  const SurfaceWalker walker(x.input, x.features.list);
  x.grid = resample(x.input, walker.connectivity(), x.features.list, x.s, BaseCharts(x.s.base), 3);
  return x;
}

// The remeshed surface as resampling leaves it, before the clean-up.
Remeshing resampled(const Sampled& x) {
  Remeshing out;
  out.base = x.s.base;
  out.mesh = x.grid.mesh;
  return out;
}

}  // namespace

TEST(Cleanup, MovesNothingOnACleanSampling) {
  Sampled x = sampledSphere();
  const SurfaceWalker walker(x.input, x.features.list);
  Remeshing out = resampled(x);
  cleanUp(out, x.input, x.grid.free, x.grid.line, x.grid.where, walker);
  EXPECT_EQ(out.cleanupDefectsBefore, 0);
  EXPECT_EQ(out.cleanupMovedPoints, 0);
  EXPECT_EQ(out.mesh.V, x.grid.mesh.V);
}

TEST(Cleanup, RepairsAFoldAndSaysSo) {
  Sampled x = sampledSphere();
  const SurfaceWalker walker(x.input, x.features.list);
  Remeshing out = resampled(x);
  // A free grid point dragged across one of its neighbours, half an edge beyond it.
  const VertexRings rings(out.mesh.F, static_cast<int>(out.mesh.V.rows()));
  int v = static_cast<int>(out.base.V.rows());
  while (!x.grid.free[v]) ++v;
  const int w = rings.ring(v)[0];
  out.mesh.V.row(v) = out.mesh.V.row(w) + 0.5 * (out.mesh.V.row(w) - out.mesh.V.row(v));
  x.grid.where[v] = x.grid.where[w];
  cleanUp(out, x.input, x.grid.free, x.grid.line, x.grid.where, walker);
  EXPECT_GT(out.cleanupDefectsBefore, 0);
  EXPECT_GT(out.cleanupMovedPoints, 0);
  EXPECT_EQ(out.flippedTriangles, 0);
  EXPECT_EQ(out.degenerateTriangles, 0);
  EXPECT_EQ(out.selfIntersections, 0);
}
