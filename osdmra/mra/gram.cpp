#include "osdmra/mra/gram.h"

#include <algorithm>
#include <cmath>

namespace osdmra {

SparseMatrix gram(const Connectivity& conn, int level, ElementGram& elements) {
  const double scale = std::ldexp(1.0, -2 * level);
  std::vector<Eigen::Triplet<double>> triplets;
  const std::size_t perFace = elements.scheme() == Scheme::Loop ? 144 : 9;
  triplets.reserve(perFace * static_cast<std::size_t>(conn.numFaces()));
  for (int f = 0; f < conn.numFaces(); ++f) {
    const ElementGram::Element e = elements.element(conn, f);
    const Eigen::MatrixXd& E = *e.matrix;
    const int m = static_cast<int>(e.control.size());
    for (int p = 0; p < m; ++p)
      for (int q = 0; q < m; ++q)
        triplets.emplace_back(e.control[p], e.control[q], scale * E(p, q));
  }
  SparseMatrix I(conn.numVertices(), conn.numVertices());
  I.setFromTriplets(triplets.begin(), triplets.end());
  I.makeCompressed();
  return I;
}

LocalGram::LocalGram(const Connectivity& conn, int level, ElementGram& elements)
    : conn_(conn),
      scale_(std::ldexp(1.0, -2 * level)),
      elements_(elements),
      mark_(conn.numVertices(), -1),
      faceMark_(conn.numFaces(), 0),
      elementOf_(conn.numFaces()) {}

const ElementGram::Element& LocalGram::element(int f) {
  ElementGram::Element& e = elementOf_[f];
  if (!e.matrix) e = elements_.element(conn_, f);
  return e;
}

void LocalGram::facesNear(const std::vector<int>& vertices) {
  // Loop's control sets reach one ring beyond a face's corners, so faces within one
  // ring of `vertices` can carry them; polyhedral ones are the corners alone.
  ++stamp_;
  faces_.clear();
  auto addFan = [&](int v) {
    for (int h : conn_.fan(v))
      if (faceMark_[h / 3] != stamp_) {
        faceMark_[h / 3] = stamp_;
        faces_.push_back(h / 3);
      }
  };
  for (int v : vertices) {
    addFan(v);
    if (elements_.scheme() == Scheme::Loop)
      for (int w : conn_.ring(v)) addFan(w);
  }
}

Eigen::MatrixXd LocalGram::block(const std::vector<int>& S) {
  const int n = static_cast<int>(S.size());
  for (int i = 0; i < n; ++i) mark_[S[i]] = i;
  facesNear(S);
  Eigen::MatrixXd B = Eigen::MatrixXd::Zero(n, n);
  // Plain column-major indexing in the inner loops: these run for every face of every
  // local solve, and element-wise operator() costs several times as much with
  // assertions on (sanitizer builds).
  double* const b = B.data();
  for (int f : faces_) {
    const ElementGram::Element& e = element(f);
    hits_.clear();
    for (int p = 0; p < static_cast<int>(e.control.size()); ++p)
      if (mark_[e.control[p]] >= 0) hits_.emplace_back(p, mark_[e.control[p]]);
    const double* const E = e.matrix->data();
    const Eigen::Index m = e.matrix->rows();
    for (auto [p, i] : hits_)
      for (auto [q, k] : hits_) b[i + k * n] += scale_ * E[p + q * m];
  }
  for (int v : S) mark_[v] = -1;
  return B;
}

double LocalGram::quadraticForm(const std::vector<int>& S, const Eigen::VectorXd& x) {
  const int n = static_cast<int>(S.size());
  for (int i = 0; i < n; ++i) mark_[S[i]] = i;
  facesNear(S);
  // The faces and entries block(S) would sum, each face's share x_e^T E x_e at once.
  double sum = 0;
  const double* const xs = x.data();
  for (int f : faces_) {
    const ElementGram::Element& e = element(f);
    hits_.clear();
    for (int p = 0; p < static_cast<int>(e.control.size()); ++p)
      if (mark_[e.control[p]] >= 0) hits_.emplace_back(p, mark_[e.control[p]]);
    const double* const E = e.matrix->data();  // column-major, as in block()
    const Eigen::Index m = e.matrix->rows();
    double face = 0;
    for (auto [p, i] : hits_) {
      double row = 0;
      for (auto [q, k] : hits_) row += E[p + q * m] * xs[k];
      face += xs[i] * row;
    }
    sum += face;
  }
  for (int v : S) mark_[v] = -1;
  return scale_ * sum;
}

std::vector<std::pair<int, double>> LocalGram::column(int k) {
  facesNear({k});
  touched_.clear();
  std::vector<double> values;
  for (int f : faces_) {
    const ElementGram::Element& e = element(f);
    int pk = -1;
    for (int p = 0; p < static_cast<int>(e.control.size()); ++p)
      if (e.control[p] == k) pk = p;
    if (pk < 0) continue;
    for (int p = 0; p < static_cast<int>(e.control.size()); ++p) {
      const int v = e.control[p];
      if (mark_[v] < 0) {
        mark_[v] = static_cast<int>(touched_.size());
        touched_.push_back(v);
        values.push_back(0.0);
      }
      values[mark_[v]] += scale_ * (*e.matrix)(pk, p);
    }
  }
  std::vector<std::pair<int, double>> out;
  out.reserve(touched_.size());
  for (std::size_t i = 0; i < touched_.size(); ++i) {
    out.emplace_back(touched_[i], values[i]);
    mark_[touched_[i]] = -1;
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace osdmra
