// osdmra-viewer: levels of detail of a wavelet-analysed subdivision surface, drawn
// beside the original at the same projected size (the paper's Figures 8-10).
//
//   osdmra-viewer [MESH] [options]                 interactive (GLFW + Dear ImGui)
//   osdmra-viewer [MESH] --screenshot OUT.png ...  headless: render, write, exit
//   osdmra-viewer [MESH] --bench-slider K ...      headless: time a triangle-slider drag
//
// Both modes share the Session (app.h) and the Renderer; the headless mode draws
// into an off-screen framebuffer of a hidden window, so it needs a display (Xvfb
// will do) but never shows anything.
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_opengl3.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <string>
#include <vector>

#include "app.h"
#include "camera.h"
#include "osdmra/base/error.h"
#include "renderer.h"

namespace {

using viewer::ColorMode;

const char* kUsage =
    "usage: osdmra-viewer [MESH] [options]\n"
    "\n"
    "Shows levels of detail of MESH (a triangle mesh with subdivision connectivity;\n"
    "default: the bundled igea-oct6.obj) beside the full-resolution surface.\n"
    "\n"
    "  --budget N          triangle budget of the level of detail (default 4054)\n"
    "  --epsilon E         keep coefficients of importance >= E instead of a budget\n"
    "  --scheme S          loop (default) or linear (polyhedral)\n"
    "  --rings R           quasi-wavelet rings, 0..4 (default 1)\n"
    "  --remesh            MESH has no subdivision connectivity: remesh it first\n"
    "                      (osdmra remesh) with --base-faces N (default 300),\n"
    "                      --levels J (default 5) and --feature-angle A (default 70)\n"
    "  --view V            front (default), side, top or iso\n"
    "  --color C           plain (default), level or error\n"
    "  --error-scale P     error colouring: red at P percent of the diagonal (default 0.2)\n"
    "  --layout L          split (default: original left, level of detail right) or lod\n"
    "  --wireframe         draw the edges over the surface\n"
    "  --smooth            draw the truncated surface as Loop limit patches (OpenSubdiv)\n"
    "  --tess L            tessellation level of the smooth mode, 1..32 (default 1)\n"
    "  --smooth-level J    control mesh level of the smooth mode (default: finest)\n"
    "  --screenshot OUT    headless: render to the PNG OUT and exit\n"
    "  --size WxH          headless image size (default 1200x600; with --bench-slider\n"
    "                      the window size, default 1600x900 as the interactive one)\n"
    "  --bench-slider K    headless: after the analysis, move the triangle slider through\n"
    "                      K log-spaced values up to all triangles and back, as a drag,\n"
    "                      and report the frame times (extraction, upload, draw); exit\n"
    "  --json              with --bench-slider: one JSON object, with every step\n"
    "  --no-pane-cache     redraw the original's pane every frame instead of keeping it\n"
    "                      as an image while the camera and display options are unchanged\n"
    "\n"
    "Interactive: drag to rotate, right-drag to pan, wheel to zoom, P saves a PNG,\n"
    "Esc quits.\n";

struct Options {
  std::string mesh;
  viewer::Selection selection;
  viewer::AnalysisRequest request;
  viewer::View view = viewer::View::Front;
  viewer::DrawSettings draw;
  ColorMode color = ColorMode::Plain;
  double errorPercent = 0.2;
  int smoothLevel = -1;
  std::string screenshot;
  int width = 1200, height = 600;
  bool sizeGiven = false;
  int benchSteps = 0;  ///< --bench-slider K; 0: not benchmarking
  bool json = false;
};

[[noreturn]] void fail(const std::string& message) {
  std::fprintf(stderr, "osdmra-viewer: %s\n", message.c_str());
  std::exit(1);
}

long long integer(const std::string& name, const std::string& text, long long lo, long long hi) {
  char* end = nullptr;
  errno = 0;
  const long long v = std::strtoll(text.c_str(), &end, 10);
  if (text.empty() || *end || errno || v < lo || v > hi)
    fail(name + " needs an integer in " + std::to_string(lo) + ".." + std::to_string(hi) +
         ", got '" + text + "'");
  return v;
}

double real(const std::string& name, const std::string& text) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || *end || !std::isfinite(v) || v < 0)
    fail(name + " needs a non-negative number, got '" + text + "'");
  return v;
}

