// Element Gram matrices (element_gram.h) and the closed forms of math.md section 2
// they give: the polyhedral element is the P1 mass matrix of a unit-area triangle;
// every element is symmetric, non-negative, positive semi-definite and sums to 1
// (partition of unity); its control set is the union of the corners' 1-rings (Loop)
// or the corners (polyhedral); a Loop element is 1/4 of its children's pulled back
// through P (the refinement relation, per triangle); and elements are keyed by the
// neighbourhood's shape, not by its numbering.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <map>
#include <set>
#include <vector>

#include "osdmra/mra/element_gram.h"
#include "osdmra/mra/gram.h"
#include "osdmra/subdivision/shapes.h"
#include "support.h"

using namespace osdmra;
using namespace osdmra::test;

namespace {

// The shapes with every kind of vertex: regular (torus), low valence (octahedron),
// valences 3 to 10, boundaries with corners (disc) and without (cylinder).
const char* const kShapes[] = {"octahedron", "torus", "valences", "disc", "cylinder"};

std::set<int> asSet(const std::vector<int>& v) {
  return std::set<int>(v.begin(), v.end());
}

// The vertices whose Loop basis functions are non-zero on face f: its corners' 1-rings.
std::set<int> loopSupport(const Connectivity& c, int f) {
  std::set<int> s;
  for (int k = 0; k < 3; ++k) {
    const int v = c.faces()(f, k);
    s.insert(v);
    for (int w : c.ring(v)) s.insert(w);
  }
  return s;
}

// Calls visit(elements, h) for each scheme of `schemes` (one library each) and each of
// kShapes refined `levels` times.
template <class Visit>
void forEachShape(std::initializer_list<Scheme> schemes, int levels, Visit visit) {
  for (Scheme s : schemes) {
    ElementGram elements(s);
    for (const char* name : kShapes) {
      SCOPED_TRACE(std::string(name) + " " + schemeName(s));
      const TriMesh base = shapes::byName(name);
      const Hierarchy h(base.F, static_cast<int>(base.V.rows()), levels);
      visit(elements, h);
    }
  }
}

// Row sums of I^j: the integrals of the level-j scaling functions.
Eigen::VectorXd rowSums(const SparseMatrix& I) {
  return I * Eigen::VectorXd::Ones(I.cols());
}

}  // namespace

TEST(ElementGram, PolyhedralElementIsTheP1MassMatrix) {
  Eigen::Matrix3d mass = Eigen::Matrix3d::Constant(1.0 / 12);
  mass.diagonal().setConstant(1.0 / 6);
  forEachShape({Scheme::Linear}, 1, [&](ElementGram& elements, const Hierarchy& h) {
    EXPECT_EQ(elements.scheme(), Scheme::Linear);
    const Connectivity& c = h.connectivity(1);
    for (int f = 0; f < c.numFaces(); ++f) {
      const ElementGram::Element e = elements.element(c, f);
      EXPECT_EQ(asSet(e.control),
                (std::set<int>{c.faces()(f, 0), c.faces()(f, 1), c.faces()(f, 2)}));
      ASSERT_EQ(e.control.size(), 3u);
      ASSERT_NE(e.matrix, nullptr);
      EXPECT_EQ(*e.matrix, Eigen::MatrixXd(mass));
      EXPECT_EQ(e.type, 0);
    }
    EXPECT_EQ(elements.numTypes(), 1);
  });
}

// math.md 2.3 and 2.4 for the polyhedral scheme: the integral of phi^j_i is a third of
// the area of its faces, (faces around i) * 4^-j / 3, and the entries of row i of I^j
// sum to it.
TEST(ElementGram, PolyhedralRowsSumToTheIntegralOfTheHatFunction) {
  forEachShape({Scheme::Linear}, 2, [](ElementGram& elements, const Hierarchy& h) {
    for (int j = 0; j <= 2; ++j) {
      const Connectivity& c = h.connectivity(j);
      const Eigen::VectorXd sums = rowSums(gram(c, j, elements));
      for (int v = 0; v < c.numVertices(); ++v)
        EXPECT_DOUBLE_EQ(sums(v), c.numVertexFaces(v) * std::ldexp(1.0, -2 * j) / 3) << v;
    }
  });
}

