#include "osdmra/mra/truncation.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numeric>

#include "osdmra/base/error.h"
#include "osdmra/mra/element_gram.h"

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

std::vector<Eigen::VectorXd> surfaceAreaWeights(const Hierarchy& h, const Points& fine) {
  const int J = h.levels();
  if (fine.rows() != h.numVertices(J) || fine.cols() != 3)
    throw Error("surfaceAreaWeights: expected " + std::to_string(h.numVertices(J)) +
                " positions, got " + std::to_string(fine.rows()));
  // Relative area of every hierarchy triangle, finest first: a level-J triangle's
  // surface area over the mean, then each coarser one the mean of its four children.
  const Faces& F = h.faces(J);
  std::vector<Eigen::VectorXd> area(J + 1);
  area[J].resize(F.rows());
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const Eigen::RowVector3d a = fine.row(F(f, 0)), b = fine.row(F(f, 1)), c = fine.row(F(f, 2));
    area[J](f) = 0.5 * (b - a).cross(c - a).norm();
  }
  const double mean = area[J].mean();
  if (!(mean > 0)) throw Error("surfaceAreaWeights: the surface has no area");
  area[J] /= mean;
  for (int j = J - 1; j >= 0; --j) {
    area[j].resize(h.numFaces(j));
    for (int f = 0; f < h.numFaces(j); ++f) area[j](f) = 0.25 * area[j + 1].segment(4 * f, 4).sum();
  }
  std::vector<Eigen::VectorXd> out(J);
  for (int j = 0; j < J; ++j) {
    const Connectivity& c = h.connectivity(j);
    out[j].resize(h.numVertices(j + 1) - h.numVertices(j));
    for (Eigen::Index e = 0; e < out[j].size(); ++e) {
      const auto ab = h.parentEdge(j, static_cast<int>(e));
      const int he = c.edgeHalfedge(c.findEdge(ab[0], ab[1])), tw = c.twin(he);
      const double a = tw < 0 ? area[j](he / 3) : 0.5 * (area[j](he / 3) + area[j](tw / 3));
      out[j](e) = std::sqrt(a);
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

namespace {

void checkMask(const Decomposition& d, const KeepMask& keep) {
  if (keep.size() != d.details.size()) throw Error("truncate: mask has the wrong number of levels");
  for (std::size_t j = 0; j < d.details.size(); ++j)
    if (keep[j].size() != static_cast<std::size_t>(d.details[j].rows()))
      throw Error("truncate: mask of level " + std::to_string(j) + " has the wrong size");
}

}  // namespace

Decomposition truncate(const Decomposition& d, const KeepMask& keep) {
  checkMask(d, keep);
  Decomposition out = d;
  for (std::size_t j = 0; j < d.details.size(); ++j) {
    for (Eigen::Index i = 0; i < d.details[j].rows(); ++i)
      if (!keep[j][i]) out.details[j].row(i).setZero();
  }
  return out;
}

Points synthesizeTruncated(const FilterBank& bank, const Decomposition& d, const KeepMask& keep,
                           int level) {
  checkMask(d, keep);
  if (level < 0 || level > d.levels)
    throw Error("synthesis level " + std::to_string(level) + " is outside 0.." +
                std::to_string(d.levels));
  const Hierarchy& h = *bank.hierarchy;
  Points c = d.base;
  for (int j = 0; j < level; ++j) {
    const Points& detail = d.details[j];
    const std::vector<char>& kept = keep[j];
    // u = c^j - alpha d^j (filter_bank.h), column by column and each term subtracted
    // in turn, as Eigen evaluates the whole product: the same sums, less the zeros.
    const AlphaMatrix& alpha = bank.alpha[j];
    for (Eigen::Index e = 0; e < alpha.outerSize(); ++e)
      if (kept[e])
        for (AlphaMatrix::InnerIterator it(alpha, e); it; ++it)
          c.row(it.index()) -= it.value() * detail.row(e);
    // noalias: fine is not c, so the product is written in place, not through a copy.
    Points fine(h.numVertices(j + 1), 3);
    fine.noalias() = h.refinement(bank.scheme, j) * c;
    const Eigen::Index n = h.numVertices(j);
    for (std::size_t e = 0; e < kept.size(); ++e)
      if (kept[e]) fine.row(n + static_cast<Eigen::Index>(e)) += detail.row(e);
    c = std::move(fine);
  }
  return c;
}

double l2Distance(const Hierarchy& h, Scheme scheme, const Points& a, const Points& b) {
  const int J = h.levels();
  if (a.rows() != h.numVertices(J) || b.rows() != h.numVertices(J))
    throw Error("l2Distance: expected " + std::to_string(h.numVertices(J)) + " points");
  return L2Distance(h, scheme)(a, b);
}

L2Distance::L2Distance(const Hierarchy& h, Scheme scheme)
    : h_(h), elements_(std::make_unique<ElementGram>(scheme)) {
  const Connectivity& conn = h.connectivity(h.levels());
  controlStart_.reserve(static_cast<std::size_t>(conn.numFaces()) + 1);
  matrix_.reserve(static_cast<std::size_t>(conn.numFaces()));
  controlStart_.push_back(0);
  for (int f = 0; f < conn.numFaces(); ++f) {
    const ElementGram::Element el = elements_->element(conn, f);
    control_.insert(control_.end(), el.control.begin(), el.control.end());
    controlStart_.push_back(static_cast<int>(control_.size()));
    matrix_.push_back(el.matrix);
  }
}

L2Distance::~L2Distance() = default;

double L2Distance::operator()(const Points& a, const Points& b) const {
  const int J = h_.levels();
  if (a.rows() != h_.numVertices(J) || b.rows() != h_.numVertices(J))
    throw Error("l2Distance: expected " + std::to_string(h_.numVertices(J)) + " points");
  const Points e = a - b;
  double sum = 0;
  // trace(L^T M L) as the sum of L .* (M L), into buffers reused across faces: no
  // 3 x 3 product and no allocation per face.
  Eigen::MatrixX3d local, weighted;
  for (std::size_t f = 0; f < matrix_.size(); ++f) {
    const int first = controlStart_[f], m = controlStart_[f + 1] - first;
    local.resize(m, 3);
    for (int p = 0; p < m; ++p) local.row(p) = e.row(control_[first + p]);
    weighted.noalias() = *matrix_[f] * local;
    sum += local.cwiseProduct(weighted).sum();
  }
  return std::sqrt(std::max(0.0, sum * std::ldexp(1.0, -2 * J)));
}

}  // namespace osdmra