Options parse(int argc, char** argv) {
  Options o;
  std::vector<std::string> args(argv + 1, argv + argc);
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= args.size()) fail(a + " needs a value");
      return args[++i];
    };
    if (a == "-h" || a == "--help") {
      std::fputs(kUsage, stdout);
      std::exit(0);
    } else if (a == "--budget") {
      o.selection.kind = viewer::Selection::Budget;
      o.selection.budget = integer(a, value(), 1, 1LL << 40);
    } else if (a == "--epsilon") {
      o.selection.kind = viewer::Selection::Epsilon;
      o.selection.epsilon = real(a, value());
    } else if (a == "--scheme") {
      try {
        o.request.scheme = osdmra::parseScheme(value());
      } catch (const osdmra::Error& e) {
        fail(std::string("--scheme: ") + e.what());
      }
    } else if (a == "--rings") {
      o.request.rings = static_cast<int>(integer(a, value(), 0, 4));
    } else if (a == "--remesh") {
      o.request.remesh = true;
    } else if (a == "--base-faces") {
      o.request.remeshOptions.baseFaces = static_cast<int>(integer(a, value(), 4, 1 << 24));
    } else if (a == "--levels") {
      o.request.remeshOptions.levels = static_cast<int>(integer(a, value(), 0, 8));
    } else if (a == "--feature-angle") {
      o.request.remeshOptions.featureAngle = real(a, value());
    } else if (a == "--view") {
      const std::string s = value();
      if (!viewer::parseView(s, o.view))
        fail("--view must be front, side, top or iso, got '" + s + "'");
    } else if (a == "--color") {
      const std::string s = value();
      if (s == "plain")
        o.color = ColorMode::Plain;
      else if (s == "level")
        o.color = ColorMode::Level;
      else if (s == "error")
        o.color = ColorMode::Value;
      else
        fail("--color must be plain, level or error, got '" + s + "'");
    } else if (a == "--error-scale") {
      o.errorPercent = real(a, value());
      if (!(o.errorPercent > 0)) fail("--error-scale needs a positive percentage");
    } else if (a == "--layout") {
      const std::string s = value();
      if (s != "split" && s != "lod") fail("--layout must be split or lod, got '" + s + "'");
      o.draw.split = s == "split";
    } else if (a == "--wireframe") {
      o.draw.wireframe = true;
    } else if (a == "--smooth") {
      o.draw.smooth = true;
    } else if (a == "--tess") {
      o.draw.tessLevel = static_cast<float>(integer(a, value(), 1, 32));
    } else if (a == "--smooth-level") {
      o.smoothLevel = static_cast<int>(integer(a, value(), 0, 15));
    } else if (a == "--screenshot") {
      o.screenshot = value();
      if (o.screenshot.empty()) fail("--screenshot needs a file name");
    } else if (a == "--size") {
      const std::string s = value();
      int w = 0, h = 0;
      char extra = 0;
      if (std::sscanf(s.c_str(), "%dx%d%c", &w, &h, &extra) != 2 || w < 16 || h < 16 || w > 8192 ||
          h > 8192)
        fail("--size needs WxH with 16..8192 pixels each, got '" + s + "'");
      o.width = w, o.height = h;
      o.sizeGiven = true;
    } else if (a == "--bench-slider") {
      o.benchSteps = static_cast<int>(integer(a, value(), 2, 100000));
    } else if (a == "--json") {
      o.json = true;
    } else if (a == "--no-pane-cache") {
      o.draw.cacheReference = false;
    } else if (a.size() > 1 && a[0] == '-') {
      fail("unknown option " + a + " (see --help)");
    } else if (o.mesh.empty()) {
      o.mesh = a;
    } else {
      fail("more than one mesh given ('" + o.mesh + "' and '" + a + "')");
    }
  }
  if (o.benchSteps && !o.screenshot.empty())
    fail("--bench-slider and --screenshot cannot be combined");
  if (o.json && !o.benchSteps) fail("--json needs --bench-slider");
  if (o.benchSteps && o.selection.kind == viewer::Selection::Epsilon)
    fail("--bench-slider moves the triangle slider; --epsilon does not apply");
  if (o.benchSteps && !o.sizeGiven) o.width = 1600, o.height = 900;
  return o;
}

