#include "osdmra/approximation.h"

#include <algorithm>
#include <cmath>

#include "osdmra/error.h"

namespace osdmra {

Approximator::Approximator(const FilterBank& bank, const Decomposition& d, Importance importance)
    : bank_(bank), d_(d), importance_(osdmra::importance(d, bank.norms, importance)) {
  // One sort serves every extraction: keeping k coefficients is a prefix.
  for (std::size_t j = 0; j < importance_.size(); ++j)
    for (Eigen::Index i = 0; i < importance_[j].size(); ++i)
      order_.emplace_back(static_cast<int>(j), static_cast<int>(i));
  std::stable_sort(order_.begin(), order_.end(), [&](const auto& a, const auto& b) {
    return importance_[a.first](a.second) > importance_[b.first](b.second);
  });
  const Hierarchy& h = *bank.hierarchy;
  if (bank.scheme == Scheme::Loop)
    limit_ = std::make_unique<Hierarchy::LimitStencils>(h.limitStencils(h.levels()));
  full_.F = h.faces(h.levels());
  fullControls_ = synthesize(bank, d, d.levels);
  full_.V = positions(fullControls_, &full_.N);
}

Points Approximator::positions(const Points& controls, Points* normals) const {
  if (!limit_) {
    if (normals) normals->resize(0, 3);
    return controls;
  }
  if (normals) *normals = unitNormals(limit_->tangent1 * controls, limit_->tangent2 * controls);
  return limit_->position * controls;
}

KeepMask Approximator::maskOfCount(long long count) const {
  KeepMask keep(importance_.size());
  for (std::size_t j = 0; j < importance_.size(); ++j)
    keep[j].assign(static_cast<std::size_t>(importance_[j].size()), 0);
  count = std::clamp<long long>(count, 0, numCoefficients());
  for (long long k = 0; k < count; ++k) keep[order_[k].first][order_[k].second] = 1;
  return keep;
}

Approximation Approximator::make(const KeepMask& keep) const {
  Approximation a;
  a.total = numCoefficients();
  a.kept = countKept(keep);
  a.keep = keep;
  a.lod = extractLod(*bank_.hierarchy, keep);
  const Points controls = synthesize(bank_, truncate(d_, keep), d_.levels);
  // Only the LOD's vertices are evaluated: rows of the limit stencils (or of the
  // controls themselves for the polyhedral scheme).
  const int n = static_cast<int>(a.lod.vertices.size());
  a.mesh.V.resize(n, 3);
  if (limit_) {
    Points du(n, 3), dv(n, 3);
    for (int i = 0; i < n; ++i) {
      const int v = a.lod.vertices[i];
      a.mesh.V.row(i) = limit_->position.row(v) * controls;
      du.row(i) = limit_->tangent1.row(v) * controls;
      dv.row(i) = limit_->tangent2.row(v) * controls;
    }
    a.mesh.N = unitNormals(du, dv);
  } else {
    for (int i = 0; i < n; ++i) a.mesh.V.row(i) = controls.row(a.lod.vertices[i]);
  }
  a.mesh.F = a.lod.compactFaces;
  return a;
}

Approximation Approximator::keepCount(long long count) const {
  return make(maskOfCount(count));
}

Approximation Approximator::keepFraction(double fraction) const {
  if (!(fraction >= 0.0 && fraction <= 1.0))
    throw Error("the fraction of coefficients kept must be in [0, 1]");
  return keepCount(std::llround(fraction * static_cast<double>(numCoefficients())));
}

Approximation Approximator::keepAbove(double epsilon) const {
  return make(osdmra::keepAbove(importance_, epsilon));
}

Approximation Approximator::budget(long long triangles) const {
  // Largest count whose mesh fits. The triangle count grows with the kept count
  // (nested keep sets give nested meshes) and almost linearly, so interpolating
  // between the bracket's ends finds it in a few extractions; every other step is
  // a bisection, so the bracket always at least halves in two steps.
  auto trianglesOf = [&](long long count) {
    return static_cast<long long>(
        extractLod(*bank_.hierarchy, maskOfCount(count)).compactFaces.rows());
  };
  long long lo = 0, hi = numCoefficients();
  long long tlo = trianglesOf(lo), thi = trianglesOf(hi);
  if (thi <= triangles) return keepCount(hi);
  if (tlo > triangles) return keepCount(0);  // the base mesh is the coarsest there is
  for (bool interpolate = true; lo + 1 < hi; interpolate = !interpolate) {
    long long mid = lo + (hi - lo) / 2;
    if (interpolate && thi > tlo) {
      const double f = static_cast<double>(triangles - tlo) / static_cast<double>(thi - tlo);
      mid = lo + static_cast<long long>(f * static_cast<double>(hi - lo));
    }
    mid = std::clamp(mid, lo + 1, hi - 1);
    const long long t = trianglesOf(mid);
    if (t <= triangles) {
      lo = mid;
      tlo = t;
    } else {
      hi = mid;
      thi = t;
    }
  }
  return keepCount(lo);
}

double Approximator::l2Error(const Approximation& a) const {
  return l2Distance(*bank_.hierarchy, bank_.scheme,
                    synthesize(bank_, truncate(d_, a.keep), d_.levels), fullControls_);
}

}  // namespace osdmra
