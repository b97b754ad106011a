#include "app.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>

#include "osdmra/base/error.h"
#include "osdmra/geometry/normals.h"
#include "osdmra/mra/truncation.h"

namespace viewer {

using osdmra::Points;
using Clock = std::chrono::steady_clock;

namespace {

double secondsSince(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

void appendMesh(DrawMesh& out, const Points& V, const Points& N, const osdmra::Faces& F) {
  out.positions.resize(static_cast<std::size_t>(V.rows()) * 3);
  out.normals.resize(out.positions.size());
  for (Eigen::Index i = 0; i < V.rows(); ++i)
    for (int k = 0; k < 3; ++k) {
      out.positions[3 * i + k] = static_cast<float>(V(i, k));
      out.normals[3 * i + k] = static_cast<float>(N(i, k));
    }
  out.indices.resize(static_cast<std::size_t>(F.rows()) * 3);
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) out.indices[3 * f + k] = static_cast<std::uint32_t>(F(f, k));
}

}  // namespace

std::shared_ptr<const Analysis> analyse(const AnalysisRequest& request,
                                        const osdmra::Progress& progress) {
  const auto t0 = Clock::now();
  auto report = [&](const char* stage, double f) {
    if (progress) progress(stage, f);
  };
  auto a = std::make_shared<Analysis>();
  a->request = request;
  osdmra::LoadedSurface input = osdmra::loadSurface(request.path, request.input, progress);
  osdmra::AnalysisOptions asked;
  asked.scheme = request.scheme;
  asked.wavelets.rings = request.rings;
  asked.approximation.placement = request.placement;
  const osdmra::AnalysisOptions options = osdmra::analysisOptionsFor(input, asked);
  a->remeshing = std::move(input.remeshing);
  a->surface =
      std::make_unique<osdmra::AnalysedSurface>(input.mesh, options, request.path, progress);
  if (request.placement == osdmra::Placement::Levels) {
    report("fitting every level", 0);
    a->approx().prepare();
  }
  const osdmra::TriMesh& full = a->approx().fullResolution();
  a->fullNormals = full.N.rows() == full.V.rows() ? full.N : osdmra::vertexNormals(full);
  a->diagonal = osdmra::boundingBoxDiagonal(full.V);
  report("preparing error measurement", 0);
  a->fullBvh = std::make_unique<osdmra::TriangleBvh>(full);
  // The epsilon slider spans the importances that occur (Approximator's default,
  // |d| * ||psi||), so every position of it selects something different.
  a->minImportance = HUGE_VAL;
  for (const Eigen::VectorXd& level : osdmra::importance(a->d(), a->bank().norms))
    for (double v : level)
      if (v > 0) {
        a->minImportance = std::min(a->minImportance, v);
        a->maxImportance = std::max(a->maxImportance, v);
      }
  if (!(a->maxImportance > 0)) a->minImportance = a->maxImportance = 1;
  a->seconds = secondsSince(t0);
  report("done", 1);
  return a;
}

Lod extract(const Analysis& a, const Selection& s) {
  Lod lod;
  const auto t0 = Clock::now();
  lod.approx =
      s.kind == Selection::Budget ? a.approx().budget(s.budget) : a.approx().keepAbove(s.epsilon);
  lod.extractSeconds = secondsSince(t0);
  lod.normals = lod.approx.mesh.N.rows() == lod.approx.mesh.V.rows()
                    ? lod.approx.mesh.N
                    : osdmra::vertexNormals(lod.approx.mesh);
  return lod;
}

void measureL2(const Analysis& a, Lod& lod) {
  const auto t0 = Clock::now();
  lod.l2Relative = a.surface->l2RmsRelative(lod.approx);
  lod.l2Seconds = secondsSince(t0);
}

void measureVertexErrors(const Analysis& a, Lod& lod) {
  const Points& V = lod.approx.mesh.V;
  lod.vertexError.resize(static_cast<std::size_t>(V.rows()));
  const double scale = a.diagonal > 0 ? 1 / a.diagonal : 1;
  for (Eigen::Index i = 0; i < V.rows(); ++i)
    lod.vertexError[i] =
        static_cast<float>(a.fullBvh->closestPoint(V.row(i).transpose()).distance * scale);
}

DrawMesh referenceMesh(const Analysis& a) {
  DrawMesh m;
  const osdmra::TriMesh& full = a.approx().fullResolution();
  appendMesh(m, full.V, a.fullNormals, full.F);
  m.faceLevel.assign(static_cast<std::size_t>(full.F.rows()), static_cast<float>(a.levels()));
  return m;
}

DrawMesh lodMesh(const Lod& lod, double errorScale) {
  DrawMesh m;
  appendMesh(m, lod.approx.mesh.V, lod.normals, lod.approx.mesh.F);
  m.faceLevel.assign(lod.approx.lod.faceLevel.begin(), lod.approx.lod.faceLevel.end());
  if (!lod.vertexError.empty()) {
    m.vertexValue.resize(lod.vertexError.size());
    for (std::size_t i = 0; i < lod.vertexError.size(); ++i)
      m.vertexValue[i] = errorScale > 0 ? static_cast<float>(lod.vertexError[i] / errorScale) : 0;
  }
  return m;
}

std::vector<int> controlTriangles(const Analysis& a, int level) {
  const osdmra::Faces& F = a.surface->hierarchy().faces(level);
  return std::vector<int>(F.data(), F.data() + F.size());
}

std::vector<double> truncatedControls(const Analysis& a, const osdmra::KeepMask& keep, int level) {
  const Points c = osdmra::synthesizeTruncated(a.bank(), a.d(), keep, level);
  return std::vector<double>(c.data(), c.data() + c.size());
}

// ---- Session ---------------------------------------------------------------------

void Session::adopt(std::shared_ptr<const Analysis> a) {
  analysis_ = std::move(a);
  lod_.reset();
  patches_.reset();
  smoothLevelBuilt_ = -1;
  smoothStatus_.clear();
  smoothOk_ = false;
  const osdmra::TriMesh& full = analysis_->approx().fullResolution();
  const Eigen::Vector3d lo = full.V.colwise().minCoeff(), hi = full.V.colwise().maxCoeff();
  renderer_.setBounds(((lo + hi) / 2).cast<float>(), static_cast<float>((hi - lo).norm() / 2));
  renderer_.setMesh(Pane::Reference, referenceMesh(*analysis_));
}

void Session::update() {
  if (!analysis_) return;
  if (!lod_ || !(selection == extracted_)) {
    lod_ = extract(*analysis_, selection);
    extracted_ = selection;
    ++generation_;
  }
  if (!interacting && std::isnan(lod_->l2Relative)) measureL2(*analysis_, *lod_);
  const bool wantErrors = color == ColorMode::Value;
  if (wantErrors && lod_->vertexError.empty()) measureVertexErrors(*analysis_, *lod_);
  if (meshGeneration_ != generation_ || (wantErrors && !meshHasErrors_) ||
      (wantErrors && meshScale_ != errorScale)) {
    renderer_.setMesh(Pane::Lod, lodMesh(*lod_, errorScale));
    meshGeneration_ = generation_;
    meshHasErrors_ = !lod_->vertexError.empty();
    meshScale_ = errorScale;
  }
  if (smooth) updateSmooth();
}

void Session::updateSmooth() {
  const Analysis& a = *analysis_;
  if (a.bank().scheme != osdmra::Scheme::Loop) {
    smoothOk_ = false;
    smoothStatus_ = "the smooth mode draws Loop limit surfaces; the polyhedral surface is its mesh";
    return;
  }
  const int level = smoothLevel < 0 ? a.levels() : std::min(smoothLevel, a.levels());
  try {
    if (!patches_ || level != smoothLevelBuilt_) {
      patches_.reset();
      smoothOk_ = false;
      smoothLevelBuilt_ = level;
      const osdmra::Hierarchy& h = a.surface->hierarchy();
      patches_ = std::make_unique<LoopPatches>(controlTriangles(a, level), h.numVertices(level),
                                               isolation);
      std::string error;
      if (!renderer_.setPatches(patches_->table(),
                                patches_->points(truncatedControls(a, lod_->approx.keep, level)),
                                error)) {
        smoothStatus_ = error;
        return;
      }
      smoothOk_ = true;
      smoothGeneration_ = generation_;
      smoothStatus_ = std::to_string(patches_->numPatches()) + " patches over M^" +
                      std::to_string(level) + " (" + std::to_string(h.numFaces(level)) +
                      " control triangles)";
    } else if (smoothOk_ && smoothGeneration_ != generation_) {
      renderer_.updatePatchPoints(patches_->points(truncatedControls(a, lod_->approx.keep, level)));
      smoothGeneration_ = generation_;
    }
  } catch (const std::exception& e) {
    smoothOk_ = false;
    smoothStatus_ = std::string("smooth mode failed: ") + e.what();
  }
}

// ---- AnalysisWorker ---------------------------------------------------------------

AnalysisWorker::~AnalysisWorker() {
  cancel_ = true;
  if (thread_.joinable()) thread_.join();
}

void AnalysisWorker::request(const AnalysisRequest& r) {
  if (running_.load()) {
    std::lock_guard<std::mutex> lock(mutex_);
    waiting_ = r;
    cancel_ = true;
    return;
  }
  start(r);
}

namespace {
// Thrown from the progress callback to abandon a superseded analysis; the library
// calls progress on the analysing thread and is exception-safe, so this unwinds
// cleanly through it.
struct Cancelled {};
}  // namespace

void AnalysisWorker::start(const AnalysisRequest& r) {
  if (thread_.joinable()) thread_.join();
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stage_ = "starting";
    error_.clear();
  }
  fraction_ = 0;
  cancel_ = false;
  running_ = true;
  thread_ = std::thread([this, r] {
    std::shared_ptr<const Analysis> result;
    std::string failure;
    try {
      result = analyse(r, [this](const char* stage, double f) {
        if (cancel_.load()) throw Cancelled{};
        {
          std::lock_guard<std::mutex> lock(mutex_);
          stage_ = stage;
        }
        fraction_ = f;
      });
    } catch (const Cancelled&) {
    } catch (const std::exception& e) {
      failure = e.what();
    }
    std::lock_guard<std::mutex> lock(mutex_);
    done_ = result;
    error_ = failure;
    running_ = false;
  });
}

