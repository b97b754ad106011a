#include <gtest/gtest.h>

#include "osdmra/hierarchy.h"
using namespace osdmra;
TEST(Hierarchy, OctahedronCounts) {
  Faces F(8, 3);
  F << 0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5;
  Hierarchy h(F, 6, 3);
  EXPECT_EQ(h.numVertices(3), 4 * 4 * 4 * 8 / 2 + 2);
  const auto& P = h.refinement(Scheme::Loop, 2);
  for (int r = 0; r < P.rows(); ++r) EXPECT_NEAR(P.row(r).sum(), 1.0, 1e-15);
}
