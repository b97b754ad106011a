#include "report.h"

#include <algorithm>
#include <cstdio>

#include "args.h"

namespace osdmra::cli {

Json topologyJson(const TriMesh& mesh, const Connectivity& c) {
  const int loops = c.numBoundaryLoops(), components = c.numComponents();
  const int chi = c.eulerCharacteristic();
  int vmin = 1 << 30, vmax = 0;
  for (int v = 0; v < c.numVertices(); ++v) {
    vmin = std::min(vmin, c.valence(v));
    vmax = std::max(vmax, c.valence(v));
  }
  return Json::object()
      .add("vertices", static_cast<int>(mesh.V.rows()))
      .add("faces", static_cast<int>(mesh.F.rows()))
      .add("edges", c.numEdges())
      .add("components", components)
      .add("boundary_loops", loops)
      .add("euler_characteristic", chi)
      .add("genus", (2 * components - chi - loops) / 2)
      .add("valence_min", vmin)
      .add("valence_max", vmax)
      .add("bbox_diagonal", boundingBoxDiagonal(mesh.V));
}

Json remeshJson(const RemeshReport& r) {
  Json warnings = Json::array();
  for (const std::string& w : r.warnings) warnings.push(withFlagNames(w));
  return Json::object()
      .add("input_vertices", r.inputVertices)
      .add("input_faces", r.inputFaces)
      .add("unreferenced_vertices_dropped", r.droppedVertices)
      .add("duplicate_faces_dropped", r.duplicateFaces)
      .add("repeated_corner_faces_dropped", r.repeatedCornerFaces)
      .add("welded_vertices", r.welding.vertices)
      .add("welded_faces_dropped", r.welding.faces)
      .add("split_vertices", r.splitVertices)
      .add("t_junction_edges_split", r.zippedEdges)
      .add("non_manifold_edges_cut", r.cutEdges)
      .add("reoriented_faces", r.reorientedFaces)
      .add("small_components_dropped", r.smallComponentsDropped)
      .add("zero_area_faces", Json::object()
                                  .add("flipped", r.zeroArea.flipped)
                                  .add("dropped", r.zeroArea.dropped)
                                  .add("collapsed", r.zeroArea.collapsed)
                                  .add("left", r.zeroArea.left))
      .add("input_self_intersections", r.inputSelfIntersections)
      .add("input_folds", Json::object()
                              .add("corners", r.result.unfold.foldCorners)
                              .add("corners_left", r.result.unfold.foldCornersLeft)
                              .add("moved_vertices", r.result.unfold.movedVertices)
                              .add("largest_move_relative", r.result.unfold.largestMove))
      .add("feature_edges", r.result.featureEdges)
      .add("feature_edges_dropped", r.result.featureEdgesDropped)
      .add("tips", r.result.tips)
      .add("base_vertices", static_cast<int>(r.result.base.V.rows()))
      .add("base_faces", static_cast<int>(r.result.base.F.rows()))
      .add("levels", r.result.levels)
      .add("faces", static_cast<int>(r.result.mesh.F.rows()))
      .add("simplification", Json::object()
                                 .add("rounds", r.result.simplificationRounds)
                                 .add("stage", r.result.simplificationStage)
                                 .add("stages", r.result.stages)
                                 .add("per_vertex_defects", r.result.perVertexDefects))
      .add("smoothing", Json::object()
                            .add("moves", r.result.smoothingMoves)
                            .add("refused", r.result.smoothingRefused))
      .add("base_flips", Json::object()
                             .add("made", r.result.baseFlips)
                             .add("refused", r.result.baseFlipsRefused)
                             .add("towards_input", r.result.baseFlipsTowardsInput))
      .add("base_splits", Json::object()
                              .add("made", r.result.baseSplits)
                              .add("refused", r.result.baseSplitsRefused)
                              .add("at_points", r.result.baseSplitsAtPoints))
      .add("grid_refinement", Json::object().add("moves", r.result.gridRefinementMoves))
      .add("grid_map", Json::object()
                           .add("used", r.result.gridMap)
                           .add("straightened_folds", r.result.straightenedFolds)
                           .add("exact_folds", r.result.exactFolds)
                           .add("straightened_defects", r.result.straightenedDefects)
                           .add("exact_defects", r.result.exactDefects))
      .add("clean_up", Json::object()
                           .add("defects_before", r.result.cleanupDefectsBefore)
                           .add("moved_points", r.result.cleanupMovedPoints)
                           .add("relaxed_faces", r.result.cleanupRelaxedFaces))
      .add("flipped_triangles", r.result.flippedTriangles)
      .add("degenerate_triangles", r.result.degenerateTriangles)
      .add("self_intersections", r.result.selfIntersections)
      .add("self_intersections_at_input_crossings", r.result.selfIntersectionsAtInputCrossings)
      .add("rms_relative", r.distance.rmsRelative)
      .add("hausdorff_relative", r.distance.hausdorffRelative)
      .add("seconds", r.seconds)
      .add("warnings", warnings);
}

void printRemesh(const std::string& in, const RemeshReport& r) {
  std::printf(
      "%s: remeshed %d faces to %d over a base of %d faces split %d times (%d feature edges) "
      "in %.2f s; distance to the input: RMS %.3g, Hausdorff %.3g of the bounding-box "
      "diagonal; %d flipped, %d zero-area triangles, %lld crossing pairs\n",
      in.c_str(), r.inputFaces, static_cast<int>(r.result.mesh.F.rows()),
      static_cast<int>(r.result.base.F.rows()), r.result.levels, r.result.featureEdges, r.seconds,
      r.distance.rmsRelative, r.distance.hausdorffRelative, r.result.flippedTriangles,
      r.result.degenerateTriangles, r.result.selfIntersections);
}

Json startJson(const LoadedSurface& s) {
  Json j = Json::object();
  if (s.remeshing) j.add("remesh", remeshJson(*s.remeshing));
  return j;
}

double maxDetail(const Points& d) {
  return d.rows() ? d.rowwise().norm().maxCoeff() : 0.0;
}

Json levelsJson(const Hierarchy& h, const Decomposition& d) {
  Json levels = Json::array();
  for (int j = 0; j < d.levels; ++j)
    levels.push(Json::object()
                    .add("level", j)
                    .add("vertices", h.numVertices(j + 1))
                    .add("coefficients", static_cast<int>(d.details[j].rows()))
                    .add("max_detail_norm", maxDetail(d.details[j])));
  return levels;
}

LodReport lodReport(const AnalysedSurface& a, const Approximation& x, double extractSeconds,
                    const DistanceOptions& distance, const LoadedSurface* loaded,
                    long long budget) {
  LodReport r;
  const bool remeshed = loaded && loaded->remeshing;
  if (remeshed) r.toInput = surfaceDistance(x.mesh, loaded->remeshing->input, distance);
  if (budget >= 0 && x.triangles() > budget) {
    std::string why = " (remesh the surface with --remesh and fewer --base-faces)";
    if (remeshed) {
      const RemeshReport& rr = *loaded->remeshing;
      why = rr.result.base.F.rows() > rr.requestedBaseFaces
                ? " (the remesher kept more base faces than the " +
                      std::to_string(rr.requestedBaseFaces) + " asked for: see its warnings)"
                : " (ask for fewer --base-faces)";
    }
    r.warnings.push_back("the base mesh has " + std::to_string(x.triangles()) +
                         " triangles, more than the budget " + std::to_string(budget) +
                         ", and no level of detail is coarser" + why);
  }
  r.triangles = x.triangles();
  r.selected = x.selected;
  r.kept = x.kept;
  r.total = x.total;
  r.errors = a.errors(x, distance);
  r.extractSeconds = extractSeconds;
  return r;
}

Json lodJson(const LodReport& r) {
  Json j = Json::object();
  j.add("triangles", r.triangles)
      .add("coefficients_selected", r.selected)
      .add("coefficients_kept", r.kept)
      .add("coefficients", r.total)
      .add("l2_error", r.errors.l2)
      .add("l2_rms_relative", r.errors.l2RmsRelative)
      .add("rms_relative", r.errors.rmsRelative)
      .add("hausdorff_relative", r.errors.hausdorffRelative);
  if (r.toInput)
    j.add("to_input", Json::object()
                          .add("rms_relative", r.toInput->rmsRelative)
                          .add("hausdorff_relative", r.toInput->hausdorffRelative));
  Json warnings = Json::array();
  for (const std::string& w : r.warnings) warnings.push(w);
  return j.add("extract_seconds", r.extractSeconds).add("warnings", warnings);
}

Json baseTrialsJson(const BudgetLod& b) {
  Json trials = Json::array();
  for (std::size_t i = 0; i < b.trials.size(); ++i) {
    const BaseTrial& t = b.trials[i];
    trials.push(Json::object()
                    .add("base_faces_asked", t.baseFacesAsked)
                    .add("base_faces", t.baseFaces)
                    .add("levels", t.levels)
                    .add("triangles", t.triangles)
                    .add("crossing_pairs", t.crossingPairs)
                    .add("rms_relative", t.rmsRelative)
                    .add("seconds", t.seconds)
                    .add("skinny_where_flat", t.skinnyWhereFlat)
                    .add("flips_towards_input", t.flipsTowardsInput)
                    .add("order_by_error", t.orderByError)
                    .add("input_hierarchy", t.inputHierarchy)
                    .add("kept", static_cast<int>(i) == b.chosen));
  }
  return trials;
}

void printBaseTrials(const BudgetLod& b) {
  for (std::size_t i = 0; i < b.trials.size(); ++i) {
    const BaseTrial& t = b.trials[i];
    // Each of the trial's options said on its own (--skinny-where-flat 0 leaves the
    // flipped trial without skinny faces).
    std::string asked = std::to_string(t.baseFacesAsked) + " asked";
    if (t.skinnyWhereFlat > 0) asked += ", skinny where flat";
    if (t.flipsTowardsInput > 0)
      asked += ", " + std::to_string(t.flipsTowardsInput) + " edges flipped";
    if (t.orderByError) asked += ", removals by error";
    std::printf(
        "base of %d faces (%s), J = %d: %d triangles, sampled RMS to the input "
        "%.3g (%.1f s)%s%s\n",
        t.baseFaces, t.inputHierarchy ? "the input's own" : asked.c_str(), t.levels, t.triangles,
        t.rmsRelative, t.seconds, t.crossingPairs > 0 ? ", crosses itself" : "",
        static_cast<int>(i) == b.chosen ? ", kept" : "");
  }
}

}  // namespace osdmra::cli
