// The viewer's state: what is analysed, which level of detail is shown, and the
// data the renderer draws. No GL and no GUI here, so the interactive and headless
// front ends (main.cpp) share every step.
//
// Analysis (recovery, filter bank, decomposition) takes seconds, so it runs on a
// worker thread and reports through an osdmra::Progress callback into atomics the
// UI polls each frame. A finished analysis is immutable and shared: extraction of a
// level of detail (~10 ms) runs on the UI thread as sliders move, and the sampled
// distance measurement, which takes longer, runs on a second worker against a
// snapshot of the mesh it measures.
#pragma once

#include <atomic>
#include <cmath>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "osdmra/geometry/distance.h"
#include "osdmra/pipeline.h"
#include "renderer.h"
#include "smooth.h"

namespace viewer {

/// What to analyse.
struct AnalysisRequest {
  std::string path;
  osdmra::Scheme scheme = osdmra::Scheme::Loop;
  int rings = 1;
  /// Where the level of detail's vertices go (placement.h); `levels` fits every level
  /// once, in the analysis, so that the slider stays as fast as with `surface`.
  osdmra::Placement placement = osdmra::Placement::Surface;
  /// Remeshing first, for a mesh without subdivision connectivity (osdmra remesh).
  osdmra::InputOptions input;
  bool operator==(const AnalysisRequest& o) const {
    const osdmra::RemeshOptions &a = input.remeshing, &b = o.input.remeshing;
    return path == o.path && scheme == o.scheme && rings == o.rings && placement == o.placement &&
           input.remesh == o.input.remesh &&
           (!input.remesh || (a.baseFaces == b.baseFaces && a.levels == b.levels &&
                              a.featureAngle == b.featureAngle));
  }
};

/// Everything an analysed surface gives; built once on the worker, then read-only.
struct Analysis {
  AnalysisRequest request;
  /// The pipeline's analysis (osdmra/pipeline.h): structure, filter bank,
  /// decomposition, approximator.
  std::unique_ptr<osdmra::AnalysedSurface> surface;
  /// With request.input.remesh: the remeshing and its distance to the input file,
  /// apart from truncation.
  std::optional<osdmra::RemeshReport> remeshing;
  std::unique_ptr<osdmra::TriangleBvh> fullBvh;  ///< closest points on the full surface
  osdmra::Points fullNormals;                    ///< of approx().fullResolution()
  double diagonal = 0;                           ///< of the full surface's bounding box
  double minImportance = 0, maxImportance = 0;   ///< range of the epsilon slider
  double seconds = 0;
  const osdmra::Approximator& approx() const { return surface->approximator(); }
  const osdmra::FilterBank& bank() const { return surface->bank(); }
  const osdmra::Decomposition& d() const { return surface->decomposition(); }
  int levels() const { return surface->levels(); }
  int inputTriangles() const { return surface->hierarchy().numFaces(levels()); }
};

/// Reads, validates and analyses a mesh; throws osdmra::Error with the reason.
std::shared_ptr<const Analysis> analyse(const AnalysisRequest& request,
                                        const osdmra::Progress& progress = {});

/// How the level of detail is chosen.
struct Selection {
  enum Kind { Budget, Epsilon } kind = Budget;
  long long budget = 4054;  ///< triangles
  double epsilon = 0;       ///< importance threshold
  bool operator==(const Selection& o) const {
    return kind == o.kind && (kind == Budget ? budget == o.budget : epsilon == o.epsilon);
  }
};

/// One extracted level of detail with its numbers.
struct Lod {
  osdmra::Approximation approx;
  osdmra::Points normals;  ///< Loop limit normals, or area-weighted (polyhedral)
  double extractSeconds = 0;
  double l2Seconds = 0;
  double l2Relative = NAN;         ///< parametric L2 (RMS) / diagonal; NAN until measured
  std::vector<float> vertexError;  ///< distance to the full surface / diagonal, on demand
};

Lod extract(const Analysis& a, const Selection& s);
/// Fills lod.l2Relative: Approximator::l2Error (one synthesis and a sparse quadratic
/// form: tens of milliseconds on large meshes, so it runs when a slider is released).
void measureL2(const Analysis& a, Lod& lod);
/// Fills lod.vertexError (closest-point queries against the full surface).
void measureVertexErrors(const Analysis& a, Lod& lod);

/// GPU-ready meshes. `errorScale`: the relative error drawn at the top of the map.
DrawMesh referenceMesh(const Analysis& a);
DrawMesh lodMesh(const Lod& lod, double errorScale);

/// Smooth mode: the truncated surface's control mesh at `level` (0..J) and its
/// control points, 3 doubles each.
std::vector<int> controlTriangles(const Analysis& a, int level);
std::vector<double> truncatedControls(const Analysis& a, const osdmra::KeepMask& keep, int level);

/// Runs analyses on a worker thread, one at a time. A request made while one runs
/// cancels it (at its next progress report) and starts when it has stopped, so
/// flipping through schemes never queues up stale work.
class AnalysisWorker {
 public:
  ~AnalysisWorker();
  void request(const AnalysisRequest& r);
  /// Call every frame: returns a newly finished analysis (once), or null. Errors
  /// land in error().
  std::shared_ptr<const Analysis> poll();
  bool busy() const { return running_.load(); }
  /// Stage name and fraction of the running analysis.
  std::string stage() const;
  double fraction() const { return fraction_.load(); }
  std::string error() const;