// The interactive window's panel width (window coordinates); the scene is drawn to
// its right.
float panelWidth(float windowWidth) {
  return std::min(380.0f, windowWidth * 0.4f);
}

// ---- GL context ---------------------------------------------------------------------

std::string glfwError;

void onGlfwError(int, const char* description) {
  glfwError = description;
}

// Core profile 4.1 (tessellation shaders for the smooth mode) when the driver has
// it, 3.3 otherwise.
GLFWwindow* createWindow(int w, int h, bool visible) {
  glfwSetErrorCallback(onGlfwError);
  if (!glfwInit()) fail("no OpenGL: cannot initialise GLFW (" + glfwError + ")");
  for (const auto& [major, minor] : {std::pair{4, 1}, std::pair{3, 3}}) {
    glfwDefaultWindowHints();
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, major);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, minor);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    glfwWindowHint(GLFW_VISIBLE, visible ? GLFW_TRUE : GLFW_FALSE);
    glfwWindowHint(GLFW_SAMPLES, visible ? 4 : 0);
    if (GLFWwindow* w0 = glfwCreateWindow(w, h, "osdmra-viewer", nullptr, nullptr)) {
      glfwMakeContextCurrent(w0);
      return w0;
    }
  }
  const std::string why = glfwError;
  glfwTerminate();
  fail("no OpenGL 3.3 core context (" + why + ")");
}

// ---- Headless -------------------------------------------------------------------------

// What both headless modes do first: a GL renderer, the analysis (on this thread),
// and a session with the options' display settings.
std::shared_ptr<const viewer::Analysis> prepareHeadless(const Options& o,
                                                        viewer::Renderer& renderer,
                                                        viewer::Session& session) {
  std::string error;
  if (!renderer.init(error)) fail(error);
  std::shared_ptr<const viewer::Analysis> a;
  try {
    a = viewer::analyse(o.request);
  } catch (const std::exception& e) {
    fail(e.what());
  }
  session.color = o.color;
  session.errorScale = o.errorPercent / 100;
  session.smooth = o.draw.smooth;
  session.smoothLevel = o.smoothLevel;
  session.adopt(a);
  return a;
}

int headless(const Options& o) {
  GLFWwindow* window = createWindow(64, 64, false);
  {
    viewer::Renderer renderer;
    viewer::Session session(renderer);
    const auto a = prepareHeadless(o, renderer, session);
    std::string error;
    session.selection = o.selection;
    try {
      session.update();
    } catch (const std::exception& e) {
      fail(e.what());
    }
    if (o.draw.smooth && !session.smoothReady()) fail("smooth mode: " + session.smoothStatus());
    viewer::DrawSettings draw = o.draw;
    draw.color = o.color;
    draw.levels = a->levels();
    draw.smooth = session.smoothReady();
    viewer::Camera camera;
    camera.setView(o.view);
    std::vector<unsigned char> rgb;
    // Errors from setup (uploads, patch tables) count too: check before and after.
    const std::string before = viewer::Renderer::glErrors();
    if (!before.empty()) fail("OpenGL reported " + before + " while preparing the scene");
    if (!renderer.renderImage(o.width, o.height, camera, draw, rgb, error)) fail(error);
    if (!viewer::writePng(o.screenshot, o.width, o.height, rgb, error)) fail(error);
    const viewer::Lod& lod = *session.lod();
    std::printf(
        "wrote %s: %d triangles (of %d), %lld of %lld coefficients, L2 error %.3g of the "
        "diagonal%s\n",
        o.screenshot.c_str(), lod.approx.triangles(), a->inputTriangles(), lod.approx.kept,
        lod.approx.total, lod.l2Relative,
        draw.smooth ? (", smooth: " + session.smoothStatus()).c_str() : "");
    if (a->request.remesh)
      std::printf("remeshed over %d base faces: distance to %s RMS %.3g, Hausdorff %.3g of its "
                  "diagonal\n",
                  a->remeshBaseFaces, a->request.path.c_str(), a->remeshRms, a->remeshHausdorff);
  }
  glfwDestroyWindow(window);
  glfwTerminate();
  return 0;
}

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

