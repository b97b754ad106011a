// The viewer's headless modes: one screenshot, or a timed drag of the triangle
// slider. They share the Session (app.h) and the Renderer with the interactive mode
// and draw into an off-screen framebuffer of a hidden window, so they need a display
// (Xvfb will do) but never show anything.
#include "headless.h"

#include <GLFW/glfw3.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "osdmra/base/error.h"
#include "window.h"

namespace viewer {
namespace {

// What both headless modes do first: a GL renderer, the analysis (on this thread),
// and a session with the options' display settings.
std::shared_ptr<const Analysis> prepareHeadless(const Options& o, Renderer& renderer,
                                                Session& session) {
  std::string error;
  if (!renderer.init(error)) throw osdmra::Error(error);
  std::shared_ptr<const Analysis> a;
  a = analyse(o.request);
  session.color = o.color;
  session.errorScale = o.errorPercent / 100;
  session.smooth = o.draw.smooth;
  session.smoothLevel = o.smoothLevel;
  session.adopt(a);
  return a;
}

}  // namespace

int headless(const Options& o) {
  GLFWwindow* window = createWindow(64, 64, false);
  {
    Renderer renderer;
    Session session(renderer);
    const auto a = prepareHeadless(o, renderer, session);
    std::string error;
    session.selection = o.selection;
    session.update();
    if (o.draw.smooth && !session.smoothReady())
      throw osdmra::Error("smooth mode: " + session.smoothStatus());
    DrawSettings draw = o.draw;
    draw.color = o.color;
    draw.levels = a->levels();
    draw.smooth = session.smoothReady();
    Camera camera;
    camera.setView(o.view);
    std::vector<unsigned char> rgb;
    // Errors from setup (uploads, patch tables) count too: check before and after.
    const std::string before = Renderer::glErrors();
    if (!before.empty())
      throw osdmra::Error("OpenGL reported " + before + " while preparing the scene");
    if (!renderer.renderImage(o.width, o.height, camera, draw, rgb, error))
      throw osdmra::Error(error);
    if (!writePng(o.screenshot, o.width, o.height, rgb, error)) throw osdmra::Error(error);
    const Lod& lod = *session.lod();
    std::printf(
        "wrote %s: %d triangles (of %d), %lld of %lld coefficients, L2 error %.3g of the "
        "diagonal%s\n",
        o.screenshot.c_str(), lod.approx.triangles(), a->inputTriangles(), lod.approx.kept,
        lod.approx.total, lod.l2Relative,
        draw.smooth ? (", smooth: " + session.smoothStatus()).c_str() : "");
    if (a->remeshing)
      std::printf(
          "remeshed over %d base faces: distance to %s RMS %.3g, Hausdorff %.3g of its "
          "diagonal\n",
          static_cast<int>(a->remeshing->result.base.F.rows()), a->request.path.c_str(),
          a->remeshing->distance.rmsRelative, a->remeshing->distance.hausdorffRelative);
  }
  closeWindow(window);
  return 0;
}

namespace {

// ---- Slider benchmark -------------------------------------------------------------------
//
// What a frame costs while the triangle slider is dragged: the steps the interactive
// loop runs after each move (Session::update with `interacting` set, so no L2 error:
// re-extraction by the Approximator, normals and float arrays, upload of the level
// of detail; then both panes drawn into the scene rectangle of a WxH window by the
// same Renderer::draw call as the interactive loop's, so the original's pane comes
// from its cached image, the camera being still, unless --no-pane-cache), ended
// by glFinish so the GPU's (here llvmpipe's) work is inside the time. Not included:
// the ImGui panel and the buffer swap of the interactive window; the scene goes to
// an off-screen framebuffer with the window's 4 samples instead of the window.

struct BenchStep {
  long long budget = 0;
  int triangles = 0;
  double extract = 0, upload = 0, draw = 0, frame = 0;  // seconds
};

// The K positions of ImGui's logarithmic slider from lo to hi, then back (without
// repeating the top), as a drag to the right end and back would visit them.
std::vector<long long> sliderPath(long long lo, long long hi, int k) {
  std::vector<long long> up;
  for (int i = 0; i < k; ++i) {
    const double t = static_cast<double>(i) / (k - 1);
    const long long v = std::llround(
        std::exp(std::log(static_cast<double>(lo)) +
                 t * (std::log(static_cast<double>(hi)) - std::log(static_cast<double>(lo)))));
    up.push_back(std::clamp(v, lo, hi));
  }
  std::vector<long long> path = up;
  for (int i = k - 2; i >= 0; --i) path.push_back(up[static_cast<std::size_t>(i)]);
  return path;
}

// `text` as the inside of a JSON string.
std::string jsonEscaped(const std::string& text) {
  std::string out;
  for (const char c : text) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char u[8];
      std::snprintf(u, sizeof u, "\\u%04x", static_cast<unsigned>(c));
      out += u;
    } else {
      out += c;
    }
  }
  return out;
}

// Nearest-rank percentile (p in 0..100) of the values, in milliseconds.
double percentileMs(std::vector<double> v, double p) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  const auto rank = static_cast<std::size_t>(std::ceil(p / 100 * static_cast<double>(v.size())));
  return v[std::clamp<std::size_t>(rank, 1, v.size()) - 1] * 1e3;
}

}  // namespace

