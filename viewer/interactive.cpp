// The viewer's interactive mode: a GLFW window with a Dear ImGui panel on the left
// (analysis, level of detail, display, smooth mode) and the scene on the right.
// Analysis runs on a worker thread (AnalysisWorker), sampled distances on another.
#include "interactive.h"

#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_opengl3.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <string>
#include <vector>

#include "osdmra/base/error.h"
#include "window.h"

namespace viewer {
namespace {

std::string timestampedName() {
  char name[64];
  const std::time_t t = std::time(nullptr);
  std::strftime(name, sizeof name, "osdmra-viewer-%Y%m%d-%H%M%S.png", std::localtime(&t));
  return name;
}

struct Ui {
  AnalysisRequest request;  // as edited in the panel
  char path[1024] = {};
  DrawSettings draw;
  Camera camera;
  int budget = 4054;
  float epsilon = 0;
  float errorPercent = 0.2f;
  int samples = 20000;
  bool autoMeasure = false;
  std::string message;  // last screenshot or error
  bool saveRequested = false;
  double frameSeconds = 0;  // CPU time of the last frame's update and draw calls
};

// The mesh, scheme and rings: a change of any of these starts a new analysis on the
// worker thread, whose progress or error shows below them.
void analysisSection(Ui& ui, AnalysisWorker& worker) {
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
}

// What the shown analysis is, and its remeshing.
void analysisSummary(const Analysis& a) {
  ImGui::TextWrapped("%s: %s, %s, rings %d, analysed in %.2f s",
                     a.request.path.substr(a.request.path.find_last_of('/') + 1).c_str(),
                     osdmra::describe(*a.surface->recovery()).c_str(),
                     a.bank().scheme == osdmra::Scheme::Loop ? "Loop" : "polyhedral",
                     a.bank().wavelets.rings, a.seconds);
  if (a.remeshing)
    ImGui::TextWrapped(
        "remeshed over %d base faces; distance to the file: RMS %.2g, Hausdorff "
        "%.2g of its diagonal",
        static_cast<int>(a.remeshing->result.base.F.rows()), a.remeshing->distance.rmsRelative,
        a.remeshing->distance.hausdorffRelative);
}

// Level of detail: either slider re-extracts as it moves; errors on demand.
void lodSection(Ui& ui, Session& s, const std::shared_ptr<const Analysis>& a,
                DistanceWorker& distance) {
  ImGui::Separator();
  ImGui::TextUnformatted("Level of detail");
  int kind = s.selection.kind;
  ImGui::RadioButton("budget", &kind, Selection::Budget);
  ImGui::SameLine();
  ImGui::RadioButton("epsilon", &kind, Selection::Epsilon);
  s.selection.kind = static_cast<Selection::Kind>(kind);
  const int minTris = static_cast<int>(a->d().baseFaces.rows());
  if (ImGui::SliderInt("triangles", &ui.budget, minTris, a->inputTriangles(), "%d",
                       ImGuiSliderFlags_Logarithmic))
    s.selection.kind = Selection::Budget;
  if (ImGui::SliderFloat("epsilon", &ui.epsilon, static_cast<float>(a->minImportance),
                         static_cast<float>(a->maxImportance), "%.3e",
                         ImGuiSliderFlags_Logarithmic))
    s.selection.kind = Selection::Epsilon;
  s.selection.budget = ui.budget;
  s.selection.epsilon = ui.epsilon;

  if (const Lod* lod = s.lod()) {
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
}

void displaySection(Ui& ui, Session& s) {
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
  for (auto [name, v] : {std::pair{"front", View::Front},
                         {"side", View::Side},
                         {"top", View::Top},
                         {"iso", View::Iso}}) {
    if (ImGui::Button(name)) ui.camera.setView(v);
    ImGui::SameLine();
  }
  if (ImGui::Button("save PNG (P)")) ui.saveRequested = true;
  ImGui::TextDisabled("frame %.0f ms", ui.frameSeconds * 1e3);
}

void smoothSection(Ui& ui, Session& s, const Analysis& a) {
  ImGui::Separator();
  ImGui::Checkbox("smooth (Loop limit patches)", &s.smooth);
  if (s.smooth) {
    float tess = ui.draw.tessLevel;
    if (ImGui::SliderFloat("tessellation", &tess, 1, 32, "%.0f"))
      ui.draw.tessLevel = std::round(tess);
    int level = s.smoothLevel < 0 ? a.levels() : s.smoothLevel;
    if (ImGui::SliderInt("control level", &level, 0, a.levels())) s.smoothLevel = level;
    if (!s.smoothStatus().empty()) {
      if (!s.smoothReady()) ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1, 0.45f, 0.4f, 1));
      ImGui::TextWrapped("%s", s.smoothStatus().c_str());
      if (!s.smoothReady()) ImGui::PopStyleColor();
    }
  }
}

void panel(Ui& ui, Session& s, AnalysisWorker& worker, DistanceWorker& distance, float width,
           float height) {
  ImGui::SetNextWindowPos(ImVec2(0, 0));
  ImGui::SetNextWindowSize(ImVec2(width, height));
  ImGui::Begin("osdmra", nullptr,
               ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse |
                   ImGuiWindowFlags_NoTitleBar);
  ImGui::TextUnformatted("osdmra-viewer");
  ImGui::Separator();
  analysisSection(ui, worker);
  if (const auto& a = s.analysis()) {
    analysisSummary(*a);
    lodSection(ui, s, a, distance);
    displaySection(ui, s);
    smoothSection(ui, s, *a);
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

}  // namespace

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
    Renderer renderer;
    std::string error;
    if (!renderer.init(error)) throw osdmra::Error(error);
    Session session(renderer);
    AnalysisWorker worker;
    DistanceWorker distance;
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
      DrawSettings draw = ui.draw;
      draw.color = session.color;
      draw.smooth = session.smoothReady();
      if (session.analysis()) draw.levels = session.analysis()->levels();
      // Pane labels, drawn by ImGui over the scene.
      if (const Lod* lod = session.lod()) {
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
                             writePng(name, fbw - x0, fbh, rgb, error)
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
  closeWindow(window);
  return 0;
}

}  // namespace viewer