int benchSlider(const Options& o) {
  using Clock = std::chrono::steady_clock;
  auto seconds = [](Clock::time_point a, Clock::time_point b) {
    return std::chrono::duration<double>(b - a).count();
  };
  GLFWwindow* window = createWindow(64, 64, false);
  {
    viewer::Renderer renderer;
    viewer::Session session(renderer);
    const auto a = prepareHeadless(o, renderer, session);
    std::string error;
    session.interacting = true;  // the slider is held for the whole drag
    session.selection.kind = viewer::Selection::Budget;

    // The interactive window's layout: panel on the left, scene to its right.
    const int x0 = static_cast<int>(panelWidth(static_cast<float>(o.width)));
    const int sceneW = o.width - x0;
    viewer::Camera camera;
    camera.setView(o.view);
    viewer::DrawSettings draw = o.draw;
    draw.color = o.color;
    draw.levels = a->levels();
    if (!renderer.bindOffscreen(o.width, o.height, error)) fail(error);

    const std::vector<long long> path =
        sliderPath(a->d->baseFaces.rows(), a->inputTriangles(), o.benchSteps);
    std::vector<BenchStep> steps;
    long long drawnBefore = 0, cachedBefore = 0;
    for (std::size_t i = 0; i < path.size(); ++i) {
      // The first position is where the drag starts: drawn once, not timed (it also
      // compiles llvmpipe's shader variants and touches the framebuffer).
      const auto t0 = Clock::now();
      session.selection.budget = path[i];
      try {
        session.update();
      } catch (const std::exception& e) {
        fail(e.what());
      }
      const auto t1 = Clock::now();
      draw.smooth = session.smoothReady();
      renderer.draw(x0, 0, sceneW, o.height, camera, draw);
      viewer::Renderer::finish();
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
    const std::string errors = viewer::Renderer::glErrors();
    if (!errors.empty()) fail("OpenGL reported " + errors + " during the benchmark");
    const long long referenceDrawn = renderer.referenceRedraws() - drawnBefore,
                    referenceCached = renderer.referenceCacheHits() - cachedBefore;

    auto column = [&](double BenchStep::*field) {
      std::vector<double> v;
      for (const BenchStep& s : steps) v.push_back(s.*field);
      return v;
    };
    const std::vector<double> frame = column(&BenchStep::frame);
    const std::string gl = viewer::Renderer::description();
    const char* scheme = osdmra::schemeName(a->bank->scheme);
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
          a->bank->wavelets.rings, a->inputTriangles(), o.width, o.height, sceneW, o.height, layout,
          a->seconds, steps.size(), median, p90, worst, extract, upload, drawn,
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
          a->request.path.c_str(), scheme, a->bank->wavelets.rings, a->inputTriangles(), a->seconds,
          gl.c_str(), steps.size(), path.front(), a->inputTriangles(), sceneW, o.height, layout,
          o.width, o.height, median, p90, worst, extract, upload, drawn, referenceDrawn,
          referenceCached, draw.cacheReference ? "" : " (--no-pane-cache)");
    }
  }
  glfwDestroyWindow(window);
  glfwTerminate();
  return 0;
}

// ---- Interactive ----------------------------------------------------------------------

std::string timestampedName() {
  char name[64];
  const std::time_t t = std::time(nullptr);
  std::strftime(name, sizeof name, "osdmra-viewer-%Y%m%d-%H%M%S.png", std::localtime(&t));
  return name;
}

