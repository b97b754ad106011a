// Inner products of scaling functions: the Gram matrices I^j (math.md section 2).
//
// <f,g> = sum over base triangles T of (1/Area(T)) integral_T f g  (paper, 3.2),
// so every base triangle counts as area 1 and I^j depends on topology only.
// I^j = 4^-j * sum over triangles of M^j of their element matrices (element_gram.h).
#pragma once

#include <utility>
#include <vector>

#include "osdmra/mra/element_gram.h"
#include "osdmra/subdivision/hierarchy.h"

namespace osdmra {

/// I^j over the whole of M^j = `conn` at level `level` (n_j x n_j, symmetric).
SparseMatrix gram(const Connectivity& conn, int level, ElementGram& elements);

/// Local access to I^j without assembling it: what the wavelet construction needs
/// around one edge. Keeps scratch space sized to the mesh.
class LocalGram {
 public:
  LocalGram(const Connectivity& conn, int level, ElementGram& elements);

  /// I^j[S, S] as a dense |S| x |S| matrix.
  Eigen::MatrixXd block(const std::vector<int>& S);
  /// x^T I^j[S, S] x for x indexed like S: block(S) without forming it (S may be a
  /// few hundred vertices, the block then a megabyte that is used once).
  double quadraticForm(const std::vector<int>& S, const Eigen::VectorXd& x);
  /// Column k of I^j as (row, value) pairs, rows ascending.
  std::vector<std::pair<int, double>> column(int k);

 private:
  // Faces whose control sets meet `vertices` (each face once).
  void facesNear(const std::vector<int>& vertices);
  // The element of face f, looked up once: overlapping blocks and columns meet the
  // same faces again and again, and a lookup encodes the face's fans three times.
  const ElementGram::Element& element(int f);
  const Connectivity& conn_;
  double scale_;
  ElementGram& elements_;
  std::vector<int> mark_, faceMark_, faces_, touched_;
  std::vector<std::pair<int, int>> hits_;        // (position in element, position in S)
  std::vector<ElementGram::Element> elementOf_;  // matrix == nullptr: not looked up yet
  int stamp_ = 0;
};

}  // namespace osdmra