// Loop: on a mesh whose vertices are all alike the integrals are equal, and as they
// sum to the area (one per base face), each is (faces / vertices) * 4^-j: 2 * 4^-j on
// the torus (a quotient of the regular lattice) at every level, F/V on the regular
// polyhedra.
TEST(ElementGram, LoopRowsSumToTheIntegralOnSymmetricMeshes) {
  ElementGram elements(Scheme::Loop);
  const TriMesh torus = shapes::torus();
  const Hierarchy h(torus.F, static_cast<int>(torus.V.rows()), 2);
  for (int j = 0; j <= 2; ++j) {
    const Eigen::VectorXd sums = rowSums(gram(h.connectivity(j), j, elements));
    for (Eigen::Index v = 0; v < sums.size(); ++v)
      EXPECT_NEAR(sums(v), 2 * std::ldexp(1.0, -2 * j), 1e-14) << "level " << j << " vertex " << v;
  }
  for (const char* name : {"tetrahedron", "octahedron", "icosahedron"}) {
    SCOPED_TRACE(name);
    const TriMesh m = shapes::byName(name);
    const Connectivity c(m.F, static_cast<int>(m.V.rows()));
    const Eigen::VectorXd sums = rowSums(gram(c, 0, elements));
    for (Eigen::Index v = 0; v < sums.size(); ++v)
      EXPECT_NEAR(sums(v), double(m.F.rows()) / double(m.V.rows()), 1e-14) << "vertex " << v;
  }
}

TEST(ElementGram, ElementsAreSymmetricNonNegativeAndSumToOne) {
  forEachShape({Scheme::Loop, Scheme::Linear}, 1, [](ElementGram& elements, const Hierarchy& h) {
    for (int j = 0; j <= 1; ++j) {
      const Connectivity& c = h.connectivity(j);
      for (int f = 0; f < c.numFaces(); ++f) {
        const ElementGram::Element e = elements.element(c, f);
        const Eigen::MatrixXd& E = *e.matrix;
        const int m = static_cast<int>(e.control.size());
        ASSERT_EQ(E.rows(), m);
        ASSERT_EQ(E.cols(), m);
        // The control set: distinct vertices, exactly those whose functions reach f.
        EXPECT_EQ(static_cast<int>(asSet(e.control).size()), m);
        if (elements.scheme() == Scheme::Loop) {
          EXPECT_EQ(asSet(e.control), loopSupport(c, f)) << "face " << f;
        }
        EXPECT_EQ((E - E.transpose()).cwiseAbs().maxCoeff(), 0.0);
        EXPECT_GE(E.minCoeff(), -1e-15) << "face " << f;
        EXPECT_NEAR(E.sum(), 1.0, 1e-13) << "face " << f;
        const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(E);
        EXPECT_GE(eig.eigenvalues().minCoeff(), -1e-14) << "face " << f;
      }
    }
  });
  // A regular triangle's element: 12 control vertices, and one type for the torus.
  ElementGram loop(Scheme::Loop);
  const TriMesh torus = shapes::torus();
  const Connectivity c(torus.F, static_cast<int>(torus.V.rows()));
  std::set<int> types;
  for (int f = 0; f < c.numFaces(); ++f) {
    const ElementGram::Element e = loop.element(c, f);
    EXPECT_EQ(e.control.size(), 12u);
    types.insert(e.type);
  }
  EXPECT_EQ(types.size(), 1u);
  EXPECT_EQ(loop.numTypes(), 1);
}

// element_gram.h: E_T = 1/4 sum_c A_c^T E_c A_c, A_c the rows of P^{j+1} for the child
// c's control set; with I^j = 4^-j sum_T scatter(E_T), 4^-j E_T is the pulled-back
// sum of the children's 4^-(j+1) E_c. The children's control vertices depend only on
// T's control vertices (what makes the relation local).
TEST(ElementGram, ElementsRefineLocally) {
  forEachShape({Scheme::Loop, Scheme::Linear}, 2, [](ElementGram& elements, const Hierarchy& h) {
    for (int j = 0; j < 2; ++j) {
      const Connectivity &coarse = h.connectivity(j), &fine = h.connectivity(j + 1);
      const SparseMatrix& P = h.refinement(elements.scheme(), j);
      for (int f = 0; f < coarse.numFaces(); ++f) {
        const ElementGram::Element parent = elements.element(coarse, f);
        const int m = static_cast<int>(parent.control.size());
        std::map<int, int> column;  // parent control vertex -> position
        for (int p = 0; p < m; ++p) column[parent.control[p]] = p;
        Eigen::MatrixXd pulled = Eigen::MatrixXd::Zero(m, m);
        for (int child = 4 * f; child < 4 * f + 4; ++child) {
          const ElementGram::Element e = elements.element(fine, child);
          Eigen::MatrixXd A = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(e.control.size()), m);
          for (std::size_t r = 0; r < e.control.size(); ++r)
            for (SparseMatrix::InnerIterator it(P, e.control[r]); it; ++it) {
              const auto at = column.find(static_cast<int>(it.col()));
              ASSERT_NE(at, column.end())
                  << "face " << f << ", child " << child << ": row " << e.control[r]
                  << " of P reaches vertex " << it.col() << " outside the parent's control set";
              A(static_cast<Eigen::Index>(r), at->second) = it.value();
            }
          pulled += 0.25 * A.transpose() * *e.matrix * A;
        }
        EXPECT_LT((pulled - *parent.matrix).cwiseAbs().maxCoeff(), 1e-13) << "face " << f;
      }
    }
  });
}

