// ElementGram: exact inner products of the scaling functions over one triangle.
//
// The Gram matrix I^j (paper section 3.2, math.md section 2) is a sum over the
// triangles T of M^j of element matrices E_T, where (E_T)_{pq} is the integral
// over T of phi_p phi_q divided by T's area (every level-j triangle has area 4^-j
// in the paper's normalisation, base triangles have area 1):
//
//     I^j = 4^-j * sum_T scatter(E_T, C(T))
//
// C(T), the control set, lists the vertices whose functions are non-zero on T.
// Polyhedral: T's three vertices and the P1 mass matrix. Loop: the union of the
// 1-rings of T's vertices (12 vertices for a regular triangle), and no closed form.
//
// Loop's E_T is exact all the same (the paper's equation 3, applied per triangle):
// splitting T in four gives E_T = 1/4 * sum_c A_c^T E_c A_c, where A_c holds the
// rows of P^{j+1} for the child c's control set. E_T depends only on the *fans* of
// T's three vertices (the faces around them): those determine every subdivision
// rule that ever acts on T. We encode the fan complex canonically (the "type" of
// T), discover the types reachable by refinement on tiny local meshes refined by
// OpenSubdiv, and solve the resulting finite linear system once per type: a
// homogeneous one for the regular triangle (scaled by partition of unity,
// sum_pq E_pq = 1) and Stein-like equations for the rest. Types repeat endlessly
// (every regular triangle is one type), so a mesh of any size needs a handful.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <vector>

#include "osdmra/mesh/connectivity.h"
#include "osdmra/subdivision/hierarchy.h"

namespace osdmra {

class ElementGram {
 public:
  explicit ElementGram(Scheme scheme);
  ~ElementGram();
  ElementGram(ElementGram&&) noexcept;
  ElementGram& operator=(ElementGram&&) noexcept;

  Scheme scheme() const { return scheme_; }

  /// One triangle's element: control vertices (indices into `conn`) in the
  /// canonical order of its type, and the element matrix in that order.
  struct Element {
    std::vector<int> control;
    const Eigen::MatrixXd* matrix = nullptr;
    int type = -1;
  };

  /// The element of face `f` of `conn`. Not thread-safe (it may discover and solve
  /// new types); the returned matrix stays valid for the object's lifetime.
  Element element(const Connectivity& conn, int f);

  /// Number of distinct triangle types discovered so far (Loop; 1 for Linear).
  int numTypes() const;

 private:
  Scheme scheme_;
  struct Library;
  std::unique_ptr<Library> lib_;
};

}  // namespace osdmra
