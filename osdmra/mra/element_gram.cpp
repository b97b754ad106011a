#include "osdmra/mra/element_gram.h"

#include <Eigen/QR>
#include <deque>
#include <functional>
#include <string>
#include <unordered_map>

#include "osdmra/base/detail/key_hash.h"
#include "osdmra/base/error.h"

namespace osdmra {

namespace {

// Canonical description of the fans of a triangle's three vertices, starting at
// corner `rot`: for each corner t (in order), whether it is on the boundary, its
// number of faces, where T sits in its fan, then every fan face as the positions
// of its two other vertices in the control list (new vertices are appended in the
// order met). Two triangles with equal keys have isomorphic fan complexes, and
// therefore equal element matrices in the order of `control`.
void encode(const Connectivity& conn, int f, int rot, std::vector<int>& key,
            std::vector<int>& control) {
  const Faces& F = conn.faces();
  const int v[3] = {F(f, rot), F(f, (rot + 1) % 3), F(f, (rot + 2) % 3)};
  control.assign(v, v + 3);
  key.clear();
  auto pos = [&](int x) {
    for (std::size_t i = 0; i < control.size(); ++i)
      if (control[i] == x) return static_cast<int>(i);
    control.push_back(x);
    return static_cast<int>(control.size()) - 1;
  };
  for (int t = 0; t < 3; ++t) {
    const IndexSpan fan = conn.fan(v[t]);
    const int k = fan.size();
    if (k == 0)
      throw Error("face " + std::to_string(f) + ": vertex " + std::to_string(v[t]) +
                  " is not manifold");
    int start = -1;
    for (int i = 0; i < k; ++i)
      if (fan[i] / 3 == f) start = i;
    const bool boundary = conn.isBoundaryVertex(v[t]);
    key.push_back(boundary ? 1 : 0);
    key.push_back(k);
    key.push_back(boundary ? start : 0);
    for (int s = 0; s < k; ++s) {
      const int h = fan[(start + s) % k];
      key.push_back(pos(conn.to(h)));
      key.push_back(pos(conn.from(Connectivity::prev(h))));
    }
  }
}

// Index of the upper-triangle entry (p <= q) of an m x m symmetric matrix.
inline int sym(int p, int q, int m) {
  return p * m - p * (p - 1) / 2 + (q - p);
}

}  // namespace

struct ElementGram::Library {
  struct Child {
    int type;
    Eigen::MatrixXd A;  // rows: child's control set; columns: parent's
  };
  struct Node {
    int size = 0;
    std::vector<Child> children;
    Eigen::MatrixXd E;
    bool solved = false;
  };
  std::unordered_map<std::vector<int>, int, KeyHash> index;
  std::deque<Node> nodes;  // a deque keeps references valid while it grows
  std::vector<int> pending;
  Eigen::MatrixXd linear;
  std::vector<int> scratchKey, scratchControl;

  // Canonical key and control list of face f: the smallest key over rotations.
  void canonical(const Connectivity& conn, int f, std::vector<int>& outKey,
                 std::vector<int>& outControl) {
    for (int rot = 0; rot < 3; ++rot) {
      encode(conn, f, rot, scratchKey, scratchControl);
      if (rot == 0 || scratchKey < outKey) {
        outKey = scratchKey;
        outControl = scratchControl;
      }
    }
  }

  int find(const Connectivity& conn, int f, std::vector<int>& outControl) {
    std::vector<int> k;
    canonical(conn, f, k, outControl);
    auto it = index.find(k);
    if (it != index.end()) return it->second;
    return discover(conn, f, std::move(k), outControl);
  }

  // Registers the type of face f and, recursively, of its descendants, on a local
  // mesh made of the fans of f's vertices refined once by OpenSubdiv.
  int discover(const Connectivity& conn, int f, std::vector<int> k,
               const std::vector<int>& control) {
    if (nodes.size() > 20000) throw Error("internal: Loop element types do not close");
    const int id = static_cast<int>(nodes.size());
    nodes.emplace_back();
    index.emplace(std::move(k), id);
    Node& node = nodes.back();
    const int m = static_cast<int>(control.size());
    node.size = m;

    std::vector<int> faceList;
    for (int t = 0; t < 3; ++t)
      for (int h : conn.fan(control[t])) {
        const int g = h / 3;
        bool seen = false;
        for (int x : faceList) seen = seen || x == g;
        if (!seen) faceList.push_back(g);
      }
    Faces local(static_cast<Eigen::Index>(faceList.size()), 3);
    int localT = -1;
    for (std::size_t i = 0; i < faceList.size(); ++i) {
      if (faceList[i] == f) localT = static_cast<int>(i);
      for (int c = 0; c < 3; ++c) {
        const int x = conn.faces()(faceList[i], c);
        int p = -1;
        for (int q = 0; q < m; ++q)
          if (control[q] == x) p = q;
        if (p < 0) throw Error("internal: fan vertex outside the control set");
        local(static_cast<Eigen::Index>(i), c) = p;
      }
    }
    Hierarchy h(local, m, 1);
    const SparseMatrix& P = h.refinement(Scheme::Loop, 0);
    const Connectivity& fine = h.connectivity(1);
    for (int c = 0; c < 4; ++c) {
      std::vector<int> childControl;
      const int childType = find(fine, 4 * localT + c, childControl);
      Eigen::MatrixXd A = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(childControl.size()), m);
      for (std::size_t r = 0; r < childControl.size(); ++r)
        for (SparseMatrix::InnerIterator it(P, childControl[r]); it; ++it)
          A(static_cast<Eigen::Index>(r), it.col()) = it.value();
      nodes[id].children.push_back({childType, std::move(A)});
    }
    pending.push_back(id);
    return id;
  }