// Elements are keyed by a canonical encoding of the neighbourhood: the same mesh
// numbered otherwise finds the types already known, and every element is the same
// matrix on the same vertices. A returned matrix stays valid as types are added.
TEST(ElementGram, TheNumberingDoesNotMatter) {
  const TriMesh base = shapes::valences();
  const Hierarchy h(base.F, static_cast<int>(base.V.rows()), 1);
  const TriMesh mesh{Points::Zero(h.numVertices(1), 3), h.faces(1), Points()};
  std::vector<int> newIndexOf;
  const TriMesh shuffled = shuffle(mesh, 23, &newIndexOf);
  const Connectivity original(mesh.F, static_cast<int>(mesh.V.rows()));
  const Connectivity renumbered(shuffled.F, static_cast<int>(shuffled.V.rows()));
  // Face of `original` with the same (renumbered) corners as each face of `renumbered`.
  std::map<std::set<int>, int> faceOf;
  for (int f = 0; f < original.numFaces(); ++f) {
    std::set<int> corners;
    for (int k = 0; k < 3; ++k) corners.insert(newIndexOf[mesh.F(f, k)]);
    faceOf[corners] = f;
  }
  ElementGram elements(Scheme::Loop);
  const ElementGram::Element first = elements.element(original, 0);
  const Eigen::MatrixXd firstMatrix = *first.matrix;
  std::vector<ElementGram::Element> known;
  for (int f = 0; f < original.numFaces(); ++f) known.push_back(elements.element(original, f));
  const int types = elements.numTypes();
  // The same matrices on the same vertices, from this library and from a fresh one fed
  // the renumbered mesh first (to rounding: a triangle whose rotations look alike may
  // start its control list at another corner, and its solved matrix has the triangle's
  // symmetry only to rounding).
  ElementGram fresh(Scheme::Loop);
  for (int g = 0; g < renumbered.numFaces(); ++g) {
    const std::set<int> corners{renumbered.faces()(g, 0), renumbered.faces()(g, 1),
                                renumbered.faces()(g, 2)};
    const int f = faceOf.at(corners);
    for (ElementGram* library : {&elements, &fresh}) {
      const ElementGram::Element e = library->element(renumbered, g);
      if (library == &elements) {
        EXPECT_EQ(e.type, known[f].type) << "face " << g;
      }
      ASSERT_EQ(e.control.size(), known[f].control.size());
      std::map<int, int> position;  // renumbered vertex -> position in known[f]
      for (std::size_t p = 0; p < known[f].control.size(); ++p)
        position[newIndexOf[known[f].control[p]]] = static_cast<int>(p);
      for (std::size_t p = 0; p < e.control.size(); ++p)
        for (std::size_t q = 0; q < e.control.size(); ++q)
          EXPECT_NEAR((*e.matrix)(p, q),
                      (*known[f].matrix)(position.at(e.control[p]), position.at(e.control[q])),
                      1e-15)
              << "face " << g;
    }
  }
  EXPECT_EQ(elements.numTypes(), types);
  EXPECT_EQ(fresh.numTypes(), types);
  // More shapes, more types; the first matrix is where it was, unchanged, also after
  // the library is moved.
  for (const char* name : kShapes) {
    const TriMesh other = shapes::byName(name);
    const Connectivity c(other.F, static_cast<int>(other.V.rows()));
    for (int f = 0; f < c.numFaces(); ++f) elements.element(c, f);
  }
  EXPECT_GT(elements.numTypes(), types);
  const ElementGram moved = std::move(elements);
  EXPECT_EQ(*first.matrix, firstMatrix);
  EXPECT_GT(moved.numTypes(), types);
}
