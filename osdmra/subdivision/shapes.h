// Shapes: base meshes of known topology and synthetic test surfaces over them.
//
// The base meshes cover what the property tests need: the Platonic triangle meshes,
// a torus, genus-2 and genus-3 surfaces, an open disc, an open cylinder, and a
// mesh whose valences run from 3 to at least 10. Surfaces are made from them by
// uniform refinement plus displacement at every level, so every frequency band
// carries detail.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "osdmra/subdivision/hierarchy.h"
#include "osdmra/mesh/mesh.h"

namespace osdmra {
namespace shapes {

TriMesh tetrahedron();
TriMesh octahedron();
TriMesh icosahedron();
/// Torus of `around` x `along` vertices (both >= 3); every vertex has valence 6.
TriMesh torus(int around = 6, int along = 4);
/// Closed surface of genus `genus` (>= 1): a slab with `genus` square holes.
TriMesh slab(int genus);
/// Open disc: a triangulated (n x n)-cell square (one boundary loop).
TriMesh disc(int cells = 3);
/// Open cylinder of `around` x `along` vertices: two boundary loops.
TriMesh cylinder(int around = 6, int along = 3);
/// Closed genus-0 mesh with vertex valences from 3 to at least 10.
TriMesh valences();

/// Every named shape above with its name ("tetrahedron", ..., "valences").
std::vector<std::pair<std::string, TriMesh>> all();
/// The shape of that name; throws Error for an unknown name.
TriMesh byName(const std::string& name);

}  // namespace shapes

/// Refines `base` `levels` times with `scheme` and, when amplitude > 0, adds to the
/// new vertices of level l+1 a pseudo-random offset of size amplitude * 2^-l times
/// the base's bounding-box diagonal (seeded, identical on every platform). The
/// result is in canonical order (hierarchy.h).
TriMesh subdivide(const TriMesh& base, int levels, Scheme scheme, double amplitude = 0.0,
                  std::uint64_t seed = 1);

}  // namespace osdmra
