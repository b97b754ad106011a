// The clean-up (cleanup.h), the remesher's safety net: given a resampled surface with a
// fold made on purpose (a grid point dragged across its neighbour), it repairs it and
// says how much it moved; given a clean one, it moves nothing.
#include <gtest/gtest.h>

#include <algorithm>

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

// The repairs say how far they are (the callback is also how remesh() abandons a clean-up
// it no longer needs: an exception from it ends the clean-up and reaches the caller).
// A rough torus over 20 base faces folds where neither the first stage nor the repairs
// mend it: the last resort runs.
TEST(Cleanup, ReportsItsRepairsAndCanBeAbandoned) {
  Sampled x;
  x.input = subdivide(shapes::torus(), 1, Scheme::Loop, 0.02, 3);
  x.features = detectFeatures(x.input, 70.0);
  x.s = simplify(x.input, x.features, 20);
  const SurfaceWalker walker(x.input, x.features.list);
  x.grid = resample(x.input, walker.connectivity(), x.features.list, x.s, BaseCharts(x.s.base), 3);

  Remeshing out = resampled(x);
  std::vector<SurfacePoint> at = x.grid.where;
  std::vector<double> reported;
  int lastResorts = 0;
  cleanUp(
      out, x.input, x.grid.free, x.grid.line, at, walker,
      [&](const char* stage, double f) {
        EXPECT_STREQ(stage, "clean-up");
        reported.push_back(f);
      },
      [&] { ++lastResorts; });
  EXPECT_EQ(lastResorts, 1);
  ASSERT_FALSE(reported.empty());
  EXPECT_TRUE(std::is_sorted(reported.begin(), reported.end()));
  EXPECT_EQ(reported.back(), 1.0);
  EXPECT_TRUE(std::any_of(reported.begin(), reported.end(), [](double f) {
    return f > 0.1 && f < 1;
  })) << "the repairs report as they go";

  struct Stop {};
  Remeshing abandoned = resampled(x);
  at = x.grid.where;
  EXPECT_THROW(cleanUp(abandoned, x.input, x.grid.free, x.grid.line, at, walker,
                       [](const char*, double f) {
                         if (f > 0.1) throw Stop{};
                       }),
               Stop);

  // A clean sampling leaves nothing for the last resort.
  const Sampled sphere = sampledSphere();
  const SurfaceWalker onSphere(sphere.input, sphere.features.list);
  Remeshing clean = resampled(sphere);
  at = sphere.grid.where;
  cleanUp(clean, sphere.input, sphere.grid.free, sphere.grid.line, at, onSphere, {},
          [&] { ++lastResorts; });
  EXPECT_EQ(lastResorts, 1);
}
