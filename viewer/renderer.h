// Renderer: OpenGL 3.3+ core drawing of triangle meshes and Loop limit patches.
//
// It knows meshes, not the library: the app hands it float arrays (DrawMesh) and,
// for the smooth mode, an OpenSubdiv Far::PatchTable with the positions of its
// points; it draws them Gouraud-shaded, optionally with a wireframe overlay,
// coloured plainly, by hierarchy level (one value per triangle) or by a per-vertex
// value through a colour map. Two panes can be shown side by side with one camera
// (the reference on the left, the level of detail on the right), so both have the
// same projected size. Everything can also be drawn into an off-screen framebuffer
// and read back, which is how screenshots and the headless mode work.
//
// All methods need the GL context current on the calling thread.
#pragma once

#include <opensubdiv/far/patchTable.h>

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "camera.h"

namespace viewer {

/// A triangle mesh in GPU-ready form.
struct DrawMesh {
  std::vector<float> positions;        ///< 3 per vertex
  std::vector<float> normals;          ///< 3 per vertex, unit length
  std::vector<float> vertexValue;      ///< 1 per vertex in [0, 1] (colour map), or empty
  std::vector<std::uint32_t> indices;  ///< 3 per triangle
  std::vector<float> faceLevel;        ///< 1 per triangle (hierarchy level), or empty
  int triangles() const { return static_cast<int>(indices.size() / 3); }
};

enum class ColorMode { Plain, Level, Value };

struct DrawSettings {
  bool split = true;  ///< reference left, level of detail right
  bool wireframe = false;
  ColorMode color = ColorMode::Plain;
  int levels = 1;       ///< J: level colours are spread over 0..J
  bool smooth = false;  ///< right pane: the limit patches instead of the mesh
  /// OpenSubdiv's uniform tessellation level: patches of the control mesh itself get
  /// twice this many segments per edge, patches from adaptive refinement fewer. 1
  /// keeps llvmpipe near interactive on the 32k patches of a level-6 control mesh.
  float tessLevel = 1.0f;
  /// Split view: keep the reference pane as an image (an off-screen colour texture,
  /// rendered with the target's multisampling and resolved) and draw that while the
  /// camera, pane size, display options and reference mesh are unchanged, instead of
  /// redrawing the full-resolution mesh every frame. False always redraws the mesh.
  bool cacheReference = true;
};

enum class Pane { Reference, Lod };

class Renderer {
 public:
  Renderer();
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  /// Compiles the mesh shaders; false (and why) when the context cannot run them.
  bool init(std::string& error);

  /// The model's bounding sphere: it is drawn centred and scaled to unit radius.
  void setBounds(const Eigen::Vector3f& center, float radius);
  void setMesh(Pane pane, const DrawMesh& mesh);

  /// Smooth mode: uploads the patches (the table is copied to the GPU and need not
  /// outlive the call) and compiles the patch shaders on first use. False (and why)
  /// when the context has no tessellation shaders or OpenSubdiv's shaders fail.
  bool setPatches(const OpenSubdiv::Far::PatchTable& table, const std::vector<float>& points,
                  std::string& error);
  /// New positions for the points of the patches last set (same count).
  void updatePatchPoints(const std::vector<float>& points);
  bool hasPatches() const;
  /// Patches drawn in the last frame (0 when none).
  int patchCount() const;
  /// How many times draw() has drawn the reference mesh (into its cache or directly)
  /// and how many times it drew the reference pane from the cache instead.
  long long referenceRedraws() const;
  long long referenceCacheHits() const;

  /// Draws into the bound framebuffer, in the window rectangle (x, y, w, h).
  /// With s.split and s.cacheReference the reference pane comes from its cached
  /// image when nothing it depends on changed (see referenceRedraws()).
  void draw(int x, int y, int w, int h, const Camera& camera, const DrawSettings& s);

  /// Binds an off-screen multisampled framebuffer of w x h pixels (made, or remade
  /// when the size changes) for draw(). False (and why) when it cannot be made.
  bool bindOffscreen(int w, int h, std::string& error);
  /// Waits until GL has finished every command issued (glFinish).
  static void finish();
  /// GL_RENDERER and GL_VERSION of the current context, e.g. "llvmpipe (...), 4.5 (Core
  /// Profile) Mesa 22.3.6".
  static std::string description();

  /// Draws into an off-screen multisampled framebuffer of w x h pixels and reads it
  /// back as RGB rows, top row first. Restores the default framebuffer. False (and
  /// why) when the framebuffer cannot be made or GL reported an error.
  bool renderImage(int w, int h, const Camera& camera, const DrawSettings& s,
                   std::vector<unsigned char>& rgb, std::string& error);

  /// The pending GL errors as text (empty when none); clears them.
  static std::string glErrors();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Writes RGB rows (top first) as a PNG through a temporary file and a rename, so a
/// failed write never leaves a partial file. False (and why) on failure.
bool writePng(const std::string& path, int w, int h, const std::vector<unsigned char>& rgb,
              std::string& error);

}  // namespace viewer
