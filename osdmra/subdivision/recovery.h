// Recovery of subdivision connectivity from a triangle mesh in any order.
//
// Real semi-regular meshes arrive with vertices and faces in arbitrary order. From
// connectivity alone (positions are never trusted) this finds the largest J such
// that the mesh is J rounds of 1-to-4 splitting of some base mesh M^0, the base
// mesh, and where every input vertex sits in osdmra's canonical hierarchy.
//
// One round is peeled at a time, in linear time. A new (midpoint) vertex is regular
// (6 neighbours inside, 4 on a boundary) with its two parents opposite each other in
// its ring, and every neighbour of an old vertex is new. So one vertex known to be
// old determines the labels of its whole component by a breadth-first walk:
// extraordinary vertices are always old; a component without any (a torus) has
// several valid choices, and we try the first vertex and then its neighbours in
// ring order, taking the first that works (so the base is chosen consistently).
// The coarse faces come from the centre faces (three new vertices), and the round
// is accepted only if splitting the coarse mesh reproduces every input face exactly.
#pragma once

#include <string>
#include <vector>

#include "osdmra/subdivision/hierarchy.h"
#include "osdmra/mesh/mesh.h"

namespace osdmra {

struct Recovery {
  /// Rounds of 1-to-4 splitting found (0: no subdivision connectivity).
  int levels = 0;
  /// The base mesh M^levels-down: vertices numbered 0..numBaseVertices-1.
  Faces baseFaces;
  int numBaseVertices = 0;
  /// Why the next round could not be peeled (empty if the base is a single round
  /// away from failing for counting reasons only).
  std::string stopReason;
  /// True when some component had no extraordinary vertex, so that its base mesh
  /// was one of several valid choices (the first that works, see above).
  bool arbitraryChoice = false;

  /// One peeled round, finest first: for each vertex of that round's fine mesh, its
  /// index in the coarse mesh when it is old, or -1; and for new vertices the coarse
  /// indices of its parents.
  struct Round {
    std::vector<int> coarseOf;
    std::vector<std::array<int, 2>> parents;
  };
  std::vector<Round> rounds;
};

/// Peels rounds of 1-to-4 splitting off a valid (manifold, oriented) mesh, at most
/// `maxLevels` of them.
Recovery recoverSubdivision(const Faces& F, int numVertices, int maxLevels = 15);

/// For each input vertex, its index in level `r.levels` of `h`, the hierarchy built
/// over r.baseFaces with r.levels levels.
std::vector<int> canonicalIndices(const Recovery& r, const Hierarchy& h);

/// A mesh with subdivision connectivity, brought to osdmra's canonical form.
struct CanonicalSurface {
  Recovery recovery;
  Hierarchy hierarchy;  ///< over recovery.baseFaces, recovery.levels levels
  Points V;             ///< the input's positions in canonical order
  /// Input vertex of each canonical vertex, and the input's faces; both empty when
  /// the input was already canonical.
  std::vector<int> inputOrder;
  Faces inputFaces;
};

/// Recovers the structure of `mesh` (validated) and reorders it. `levels` < 0 takes
/// the largest J found; otherwise exactly that many levels are used (fewer found is
/// an Error). No subdivision connectivity at all is an Error that says why.
CanonicalSurface canonicalSurface(const TriMesh& mesh, int levels = -1);

/// One line that says what was found, e.g. "subdivision connectivity: 6 levels over a
/// base of 6 vertices and 8 faces" or "no subdivision connectivity (...)".
std::string describe(const Recovery& r);

}  // namespace osdmra