struct Ui {
  viewer::AnalysisRequest request;  // as edited in the panel
  char path[1024] = {};
  viewer::DrawSettings draw;
  viewer::Camera camera;
  int budget = 4054;
  float epsilon = 0;
  float errorPercent = 0.2f;
  int samples = 20000;
  bool autoMeasure = false;
  std::string message;  // last screenshot or error
  bool saveRequested = false;
  double frameSeconds = 0;  // CPU time of the last frame's update and draw calls
};

void panel(Ui& ui, viewer::Session& s, viewer::AnalysisWorker& worker,
           viewer::DistanceWorker& distance, float width, float height) {
  ImGui::SetNextWindowPos(ImVec2(0, 0));
  ImGui::SetNextWindowSize(ImVec2(width, height));
  ImGui::Begin("osdmra", nullptr,
               ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse |
                   ImGuiWindowFlags_NoTitleBar);
  ImGui::TextUnformatted("osdmra-viewer");
  ImGui::Separator();

  // Analysis: a change of any of these starts a new one on the worker thread.
  bool reanalyse =
      ImGui::InputText("mesh", ui.path, sizeof ui.path, ImGuiInputTextFlags_EnterReturnsTrue);
  int scheme = ui.request.scheme == osdmra::Scheme::Loop ? 0 : 1;
  reanalyse |= ImGui::Button("Load");
  ImGui::SameLine();
  reanalyse |= ImGui::RadioButton("Loop", &scheme, 0);
  ImGui::SameLine();
  reanalyse |= ImGui::RadioButton("polyhedral", &scheme, 1);
  reanalyse |= ImGui::SliderInt("rings", &ui.request.rings, 0, 4);
  if (reanalyse) {
    ui.request.scheme = scheme == 0 ? osdmra::Scheme::Loop : osdmra::Scheme::Linear;
    ui.request.path = ui.path;
    worker.request(ui.request);
  }
  if (worker.busy()) {
    const std::string label = worker.stage();
    ImGui::ProgressBar(static_cast<float>(worker.fraction()), ImVec2(-1, 0), label.c_str());
  } else if (!worker.error().empty()) {
    ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1, 0.45f, 0.4f, 1));
    ImGui::TextWrapped("%s", worker.error().c_str());
    ImGui::PopStyleColor();
  }
  const auto& a = s.analysis();
  if (!a) {
    ImGui::End();
    return;
  }
  ImGui::TextWrapped("%s: %s, %s, rings %d, analysed in %.2f s",
                     a->request.path.substr(a->request.path.find_last_of('/') + 1).c_str(),
                     osdmra::describe(a->surface->recovery).c_str(),
                     a->bank->scheme == osdmra::Scheme::Loop ? "Loop" : "polyhedral",
                     a->bank->wavelets.rings, a->seconds);
  if (a->request.remesh)
    ImGui::TextWrapped("remeshed over %d base faces; distance to the file: RMS %.2g, Hausdorff "
                       "%.2g of its diagonal",
                       a->remeshBaseFaces, a->remeshRms, a->remeshHausdorff);

  // Level of detail: either slider re-extracts as it moves.
  ImGui::Separator();
  ImGui::TextUnformatted("Level of detail");
  int kind = s.selection.kind;
  ImGui::RadioButton("budget", &kind, viewer::Selection::Budget);
  ImGui::SameLine();
  ImGui::RadioButton("epsilon", &kind, viewer::Selection::Epsilon);
  s.selection.kind = static_cast<viewer::Selection::Kind>(kind);
  const int minTris = static_cast<int>(a->d->baseFaces.rows());
  if (ImGui::SliderInt("triangles", &ui.budget, minTris, a->inputTriangles(), "%d",
                       ImGuiSliderFlags_Logarithmic))
    s.selection.kind = viewer::Selection::Budget;
  if (ImGui::SliderFloat("epsilon", &ui.epsilon, static_cast<float>(a->minImportance),
                         static_cast<float>(a->maxImportance), "%.3e",
                         ImGuiSliderFlags_Logarithmic))
    s.selection.kind = viewer::Selection::Epsilon;
  s.selection.budget = ui.budget;
  s.selection.epsilon = ui.epsilon;

  if (const viewer::Lod* lod = s.lod()) {
    ImGui::Text("%d triangles of %d (%d red, %d green)", lod->approx.triangles(),
                a->inputTriangles(), lod->approx.lod.redTriangles, lod->approx.lod.greenTriangles);
    ImGui::Text("%lld of %lld coefficients kept", lod->approx.kept, lod->approx.total);
    if (std::isnan(lod->l2Relative)) {
      ImGui::Text("extraction %.1f ms", lod->extractSeconds * 1e3);
      ImGui::TextDisabled("L2 error: measured when the slider is released");
    } else {
      ImGui::Text("extraction %.1f ms, L2 error %.1f ms", lod->extractSeconds * 1e3,
                  lod->l2Seconds * 1e3);
      ImGui::Text("L2 error (RMS) %.3e of the diagonal", lod->l2Relative);
    }
    // The sampled distances take longer than a frame: measured on a worker, shown
    // only while they describe the mesh on screen.
    ImGui::SliderInt("samples", &ui.samples, 1000, 200000, "%d", ImGuiSliderFlags_Logarithmic);
    const auto result = distance.result();
    const bool current = result && result->first == s.generation();
    bool measure = false;
    if (distance.busy()) {
      ImGui::TextUnformatted("measuring...");
    } else {
      measure = ImGui::Button("Measure RMS / Hausdorff");
      ImGui::SameLine();
      ImGui::Checkbox("auto", &ui.autoMeasure);
      measure |= ui.autoMeasure && !current;
    }
    if (measure) distance.request(a, lod->approx.mesh, s.generation(), ui.samples);
    if (current)
      ImGui::Text("sampled RMS %.3e, Hausdorff %.3e", result->second.rmsRelative,
                  result->second.hausdorffRelative);
    else
      ImGui::TextDisabled("sampled RMS, Hausdorff: not measured");
  }

  // Display.
  ImGui::Separator();
  ImGui::TextUnformatted("Display");
  ImGui::Checkbox("split view", &ui.draw.split);
  ImGui::SameLine();
  ImGui::Checkbox("wireframe", &ui.draw.wireframe);
  int color = static_cast<int>(s.color);
  ImGui::RadioButton("shaded", &color, 0);
  ImGui::SameLine();
  ImGui::RadioButton("level", &color, 1);
  ImGui::SameLine();
  ImGui::RadioButton("local error", &color, 2);
  s.color = static_cast<ColorMode>(color);
  if (s.color == ColorMode::Value) {
    ImGui::SliderFloat("error scale %", &ui.errorPercent, 0.01f, 5.0f, "%.3f",
                       ImGuiSliderFlags_Logarithmic);
    ImGui::TextDisabled("vertex distance to the full surface; red = %.3g%% of the diagonal",
                        ui.errorPercent);
  }
  s.errorScale = ui.errorPercent / 100.0;
  for (auto [name, v] : {std::pair{"front", viewer::View::Front},
                         {"side", viewer::View::Side},
                         {"top", viewer::View::Top},
                         {"iso", viewer::View::Iso}}) {
    if (ImGui::Button(name)) ui.camera.setView(v);
    ImGui::SameLine();
  }
  if (ImGui::Button("save PNG (P)")) ui.saveRequested = true;
  ImGui::TextDisabled("frame %.0f ms", ui.frameSeconds * 1e3);

  // Smooth mode.
  ImGui::Separator();
  ImGui::Checkbox("smooth (Loop limit patches)", &s.smooth);
  if (s.smooth) {
    float tess = ui.draw.tessLevel;
    if (ImGui::SliderFloat("tessellation", &tess, 1, 32, "%.0f"))
      ui.draw.tessLevel = std::round(tess);
    int level = s.smoothLevel < 0 ? a->levels() : s.smoothLevel;
    if (ImGui::SliderInt("control level", &level, 0, a->levels())) s.smoothLevel = level;
    if (!s.smoothStatus().empty()) {
      if (!s.smoothReady()) ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1, 0.45f, 0.4f, 1));
      ImGui::TextWrapped("%s", s.smoothStatus().c_str());
      if (!s.smoothReady()) ImGui::PopStyleColor();
    }
  }
  if (!ui.message.empty()) {
    ImGui::Separator();
    ImGui::TextWrapped("%s", ui.message.c_str());
  }
  ImGui::End();
}