 private:
  void start(const AnalysisRequest& r);
  std::thread thread_;
  std::atomic<bool> running_{false}, cancel_{false};
  std::atomic<double> fraction_{0};
  mutable std::mutex mutex_;
  std::string stage_, error_;
  std::shared_ptr<const Analysis> done_;
  std::optional<AnalysisRequest> waiting_;
};

/// Sampled RMS / Hausdorff distance of a level of detail, on a worker thread.
class DistanceWorker {
 public:
  ~DistanceWorker();
  /// Measures `mesh` against the analysis' full surface; `tag` identifies the
  /// request (the UI shows a result only while its tag is current).
  void request(std::shared_ptr<const Analysis> a, osdmra::TriMesh mesh, long long tag, int samples);
  bool busy() const { return running_.load(); }
  /// The last finished result and its tag, if any.
  std::optional<std::pair<long long, osdmra::SurfaceDistance>> result() const;

 private:
  std::thread thread_;
  std::atomic<bool> running_{false};
  mutable std::mutex mutex_;
  std::optional<std::pair<long long, osdmra::SurfaceDistance>> result_;
};

/// One viewer's state: the analysis shown, the selected level of detail and how it
/// is drawn. update() brings the renderer up to date, redoing only what changed.
class Session {
 public:
  explicit Session(Renderer& renderer) : renderer_(renderer) {}

  Selection selection;
  ColorMode color = ColorMode::Plain;
  double errorScale = 0.002;  ///< relative vertex error drawn at the top of the map
  bool smooth = false;
  int smoothLevel = -1;  ///< control mesh level of the smooth mode; -1: J
  int isolation = 2;     ///< adaptive isolation of the smooth mode's patches
  /// While a slider is dragged the L2 error is left for later: it costs several
  /// times an extraction, and the mesh should follow the slider.
  bool interacting = false;

  /// Shows a new analysis (sets the renderer's bounds and reference mesh).
  void adopt(std::shared_ptr<const Analysis> a);
  /// Extracts, colours and uploads what the settings changed; call once per frame.
  /// Throws osdmra::Error when extraction fails; smooth-mode failures are kept in
  /// smoothStatus() instead, since the mesh view still works.
  void update();

  const std::shared_ptr<const Analysis>& analysis() const { return analysis_; }
  const Lod* lod() const { return lod_ ? &*lod_ : nullptr; }
  /// Increases with every extraction, to tell whether a measurement is current.
  long long generation() const { return generation_; }
  bool smoothReady() const { return smooth && smoothOk_; }
  const std::string& smoothStatus() const { return smoothStatus_; }
  int smoothLevelShown() const { return smoothLevelBuilt_; }

 private:
  void updateSmooth();

  Renderer& renderer_;
  std::shared_ptr<const Analysis> analysis_;
  std::optional<Lod> lod_;
  Selection extracted_;
  long long generation_ = 0;
  // What the renderer holds.
  long long meshGeneration_ = -1;
  bool meshHasErrors_ = false;
  double meshScale_ = 0;
  long long smoothGeneration_ = -1;
  int smoothLevelBuilt_ = -1;
  std::unique_ptr<LoopPatches> patches_;
  bool smoothOk_ = false;
  std::string smoothStatus_;
};

}  // namespace viewer
