#include "osdmra/mra/truncation.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "osdmra/mra/element_gram.h"
#include "osdmra/base/error.h"

namespace osdmra {

std::vector<Eigen::VectorXd> importance(const Decomposition& d,
                                        const std::vector<Eigen::VectorXd>& norms,
                                        Importance kind) {
  std::vector<Eigen::VectorXd> out(d.details.size());
  for (std::size_t j = 0; j < d.details.size(); ++j) {
    out[j] = d.details[j].rowwise().norm();
    if (kind == Importance::Scaled) {
      if (j >= norms.size() || norms[j].size() != out[j].size())
        throw Error("importance: wavelet norms missing for level " + std::to_string(j));
      out[j] = out[j].cwiseProduct(norms[j]);
    }
  }
  return out;
}

KeepMask keepLargest(const std::vector<Eigen::VectorXd>& imp, long long count) {
  struct Item {
    double value;
    int level, index;
  };
  std::vector<Item> items;
  KeepMask keep(imp.size());
  for (std::size_t j = 0; j < imp.size(); ++j) {
    keep[j].assign(static_cast<std::size_t>(imp[j].size()), 0);
    for (Eigen::Index i = 0; i < imp[j].size(); ++i)
      items.push_back({imp[j](i), static_cast<int>(j), static_cast<int>(i)});
  }
  count = std::clamp<long long>(count, 0, static_cast<long long>(items.size()));
  auto before = [](const Item& a, const Item& b) {
    if (a.value != b.value) return a.value > b.value;
    if (a.level != b.level) return a.level < b.level;
    return a.index < b.index;
  };
  // Linear-time selection of the largest `count`, not a full sort.
  if (count > 0 && count < static_cast<long long>(items.size()))
    std::nth_element(items.begin(), items.begin() + (count - 1), items.end(), before);
  for (long long k = 0; k < count; ++k) keep[items[k].level][items[k].index] = 1;
  return keep;
}

KeepMask keepAbove(const std::vector<Eigen::VectorXd>& imp, double epsilon) {
  KeepMask keep(imp.size());
  for (std::size_t j = 0; j < imp.size(); ++j) {
    keep[j].resize(static_cast<std::size_t>(imp[j].size()));
    for (Eigen::Index i = 0; i < imp[j].size(); ++i) keep[j][i] = imp[j](i) >= epsilon ? 1 : 0;
  }
  return keep;
}

long long countKept(const KeepMask& keep) {
  long long n = 0;
  for (const auto& level : keep) n += std::count(level.begin(), level.end(), 1);
  return n;
}

Decomposition truncate(const Decomposition& d, const KeepMask& keep) {
  if (keep.size() != d.details.size()) throw Error("truncate: mask has the wrong number of levels");
  Decomposition out = d;
  for (std::size_t j = 0; j < d.details.size(); ++j) {
    if (keep[j].size() != static_cast<std::size_t>(d.details[j].rows()))
      throw Error("truncate: mask of level " + std::to_string(j) + " has the wrong size");
    for (Eigen::Index i = 0; i < d.details[j].rows(); ++i)
      if (!keep[j][i]) out.details[j].row(i).setZero();
  }
  return out;
}

double l2Distance(const Hierarchy& h, Scheme scheme, const Points& a, const Points& b) {
  const int J = h.levels();
  if (a.rows() != h.numVertices(J) || b.rows() != h.numVertices(J))
    throw Error("l2Distance: expected " + std::to_string(h.numVertices(J)) + " points");
  const Points e = a - b;
  const Connectivity& conn = h.connectivity(J);
  ElementGram elements(scheme);
  double sum = 0;
  Eigen::MatrixX3d local;
  for (int f = 0; f < conn.numFaces(); ++f) {
    const ElementGram::Element el = elements.element(conn, f);
    local.resize(static_cast<Eigen::Index>(el.control.size()), 3);
    for (std::size_t p = 0; p < el.control.size(); ++p) local.row(p) = e.row(el.control[p]);
    sum += (local.transpose() * (*el.matrix) * local).trace();
  }
  return std::sqrt(std::max(0.0, sum * std::ldexp(1.0, -2 * J)));
}

}  // namespace osdmra