// Trackball, pan and zoom from ImGui's view of the mouse, when the panel does not
// want it. Coordinates are normalised to the scene rectangle (or one pane of it).
void cameraInput(Ui& ui, float x0, float w, float h) {
  const ImGuiIO& io = ImGui::GetIO();
  if (io.WantCaptureMouse) return;
  const float paneW = ui.draw.split ? w / 2 : w;
  auto normalised = [&](ImVec2 p) {
    float px = p.x - x0;
    if (ui.draw.split && px > paneW) px -= paneW;
    return Eigen::Vector2f(2 * px / paneW - 1, 1 - 2 * p.y / h);
  };
  if (ImGui::IsMouseDragging(ImGuiMouseButton_Left, 0)) {
    const ImVec2 p = io.MousePos, q = ImVec2(p.x - io.MouseDelta.x, p.y - io.MouseDelta.y);
    ui.camera.drag(normalised(q), normalised(p));
  }
  if (ImGui::IsMouseDragging(ImGuiMouseButton_Right, 0))
    ui.camera.pan +=
        Eigen::Vector2f(io.MouseDelta.x, -io.MouseDelta.y) *
        (2.0f * ui.camera.distance * std::tan(ui.camera.fovYDegrees * 3.14159265f / 360) / h);
  if (io.MouseWheel != 0) ui.camera.zoom(io.MouseWheel);
}

