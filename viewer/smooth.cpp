#include "smooth.h"

#include <opensubdiv/far/patchTableFactory.h>
#include <opensubdiv/far/stencilTableFactory.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>

#include <stdexcept>

namespace viewer {

namespace Far = OpenSubdiv::Far;
namespace Sdc = OpenSubdiv::Sdc;

namespace {

// A point for Far's stencil evaluation (which needs Clear and AddWithWeight).
struct Point3 {
  double p[3];
  void Clear() { p[0] = p[1] = p[2] = 0.0; }
  void AddWithWeight(const Point3& src, double w) {
    p[0] += w * src.p[0];
    p[1] += w * src.p[1];
    p[2] += w * src.p[2];
  }
};

}  // namespace

LoopPatches::LoopPatches(const std::vector<int>& triangles, int numVertices, int isolation)
    : numControl_(numVertices) {
  const int faces = static_cast<int>(triangles.size() / 3);
  const std::vector<int> valences(static_cast<std::size_t>(faces), 3);
  Far::TopologyDescriptor desc;
  desc.numVertices = numVertices;
  desc.numFaces = faces;
  desc.numVertsPerFace = valences.data();
  desc.vertIndicesPerFace = triangles.data();

  Sdc::Options sdc;
  // Loop's crease rule on boundaries, the rule osdmra's hierarchy uses.
  sdc.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_EDGE_ONLY);
  using Factory = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;
  std::unique_ptr<Far::TopologyRefiner> refiner(
      Factory::Create(desc, Factory::Options(Sdc::SCHEME_LOOP, sdc)));
  if (!refiner) throw std::runtime_error("OpenSubdiv rejected the control mesh");

  Far::TopologyRefiner::AdaptiveOptions adaptive(isolation);
  refiner->RefineAdaptive(adaptive);

  Far::PatchTableFactory::Options po(isolation);
  po.SetEndCapType(Far::PatchTableFactory::Options::ENDCAP_GREGORY_BASIS);
  po.SetPatchPrecision<double>();
  patches_.reset(Far::PatchTableFactory::Create(*refiner, po));

  // The patches index the control points, then the points of every refined level,
  // then the end caps' local points: one stencil table gives all but the first.
  Far::StencilTableFactoryReal<double>::Options so;
  so.generateOffsets = true;
  so.generateIntermediateLevels = true;
  std::unique_ptr<const Far::StencilTableReal<double>> refined(
      Far::StencilTableFactoryReal<double>::Create(*refiner, so));
  const Far::StencilTableReal<double>* local = patches_->GetLocalPointStencilTable<double>();
  if (local && local->GetNumStencils() > 0) {
    stencils_.reset(Far::StencilTableFactoryReal<double>::AppendLocalPointStencilTable(
        *refiner, refined.get(), local));
  } else {
    stencils_ = std::move(refined);
  }
}

LoopPatches::~LoopPatches() = default;

std::vector<float> LoopPatches::points(const std::vector<double>& controls) const {
  const int extra = stencils_ ? stencils_->GetNumStencils() : 0;
  std::vector<Point3> all(static_cast<std::size_t>(numControl_ + extra));
  for (int i = 0; i < numControl_; ++i)
    for (int k = 0; k < 3; ++k) all[i].p[k] = controls[3 * static_cast<std::size_t>(i) + k];
  if (extra) stencils_->UpdateValues(all.data(), all.data() + numControl_);
  std::vector<float> out(all.size() * 3);
  for (std::size_t i = 0; i < all.size(); ++i)
    for (int k = 0; k < 3; ++k) out[3 * i + k] = static_cast<float>(all[i].p[k]);
  return out;
}

}  // namespace viewer
