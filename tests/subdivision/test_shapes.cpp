// The built-in shapes (shapes.h): every base mesh has the topology its name promises.
#include <gtest/gtest.h>

#include <set>

#include "osdmra/mesh/connectivity.h"
#include "osdmra/subdivision/shapes.h"
#include "support.h"

using namespace osdmra;
using namespace osdmra::test;

// The test shapes have the topology their names promise.
TEST(Shapes, TopologyAsAdvertised) {
  struct Expect {
    const char* name;
    int genus, loops;
  };
  for (Expect e :
       {Expect{"tetrahedron", 0, 0}, Expect{"octahedron", 0, 0}, Expect{"icosahedron", 0, 0},
        Expect{"torus", 1, 0}, Expect{"genus2", 2, 0}, Expect{"genus3", 3, 0}, Expect{"disc", 0, 1},
        Expect{"cylinder", 0, 2}, Expect{"valences", 0, 0}}) {
    SCOPED_TRACE(e.name);
    const TriMesh m = shapes::byName(e.name);
    validate(m, e.name);
    const Topology t = topology(m);
    EXPECT_EQ(t.components, 1);
    EXPECT_EQ(t.boundaryLoops, e.loops);
    EXPECT_EQ(t.genus, e.genus);
  }
  // Valences 3 to at least 10 in one mesh.
  const TriMesh v = shapes::valences();
  const Connectivity c(v.F, static_cast<int>(v.V.rows()));
  std::set<int> seen;
  for (int i = 0; i < c.numVertices(); ++i) seen.insert(c.valence(i));
  for (int k = 3; k <= 10; ++k) EXPECT_TRUE(seen.count(k)) << "valence " << k;
}