std::shared_ptr<const Analysis> AnalysisWorker::poll() {
  std::shared_ptr<const Analysis> out;
  std::optional<AnalysisRequest> next;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (running_.load()) return nullptr;
    out = std::move(done_);
    done_.reset();
    next = std::move(waiting_);
    waiting_.reset();
  }
  if (next) {
    // A newer request supersedes the one that just finished.
    start(*next);
    return nullptr;
  }
  return out;
}

std::string AnalysisWorker::stage() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return stage_;
}

std::string AnalysisWorker::error() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return error_;
}

// ---- DistanceWorker ---------------------------------------------------------------

DistanceWorker::~DistanceWorker() {
  if (thread_.joinable()) thread_.join();
}

void DistanceWorker::request(std::shared_ptr<const Analysis> a, osdmra::TriMesh mesh, long long tag,
                             int samples) {
  if (running_.load()) return;
  if (thread_.joinable()) thread_.join();
  running_ = true;
  thread_ = std::thread([this, a = std::move(a), mesh = std::move(mesh), tag, samples] {
    osdmra::DistanceOptions opts;
    opts.samples = samples;
    osdmra::SurfaceDistance d;
    try {
      d = osdmra::surfaceDistance(mesh, a->approx().fullResolution(), opts);
    } catch (const std::exception&) {
      d.rmsRelative = d.hausdorffRelative = NAN;
    }
    std::lock_guard<std::mutex> lock(mutex_);
    result_ = std::make_pair(tag, d);
    running_ = false;
  });
}

std::optional<std::pair<long long, osdmra::SurfaceDistance>> DistanceWorker::result() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return result_;
}

}  // namespace viewer
