// Uses the installed osdmra: refines an octahedron twice and checks the sizes and
// the refinement matrices (which come from OpenSubdiv, so its linkage is exercised),
// then takes a surface through the top layer, pipeline.h, whose header includes
// every layer's (so each must be installed and need no detail/ header).
#include <osdmra/base/error.h>
#include <osdmra/pipeline.h>
#include <osdmra/subdivision/hierarchy.h>
#include <osdmra/subdivision/shapes.h>

#include <cmath>
#include <cstdio>

int main() {
  try {
    osdmra::Faces F(8, 3);
    F << 0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5;
    const osdmra::Hierarchy h(F, 6, 2);
    const int vertices[] = {6, 18, 66};
    const int faces[] = {8, 32, 128};
    for (int j = 0; j <= 2; ++j)
      if (h.numVertices(j) != vertices[j] || h.numFaces(j) != faces[j]) {
        std::fprintf(stderr, "level %d: %d vertices, %d faces; expected %d, %d\n", j,
                     h.numVertices(j), h.numFaces(j), vertices[j], faces[j]);
        return 1;
      }
    const osdmra::SparseMatrix& P = h.refinement(osdmra::Scheme::Loop, 1);
    if (P.rows() != 66 || P.cols() != 18) {
      std::fprintf(stderr, "P^2 is %ldx%ld, expected 66x18\n", static_cast<long>(P.rows()),
                   static_cast<long>(P.cols()));
      return 1;
    }
    for (int r = 0; r < P.rows(); ++r)
      if (std::abs(P.row(r).sum() - 1.0) > 1e-12) {
        std::fprintf(stderr, "row %d of P^2 sums to %g, expected 1\n", r, P.row(r).sum());
        return 1;
      }
    // Analysis and synthesis give the surface back.
    const osdmra::TriMesh surface =
        osdmra::subdivide(osdmra::shapes::octahedron(), 2, osdmra::Scheme::Loop, 0.05);
    const osdmra::AnalysedSurface analysed(surface);
    const osdmra::TriMesh back = analysed.reconstruct(analysed.decomposition(), 2);
    const double error = (back.V - surface.V).cwiseAbs().maxCoeff();
    if (analysed.levels() != 2 || !(error < 1e-12 * osdmra::boundingBoxDiagonal(surface.V))) {
      std::fprintf(stderr, "pipeline: %d levels, reconstruction error %g\n", analysed.levels(),
                   error);
      return 1;
    }
  } catch (const osdmra::Error& e) {
    std::fprintf(stderr, "osdmra::Error: %s\n", e.what());
    return 1;
  }
  std::puts("consumer: ok");
  return 0;
}
