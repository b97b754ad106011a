// Checks of a parameterisation over a base mesh shared by the simplification's and the
// base flips' tests: every input vertex has a place, and the map is a bijection.
#pragma once

#include <gtest/gtest.h>

#include <array>

#include "osdmra/remesh/distortion.h"
#include "osdmra/remesh/planar.h"
#include "osdmra/remesh/simplify.h"

namespace osdmra::test {

using remeshing::cross2;
using remeshing::layFlat;
using remeshing::minOf;
using remeshing::Param;
using remeshing::Simplification;
using remeshing::traceToInput;
using remeshing::Vec2;
using remeshing::Vec3;

// The image of input triangle t in base face f laid flat, if its corners all lie in f
// (a base vertex counts as lying in each of its faces).
inline bool imageIn(const TriMesh& input, const Simplification& s, int t,
                    std::array<Vec2, 3>& image) {
  const int f = s.params[input.F(t, 0)].face;
  const auto chart =
      layFlat(s.base.V.row(s.base.F(f, 0)).transpose(), s.base.V.row(s.base.F(f, 1)).transpose(),
              s.base.V.row(s.base.F(f, 2)).transpose());
  for (int c = 0; c < 3; ++c) {
    const int v = input.F(t, c);
    std::array<double, 3> b = s.params[v].bary;
    if (s.params[v].face != f) {
      if (s.baseOf[v] < 0) return false;
      b = {0, 0, 0};
      int k = 0;
      while (k < 3 && s.base.F(f, k) != s.baseOf[v]) ++k;
      if (k == 3) return false;
      b[k] = 1;
    }
    image[c] = b[0] * chart[0] + b[1] * chart[1] + b[2] * chart[2];
  }
  return true;
}

// Every input vertex has a place on the base (a face and barycentric coordinates), and
// every input triangle inside one base face keeps its orientation there: more than
// `inside` of them are checked.
inline void expectBijection(const TriMesh& input, const Simplification& s, int inside) {
  ASSERT_EQ(s.params.size(), static_cast<std::size_t>(input.V.rows()));
  for (const Param& p : s.params) {
    ASSERT_GE(p.face, 0);
    ASSERT_LT(p.face, s.base.F.rows());
    EXPECT_NEAR(p.bary[0] + p.bary[1] + p.bary[2], 1.0, 1e-12);
    EXPECT_GE(minOf(p.bary), 0.0);
  }
  int checked = 0;
  for (int t = 0; t < input.F.rows(); ++t) {
    std::array<Vec2, 3> image;
    if (!imageIn(input, s, t, image)) continue;
    ++checked;
    EXPECT_GT(cross2(image[1] - image[0], image[2] - image[0]), 0) << "input triangle " << t;
  }
  EXPECT_GT(checked, inside);
}

// Every removed input vertex's place on the base, traced back through the history,
// lands on that vertex: the map and its inverse compose to the identity.
inline void expectTracingBackIsTheIdentity(const TriMesh& input, const Simplification& s) {
  for (int v = 0; v < input.V.rows(); ++v) {
    if (s.baseOf[v] >= 0) continue;
    const SurfacePoint at = traceToInput(s.history, s.params[v].face, s.params[v].bary);
    ASSERT_GE(at.triangle, 0);
    ASSERT_LT(at.triangle, input.F.rows());
    Vec3 p = Vec3::Zero();
    for (int i = 0; i < 3; ++i) p += at.bary[i] * input.V.row(input.F(at.triangle, i)).transpose();
    EXPECT_LT((p - input.V.row(v).transpose()).norm(), 1e-9) << "vertex " << v;
  }
}

}  // namespace osdmra::test