// Input events seen so far. Counted by our own callbacks, which ImGui's backend
// chains to, so the loop can sleep while nothing happens (the machine is shared)
// and still draw the few frames ImGui needs after each event.
int inputEvents = 0;

void countEvents(GLFWwindow* window) {
  glfwSetCursorPosCallback(window, [](GLFWwindow*, double, double) { ++inputEvents; });
  glfwSetMouseButtonCallback(window, [](GLFWwindow*, int, int, int) { ++inputEvents; });
  glfwSetScrollCallback(window, [](GLFWwindow*, double, double) { ++inputEvents; });
  glfwSetKeyCallback(window, [](GLFWwindow*, int, int, int, int) { ++inputEvents; });
  glfwSetCharCallback(window, [](GLFWwindow*, unsigned) { ++inputEvents; });
  glfwSetWindowSizeCallback(window, [](GLFWwindow*, int, int) { ++inputEvents; });
}

int interactive(const Options& o) {
  GLFWwindow* window = createWindow(1600, 900, true);
  glfwSwapInterval(1);
  countEvents(window);
  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;
  ImGui::StyleColorsDark();
  ImGui_ImplGlfw_InitForOpenGL(window, true);
  ImGui_ImplOpenGL3_Init("#version 330 core");
  {
    viewer::Renderer renderer;
    std::string error;
    if (!renderer.init(error)) fail(error);
    viewer::Session session(renderer);
    viewer::AnalysisWorker worker;
    viewer::DistanceWorker distance;
    Ui ui;
    ui.request = o.request;
    ui.request.path = o.mesh;
    std::snprintf(ui.path, sizeof ui.path, "%s", o.mesh.c_str());
    ui.draw = o.draw;
    ui.camera.setView(o.view);
    ui.budget = static_cast<int>(std::min<long long>(o.selection.budget, 1 << 30));
    ui.epsilon = static_cast<float>(o.selection.epsilon);
    ui.errorPercent = static_cast<float>(o.errorPercent);
    session.selection = o.selection;
    session.color = o.color;
    session.smooth = o.draw.smooth;
    session.smoothLevel = o.smoothLevel;
    worker.request(ui.request);

    int seenEvents = -1, activeFrames = 0;
    while (!glfwWindowShouldClose(window)) {
      if (inputEvents != seenEvents) activeFrames = 4;
      seenEvents = inputEvents;
      if (activeFrames > 0) {
        --activeFrames;
        glfwPollEvents();
      } else {
        glfwWaitEventsTimeout(worker.busy() || distance.busy() ? 0.05 : 0.5);
      }
      if (auto a = worker.poll()) {
        session.adopt(a);
        // An epsilon outside this surface's importances would select all or nothing.
        if (!(ui.epsilon >= a->minImportance && ui.epsilon <= a->maxImportance)) {
          ui.epsilon = static_cast<float>(std::sqrt(a->minImportance * a->maxImportance));
          session.selection.epsilon = ui.epsilon;
        }
      }
      const double frameStart = glfwGetTime();
      // Settings the panel changed last frame take effect here, before the panel
      // reports on them, so its numbers always describe the mesh on screen.
      try {
        session.update();
      } catch (const std::exception& e) {
        ui.message = e.what();
      }
      ImGui_ImplOpenGL3_NewFrame();
      ImGui_ImplGlfw_NewFrame();
      ImGui::NewFrame();
      int fbw = 0, fbh = 0, ww = 0, wh = 0;
      glfwGetFramebufferSize(window, &fbw, &fbh);
      glfwGetWindowSize(window, &ww, &wh);
      const float panelW = panelWidth(static_cast<float>(ww));
      panel(ui, session, worker, distance, panelW, static_cast<float>(wh));
      cameraInput(ui, panelW, ww - panelW, static_cast<float>(wh));
      if (!ImGui::GetIO().WantCaptureKeyboard) {
        if (ImGui::IsKeyPressed(GLFW_KEY_P, false)) ui.saveRequested = true;
        if (ImGui::IsKeyPressed(GLFW_KEY_ESCAPE, false)) glfwSetWindowShouldClose(window, 1);
      }
      viewer::DrawSettings draw = ui.draw;
      draw.color = session.color;
      draw.smooth = session.smoothReady();
      if (session.analysis()) draw.levels = session.analysis()->levels();
      // Pane labels, drawn by ImGui over the scene.
      if (const viewer::Lod* lod = session.lod()) {
        const float sceneW = ww - panelW, x1 = panelW + (draw.split ? sceneW / 2 : 0);
        ImDrawList* dl = ImGui::GetForegroundDrawList();
        const ImU32 c = IM_COL32(230, 230, 230, 255);
        char text[128];
        if (draw.split) {
          std::snprintf(text, sizeof text, "original: %d triangles",
                        session.analysis()->inputTriangles());
          dl->AddText(ImVec2(panelW + 12, 10), c, text);
        }
        std::snprintf(text, sizeof text, "%s: %d triangles",
                      draw.smooth ? "smooth" : "level of detail", lod->approx.triangles());
        dl->AddText(ImVec2(x1 + 12, 10), c, text);
      }
      session.interacting = ImGui::IsAnyItemActive();
      ImGui::Render();

      const float sx = ww > 0 ? static_cast<float>(fbw) / ww : 1;
      const int x0 = static_cast<int>(panelW * sx);
      glViewport(0, 0, fbw, fbh);
      renderer.draw(x0, 0, fbw - x0, fbh, ui.camera, draw);
      if (ui.saveRequested && session.lod()) {
        // The scene alone, at the scene's size, through the same path as headless.
        ui.saveRequested = false;
        std::vector<unsigned char> rgb;
        const std::string name = timestampedName();
        ui.message = renderer.renderImage(fbw - x0, fbh, ui.camera, draw, rgb, error) &&
                             viewer::writePng(name, fbw - x0, fbh, rgb, error)
                         ? "saved " + name
                         : error;
      }
      ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
      glfwSwapBuffers(window);
      ui.frameSeconds = glfwGetTime() - frameStart;
    }
  }
  ImGui_ImplOpenGL3_Shutdown();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
  glfwDestroyWindow(window);
  glfwTerminate();
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  Options o = parse(argc, argv);
  if (o.mesh.empty()) {
    try {
      o.mesh = viewer::defaultMesh();
    } catch (const std::exception& e) {
      fail(e.what());
    }
  }
  o.request.path = o.mesh;
  if (o.benchSteps) return benchSlider(o);
  return o.screenshot.empty() ? interactive(o) : headless(o);
}