int benchSlider(const Options& o) {
  using Clock = std::chrono::steady_clock;
  auto seconds = [](Clock::time_point a, Clock::time_point b) {
    return std::chrono::duration<double>(b - a).count();
  };
  GLFWwindow* window = createWindow(64, 64, false);
  {
    Renderer renderer;
    Session session(renderer);
    const auto a = prepareHeadless(o, renderer, session);
    std::string error;
    session.interacting = true;  // the slider is held for the whole drag
    session.selection.kind = Selection::Budget;

    // The interactive window's layout: panel on the left, scene to its right.
    const int x0 = static_cast<int>(panelWidth(static_cast<float>(o.width)));
    const int sceneW = o.width - x0;
    Camera camera;
    camera.setView(o.view);
    DrawSettings draw = o.draw;
    draw.color = o.color;
    draw.levels = a->levels();
    if (!renderer.bindOffscreen(o.width, o.height, error)) throw osdmra::Error(error);

    const std::vector<long long> path =
        sliderPath(a->d().baseFaces.rows(), a->inputTriangles(), o.benchSteps);
    std::vector<BenchStep> steps;
    long long drawnBefore = 0, cachedBefore = 0;
    for (std::size_t i = 0; i < path.size(); ++i) {
      // The first position is where the drag starts: drawn once, not timed (it also
      // compiles llvmpipe's shader variants and touches the framebuffer).
      const auto t0 = Clock::now();
      session.selection.budget = path[i];
      session.update();
      const auto t1 = Clock::now();
      draw.smooth = session.smoothReady();
      renderer.draw(x0, 0, sceneW, o.height, camera, draw);
      Renderer::finish();
      const auto t2 = Clock::now();
      if (i == 0) {
        drawnBefore = renderer.referenceRedraws();
        cachedBefore = renderer.referenceCacheHits();
        continue;
      }
      BenchStep s;
      s.budget = path[i];
      s.triangles = session.lod()->approx.triangles();
      s.extract = session.lod()->extractSeconds;
      s.upload = seconds(t0, t1) - s.extract;
      s.draw = seconds(t1, t2);
      s.frame = seconds(t0, t2);
      steps.push_back(s);
    }
    const std::string errors = Renderer::glErrors();
    if (!errors.empty()) throw osdmra::Error("OpenGL reported " + errors + " during the benchmark");
    const long long referenceDrawn = renderer.referenceRedraws() - drawnBefore,
                    referenceCached = renderer.referenceCacheHits() - cachedBefore;

    auto column = [&](double BenchStep::*field) {
      std::vector<double> v;
      for (const BenchStep& s : steps) v.push_back(s.*field);
      return v;
    };
    const std::vector<double> frame = column(&BenchStep::frame);
    const std::string gl = Renderer::description();
    const char* scheme = osdmra::schemeName(a->bank().scheme);
    const char* layout = draw.split ? "both panes" : "level of detail only";
    const double median = percentileMs(frame, 50), p90 = percentileMs(frame, 90),
                 worst = percentileMs(frame, 100),
                 extract = percentileMs(column(&BenchStep::extract), 50),
                 upload = percentileMs(column(&BenchStep::upload), 50),
                 drawn = percentileMs(column(&BenchStep::draw), 50);
    if (o.json) {
      std::printf(
          "{\"mesh\": \"%s\", \"renderer\": \"%s\", \"scheme\": \"%s\", \"rings\": %d, "
          "\"input_triangles\": %d, \"window\": [%d, %d], \"scene\": [%d, %d], \"layout\": "
          "\"%s\", \"analysis_seconds\": %.3f, \"steps\": %zu, \"frame_ms\": {\"median\": %.3f, "
          "\"p90\": %.3f, \"max\": %.3f}, \"median_ms\": {\"extract\": %.3f, \"upload\": %.3f, "
          "\"draw\": %.3f}, \"pane_cache\": %s, \"reference_drawn\": %lld, "
          "\"reference_from_cache\": %lld,\n \"per_step\": [",
          jsonEscaped(a->request.path).c_str(), jsonEscaped(gl).c_str(), scheme,
          a->bank().wavelets.rings, a->inputTriangles(), o.width, o.height, sceneW, o.height,
          layout, a->seconds, steps.size(), median, p90, worst, extract, upload, drawn,
          draw.cacheReference ? "true" : "false", referenceDrawn, referenceCached);
      for (std::size_t i = 0; i < steps.size(); ++i) {
        const BenchStep& s = steps[i];
        std::printf(
            "%s\n  {\"budget\": %lld, \"triangles\": %d, \"extract_ms\": %.3f, \"upload_ms\": "
            "%.3f, \"draw_ms\": %.3f, \"frame_ms\": %.3f}",
            i ? "," : "", s.budget, s.triangles, s.extract * 1e3, s.upload * 1e3, s.draw * 1e3,
            s.frame * 1e3);
      }
      std::printf("]}\n");
    } else {
      std::printf(
          "%s: %s, rings %d, %d triangles, analysed in %.2f s (not timed below)\n"
          "renderer: %s\n"
          "slider: %zu steps from %lld to %d triangles and back; scene %dx%d (%s) of a %dx%d "
          "window\n"
          "frame ms: median %.1f, p90 %.1f, max %.1f\n"
          "median ms: extraction %.1f, normals+upload %.1f, draw+glFinish %.1f\n"
          "original's pane (timed steps): drawn %lld times, from its cached image %lld times%s\n",
          a->request.path.c_str(), scheme, a->bank().wavelets.rings, a->inputTriangles(),
          a->seconds, gl.c_str(), steps.size(), path.front(), a->inputTriangles(), sceneW, o.height,
          layout, o.width, o.height, median, p90, worst, extract, upload, drawn, referenceDrawn,
          referenceCached, draw.cacheReference ? "" : " (--no-pane-cache)");
    }
  }
  closeWindow(window);
  return 0;
}

}  // namespace viewer
