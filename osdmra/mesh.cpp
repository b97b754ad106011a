#include "osdmra/mesh.h"
namespace osdmra {
double boundingBoxDiagonal(const Points& V) {
  if (V.rows() == 0) return 0.0;
  return (V.colwise().maxCoeff() - V.colwise().minCoeff()).norm();
}
void validate(const TriMesh&, const std::string&) {}
}  // namespace osdmra
