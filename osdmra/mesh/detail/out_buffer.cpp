#include "osdmra/mesh/detail/out_buffer.h"

namespace osdmra::detail {

/// The writers refuse what the readers would reject, so every file osdmra writes
/// reads back.
void checkWritable(const TriMesh& mesh) {
  const Eigen::Index nv = mesh.V.rows();
  for (Eigen::Index v = 0; v < nv; ++v)
    if (!mesh.V.row(v).allFinite())
      fail("cannot write vertex " + std::to_string(v) + ": non-finite coordinate");
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f)
    for (int i = 0; i < 3; ++i)
      if (mesh.F(f, i) < 0 || mesh.F(f, i) >= nv)
        fail("cannot write face " + std::to_string(f) + ": vertex index " +
             std::to_string(mesh.F(f, i)) + " is out of range (" + std::to_string(nv) +
             " vertices)");
}

bool writesNormals(const TriMesh& mesh, const WriteOptions& opts) {
  return opts.writeNormals && mesh.V.rows() > 0 && mesh.N.rows() == mesh.V.rows();
}

}  // namespace osdmra::detail