  // Solves every pending type: strongly connected components of the child graph
  // in dependency order, each as one small dense system (see the header).
  void solvePending() {
    std::vector<int> order(nodes.size(), -1), low(nodes.size(), 0), stack;
    std::vector<char> onStack(nodes.size(), 0);
    int counter = 0;
    std::function<void(int)> visit = [&](int v) {
      order[v] = low[v] = counter++;
      stack.push_back(v);
      onStack[v] = 1;
      for (const Child& c : nodes[v].children) {
        if (nodes[c.type].solved) continue;
        if (order[c.type] < 0) {
          visit(c.type);
          low[v] = std::min(low[v], low[c.type]);
        } else if (onStack[c.type]) {
          low[v] = std::min(low[v], order[c.type]);
        }
      }
      if (low[v] == order[v]) {
        std::vector<int> component;
        int w;
        do {
          w = stack.back();
          stack.pop_back();
          onStack[w] = 0;
          component.push_back(w);
        } while (w != v);
        solveComponent(component);
      }
    };
    for (int id : pending)
      if (!nodes[id].solved && order[id] < 0) visit(id);
    pending.clear();
  }

  void solveComponent(const std::vector<int>& comp) {
    std::unordered_map<int, int> offset;
    int n = 0;
    for (int t : comp) {
      offset[t] = n;
      n += nodes[t].size * (nodes[t].size + 1) / 2;
    }
    const int rows = n + static_cast<int>(comp.size());
    Eigen::MatrixXd M = Eigen::MatrixXd::Zero(rows, n);
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(rows);
    for (std::size_t ti = 0; ti < comp.size(); ++ti) {
      const int t = comp[ti];
      const int m = nodes[t].size, ot = offset[t];
      for (int p = 0; p < m; ++p)
        for (int q = p; q < m; ++q) M(ot + sym(p, q, m), ot + sym(p, q, m)) += 1.0;
      Eigen::MatrixXd known = Eigen::MatrixXd::Zero(m, m);
      for (const Child& c : nodes[t].children) {
        const Eigen::MatrixXd& A = c.A;
        auto it = offset.find(c.type);
        if (it == offset.end()) {
          known += 0.25 * A.transpose() * nodes[c.type].E * A;
          continue;
        }
        // d[A^T X A]_pq / dX_rs for the symmetric unknown X of the child's type.
        const int mc = nodes[c.type].size, oc = it->second;
        for (int r = 0; r < mc; ++r)
          for (int s = r; s < mc; ++s) {
            const int col = oc + sym(r, s, mc);
            for (int p = 0; p < m; ++p)
              for (int q = p; q < m; ++q) {
                double d = A(r, p) * A(s, q);
                if (r != s) d += A(s, p) * A(r, q);
                if (d != 0.0) M(ot + sym(p, q, m), col) -= 0.25 * d;
              }
          }
      }
      for (int p = 0; p < m; ++p)
        for (int q = p; q < m; ++q) rhs(ot + sym(p, q, m)) = known(p, q);
      // Partition of unity: the integral of (sum phi)^2 over T is T's area.
      const int row = n + static_cast<int>(ti);
      for (int p = 0; p < m; ++p)
        for (int q = p; q < m; ++q) M(row, ot + sym(p, q, m)) = p == q ? 1.0 : 2.0;
      rhs(row) = 1.0;
    }
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(M);
    if (qr.rank() < n)
      throw Error("internal: the Loop inner-product system of " + std::to_string(comp.size()) +
                  " triangle type(s) is rank deficient (" + std::to_string(qr.rank()) + " < " +
                  std::to_string(n) + ")");
    const Eigen::VectorXd x = qr.solve(rhs);
    const double residual = (M * x - rhs).lpNorm<Eigen::Infinity>();
    if (!(residual < 1e-11))
      throw Error("internal: the Loop inner-product system is inconsistent (residual " +
                  std::to_string(residual) + ")");
    for (int t : comp) {
      const int m = nodes[t].size, ot = offset[t];
      Eigen::MatrixXd E(m, m);
      for (int p = 0; p < m; ++p)
        for (int q = p; q < m; ++q) E(p, q) = E(q, p) = x(ot + sym(p, q, m));
      nodes[t].E = std::move(E);
      nodes[t].solved = true;
    }
  }
};

ElementGram::ElementGram(Scheme scheme) : scheme_(scheme), lib_(std::make_unique<Library>()) {
  // P1 mass matrix of a unit-area triangle.
  lib_->linear = Eigen::MatrixXd::Constant(3, 3, 1.0 / 12.0);
  lib_->linear.diagonal().setConstant(1.0 / 6.0);
}
ElementGram::~ElementGram() = default;
ElementGram::ElementGram(ElementGram&&) noexcept = default;
ElementGram& ElementGram::operator=(ElementGram&&) noexcept = default;

int ElementGram::numTypes() const {
  return scheme_ == Scheme::Linear ? 1 : static_cast<int>(lib_->nodes.size());
}

ElementGram::Element ElementGram::element(const Connectivity& conn, int f) {
  Element e;
  if (scheme_ == Scheme::Linear) {
    e.control = {conn.faces()(f, 0), conn.faces()(f, 1), conn.faces()(f, 2)};
    e.matrix = &lib_->linear;
    e.type = 0;
    return e;
  }
  e.type = lib_->find(conn, f, e.control);
  if (!lib_->nodes[e.type].solved) lib_->solvePending();
  e.matrix = &lib_->nodes[e.type].E;
  return e;
}

}  // namespace osdmra
