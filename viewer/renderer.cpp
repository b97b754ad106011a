#include "renderer.h"

// Core-profile entry points come straight from libGL (GLVND exports all of them), so
// no loader is needed; GL_GLEXT_PROTOTYPES makes glext.h declare them.
#define GL_GLEXT_PROTOTYPES 1
#include <GL/gl.h>
#include <GL/glext.h>
#include <opensubdiv/far/patchDescriptor.h>
#include <opensubdiv/osd/glPatchTable.h>
#include <opensubdiv/osd/glslPatchShaderSource.h>
#include <stb_image_write.h>

#include <algorithm>
#include <cstdio>
#include <map>

// libosdGPU resolves its GL entry points through an internal loader that must be
// initialised before any Osd::GL* object is made, and the installed headers do not
// declare it (see shared/notes/opensubdiv.md).
namespace OpenSubdiv {
namespace internal {
namespace GLLoader {
bool libraryInitializeGL();
}  // namespace GLLoader
}  // namespace internal
}  // namespace OpenSubdiv

namespace viewer {
namespace {

namespace Osd = OpenSubdiv::Osd;
namespace Far = OpenSubdiv::Far;

// ---- Shaders -------------------------------------------------------------------
// Gouraud shading: the lighting is evaluated per vertex and interpolated; the
// fragment shader only multiplies it with the base colour (which may vary per face,
// for level colouring, so it cannot be folded into the vertex colour).

const char* kLighting = R"(
// Two lights fixed in eye space (a key light from the upper left, a weak fill from
// the lower right) and an ambient term; both sides of a surface are lit alike.
vec2 lightSurface(vec3 n, vec3 p) {
  vec3 v = normalize(-p);
  if (dot(n, v) < 0.0) n = -n;
  vec3 key = normalize(vec3(-0.45, 0.55, 0.7));
  vec3 fill = normalize(vec3(0.6, -0.3, 0.5));
  float diffuse = 0.16 + 0.72 * max(dot(n, key), 0.0) + 0.22 * max(dot(n, fill), 0.0);
  float specular = 0.22 * pow(max(dot(n, normalize(key + v)), 0.0), 48.0);
  return vec2(diffuse, specular);
}
)";

const char* kMeshVertex = R"(
layout(location = 0) in vec3 aPosition;
layout(location = 1) in vec3 aNormal;
layout(location = 2) in float aValue;
uniform mat4 uModelView;
uniform mat4 uProjection;
out vec2 vLight;
out float vValue;
void main() {
  vec4 p = uModelView * vec4(aPosition, 1.0);
  // The model transform is a uniform scale and a rotation, so it maps normals too.
  vec3 n = normalize(mat3(uModelView) * aNormal);
  vLight = lightSurface(n, p.xyz);
  vValue = aValue;
  gl_Position = uProjection * p;
}
)";

const char* kColors = R"(
uniform int uColorMode;    // 0 plain, 1 level, 2 value
uniform int uLevels;
uniform int uWire;
uniform samplerBuffer uFaceLevel;
out vec4 fragColor;

vec3 levelColor(float level) {
  // Coarse levels cool, fine levels warm, so refinement reads as heat.
  float t = uLevels > 0 ? clamp(level / float(uLevels), 0.0, 1.0) : 0.0;
  vec3 c0 = vec3(0.25, 0.40, 0.85), c1 = vec3(0.30, 0.75, 0.75), c2 = vec3(0.55, 0.82, 0.35),
       c3 = vec3(0.95, 0.80, 0.30), c4 = vec3(0.90, 0.35, 0.25);
  t *= 4.0;
  return t < 1.0 ? mix(c0, c1, t) : t < 2.0 ? mix(c1, c2, t - 1.0)
       : t < 3.0 ? mix(c2, c3, t - 2.0) : mix(c3, c4, t - 3.0);
}

vec3 valueColor(float t) {
  // Sequential map: small values dark blue, large values bright yellow-red.
  t = clamp(t, 0.0, 1.0) * 4.0;
  vec3 c0 = vec3(0.15, 0.20, 0.55), c1 = vec3(0.15, 0.55, 0.80), c2 = vec3(0.45, 0.80, 0.45),
       c3 = vec3(0.98, 0.82, 0.25), c4 = vec3(0.90, 0.20, 0.15);
  return t < 1.0 ? mix(c0, c1, t) : t < 2.0 ? mix(c1, c2, t - 1.0)
       : t < 3.0 ? mix(c2, c3, t - 2.0) : mix(c3, c4, t - 3.0);
}

const vec3 kMaterial = vec3(0.86, 0.80, 0.70);
const vec4 kWire = vec4(0.10, 0.10, 0.12, 1.0);
)";

const char* kMeshFragment = R"(
in vec2 vLight;
in float vValue;
void main() {
  if (uWire != 0) { fragColor = kWire; return; }
  vec3 base = kMaterial;
  if (uColorMode == 1) base = levelColor(texelFetch(uFaceLevel, gl_PrimitiveID).r);
  else if (uColorMode == 2) base = valueColor(vValue);
  fragColor = vec4(base * vLight.x + vec3(vLight.y), 1.0);
}
)";

// OpenSubdiv's patch shaders call these to learn the client's state.
const char* kOsdClient = R"(
uniform mat4 uModelView;
uniform mat4 uProjection;
uniform float uTessLevel;
uniform int uPrimitiveIdBase;
mat4 OsdModelViewMatrix() { return uModelView; }
mat4 OsdProjectionMatrix() { return uProjection; }
mat4 OsdModelViewProjectionMatrix() { return uProjection * uModelView; }
float OsdTessLevel() { return uTessLevel; }
int OsdGregoryQuadOffsetBase() { return 0; }
int OsdPrimitiveIdBase() { return uPrimitiveIdBase; }
int OsdBaseVertex() { return 0; }
)";

// The limit surface is lit per fragment from the exact limit normal that the
// tessellation evaluation shader computes (OpenSubdiv's OutputVertex block).
const char* kPatchFragment = R"(
struct OutputVertex {
  vec4 position;
  vec3 normal;
  vec3 tangent;
  vec3 bitangent;
  vec4 patchCoord;
  vec2 tessCoord;
};
in block { OutputVertex v; } inpt;
void main() {
  if (uWire != 0) { fragColor = kWire; return; }
  vec2 light = lightSurface(normalize(inpt.v.normal), inpt.v.position.xyz);
  fragColor = vec4(kMaterial * light.x + vec3(light.y), 1.0);
}
)";

// The cached image of the reference pane, copied pixel for pixel into the pane's
// viewport by one triangle that covers it.
const char* kImageVertex = R"(
void main() {
  const vec2 corner[3] = vec2[3](vec2(-1.0, -1.0), vec2(3.0, -1.0), vec2(-1.0, 3.0));
  gl_Position = vec4(corner[gl_VertexID], 0.0, 1.0);
}
)";

const char* kImageFragment = R"(
uniform sampler2D uImage;
out vec4 fragColor;
void main() { fragColor = texelFetch(uImage, ivec2(gl_FragCoord.xy), 0); }
)";

GLuint compile(GLenum stage, const std::string& source, const char* what, std::string& error) {
  const GLuint s = glCreateShader(stage);
  const char* text = source.c_str();
  glShaderSource(s, 1, &text, nullptr);
  glCompileShader(s);
  GLint ok = 0;
  glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    GLint n = 0;
    glGetShaderiv(s, GL_INFO_LOG_LENGTH, &n);
    std::string log(static_cast<std::size_t>(std::max(n, 1)), '\0');
    glGetShaderInfoLog(s, n, nullptr, log.data());
    error = std::string(what) + " shader does not compile: " + log.c_str();
    glDeleteShader(s);
    return 0;
  }
  return s;
}

GLuint link(const std::vector<std::pair<GLenum, std::string>>& stages, const char* what,
            std::string& error) {
  std::vector<GLuint> shaders;
  for (const auto& [stage, source] : stages) {
    const GLuint s = compile(stage, source, what, error);
    if (!s) {
      for (GLuint t : shaders) glDeleteShader(t);
      return 0;
    }
    shaders.push_back(s);
  }
  const GLuint p = glCreateProgram();
  for (GLuint s : shaders) glAttachShader(p, s);
  glLinkProgram(p);
  for (GLuint s : shaders) glDeleteShader(s);
  GLint ok = 0;
  glGetProgramiv(p, GL_LINK_STATUS, &ok);
  if (!ok) {
    GLint n = 0;
    glGetProgramiv(p, GL_INFO_LOG_LENGTH, &n);
    std::string log(static_cast<std::size_t>(std::max(n, 1)), '\0');
    glGetProgramInfoLog(p, n, nullptr, log.data());
    error = std::string(what) + " program does not link: " + log.c_str();
    glDeleteProgram(p);
    return 0;
  }
  return p;
}

struct GpuMesh {
  GLuint vao = 0, position = 0, normal = 0, value = 0, index = 0;
  GLuint levelBuffer = 0, levelTexture = 0;
  GLsizei indexCount = 0;

  void upload(const DrawMesh& m) {
    if (!vao) {
      glGenVertexArrays(1, &vao);
      GLuint b[5];
      glGenBuffers(5, b);
      position = b[0], normal = b[1], value = b[2], index = b[3], levelBuffer = b[4];
      glGenTextures(1, &levelTexture);
    }
    const std::size_t n = m.positions.size() / 3;
    glBindVertexArray(vao);
    auto attribute = [](GLuint buffer, GLuint location, int size, const std::vector<float>& data) {
      glBindBuffer(GL_ARRAY_BUFFER, buffer);
      glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(data.size() * sizeof(float)),
                   data.data(), GL_STATIC_DRAW);
      glVertexAttribPointer(location, size, GL_FLOAT, GL_FALSE, 0, nullptr);
      glEnableVertexAttribArray(location);
    };
    attribute(position, 0, 3, m.positions);
    attribute(normal, 1, 3,
              m.normals.size() == 3 * n ? m.normals : std::vector<float>(3 * n, 0.0f));
    attribute(value, 2, 1, m.vertexValue.size() == n ? m.vertexValue : std::vector<float>(n, 0.0f));
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, index);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER,
                 static_cast<GLsizeiptr>(m.indices.size() * sizeof(std::uint32_t)),
                 m.indices.data(), GL_STATIC_DRAW);
    glBindVertexArray(0);
    indexCount = static_cast<GLsizei>(m.indices.size());

    // Per-face levels live in a buffer texture read with gl_PrimitiveID, so faces
    // can share vertices and still have flat colours.
    const std::size_t faces = m.indices.size() / 3;
    const std::vector<float> levels =
        m.faceLevel.size() == faces ? m.faceLevel
                                    : std::vector<float>(std::max<std::size_t>(faces, 1), 0.0f);
    glBindBuffer(GL_TEXTURE_BUFFER, levelBuffer);
    glBufferData(GL_TEXTURE_BUFFER, static_cast<GLsizeiptr>(levels.size() * sizeof(float)),
                 levels.data(), GL_STATIC_DRAW);
    glBindTexture(GL_TEXTURE_BUFFER, levelTexture);
    glTexBuffer(GL_TEXTURE_BUFFER, GL_R32F, levelBuffer);
    glBindTexture(GL_TEXTURE_BUFFER, 0);
    glBindBuffer(GL_TEXTURE_BUFFER, 0);
  }

  ~GpuMesh() {
    if (!vao) return;
    glDeleteVertexArrays(1, &vao);
    const GLuint b[5] = {position, normal, value, index, levelBuffer};
    glDeleteBuffers(5, b);
    glDeleteTextures(1, &levelTexture);
  }
};

// Reads the context's version, e.g. 45 for 4.5.
int contextVersion() {
  GLint major = 0, minor = 0;
  glGetIntegerv(GL_MAJOR_VERSION, &major);
  glGetIntegerv(GL_MINOR_VERSION, &minor);
  return major * 10 + minor;
}

}  // namespace

struct Renderer::Impl {
  GLuint meshProgram = 0;
  GpuMesh meshes[2];
  Eigen::Vector3f center = Eigen::Vector3f::Zero();
  float radius = 1.0f;

  // Smooth mode.
  std::map<Far::PatchDescriptor::Type, GLuint> patchPrograms;
  std::unique_ptr<Osd::GLPatchTable> patchTable;
  GLuint patchVao = 0, patchPoints = 0;
  int patches = 0;
  bool patchShadersFailed = false;
  std::string patchShaderError;

  // The reference pane's cached image: rendered into cacheMsFbo (the target's
  // samples) and resolved into cacheTexture (cacheFbo), or, when the target is not
  // multisampled, rendered into cacheFbo directly. Remade when the size or the
  // sample count changes; redrawn when the key changes.
  GLuint imageProgram = 0, emptyVao = 0;
  GLuint cacheMsFbo = 0, cacheMsColor = 0, cacheDepth = 0, cacheFbo = 0, cacheTexture = 0;
  int cacheW = 0, cacheH = 0, cacheSamples = -1;
  struct CacheKey {
    Eigen::Matrix4f mv = Eigen::Matrix4f::Zero(), proj = Eigen::Matrix4f::Zero();
    bool wireframe = false;
    ColorMode color = ColorMode::Plain;
    int levels = 0, x = 0, y = 0;
    std::uint64_t mesh = 0;
    bool operator==(const CacheKey& o) const {
      return mv == o.mv && proj == o.proj && wireframe == o.wireframe && color == o.color &&
             levels == o.levels && x == o.x && y == o.y && mesh == o.mesh;
    }
  };
  CacheKey cacheKey;
  bool cacheValid = false;
  std::uint64_t referenceGeneration = 1;  ///< bumped by setMesh(Reference), setBounds
  long long referenceRedraws = 0, referenceCacheHits = 0;

  // Off-screen targets, remade when the size changes.
  GLuint msFbo = 0, msColor = 0, msDepth = 0, resolveFbo = 0, resolveColor = 0;
  int fboW = 0, fboH = 0;

  ~Impl() {
    if (meshProgram) glDeleteProgram(meshProgram);
    for (auto& [type, p] : patchPrograms) glDeleteProgram(p);
    if (patchVao) glDeleteVertexArrays(1, &patchVao);
    if (patchPoints) glDeleteBuffers(1, &patchPoints);
    deleteTargets();
    deleteCache();
    if (imageProgram) glDeleteProgram(imageProgram);
    if (emptyVao) glDeleteVertexArrays(1, &emptyVao);
  }

  void deleteCache() {
    const GLuint fbos[2] = {cacheMsFbo, cacheFbo};
    const GLuint rbs[2] = {cacheMsColor, cacheDepth};
    glDeleteFramebuffers(2, fbos);
    glDeleteRenderbuffers(2, rbs);
    glDeleteTextures(1, &cacheTexture);
    cacheMsFbo = cacheMsColor = cacheDepth = cacheFbo = cacheTexture = 0;
    cacheW = cacheH = 0, cacheSamples = -1;
    cacheValid = false;
  }

  // (Re)makes the cache's targets for w x h pixels with `samples` samples (0: none);
  // false when the framebuffers are incomplete. Leaves framebuffer bindings changed.
  bool cacheTargets(int w, int h, int samples) {
    if (cacheFbo && cacheW == w && cacheH == h && cacheSamples == samples) return true;
    deleteCache();
    glGenTextures(1, &cacheTexture);
    glBindTexture(GL_TEXTURE_2D, cacheTexture);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, w, h, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, 0);
    glBindTexture(GL_TEXTURE_2D, 0);
    glGenRenderbuffers(1, &cacheDepth);
    glBindRenderbuffer(GL_RENDERBUFFER, cacheDepth);
    glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples, GL_DEPTH_COMPONENT24, w, h);
    glGenFramebuffers(1, &cacheFbo);
    glBindFramebuffer(GL_FRAMEBUFFER, cacheFbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, cacheTexture, 0);
    if (samples == 0)
      glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, cacheDepth);
    bool ok = glCheckFramebufferStatus(GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE;
    if (samples > 0) {
      glGenRenderbuffers(1, &cacheMsColor);
      glBindRenderbuffer(GL_RENDERBUFFER, cacheMsColor);
      glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples, GL_RGBA8, w, h);
      glGenFramebuffers(1, &cacheMsFbo);
      glBindFramebuffer(GL_FRAMEBUFFER, cacheMsFbo);
      glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER,
                                cacheMsColor);
      glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, cacheDepth);
      ok = ok && glCheckFramebufferStatus(GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE;
    }
    glBindRenderbuffer(GL_RENDERBUFFER, 0);
    if (!ok) {
      deleteCache();
      return false;
    }
    cacheW = w, cacheH = h, cacheSamples = samples;
    return true;
  }

  // The reference pane at (x, y, w, h) of the bound framebuffer from its cached
  // image, redrawn first when the key changed. The mesh is rendered exactly as the
  // uncached path would (same viewport, projection, clear colour and sample count;
  // the cache spans (0, 0)..(x + w, y + h) so that the viewport is the same one, as
  // rasterisation is not exactly invariant under moving it) and resolved, so the
  // final resolve of the target gives the same pixels.
  // False, with nothing drawn, when the cache's framebuffers cannot be made.
  bool drawReferenceCached(int x, int y, int w, int h, const Eigen::Matrix4f& mv,
                           const Eigen::Matrix4f& proj, const DrawSettings& s) {
    if (!imageProgram) return false;
    GLint drawFbo = 0, readFbo = 0, samples = 0;
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &drawFbo);
    glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &readFbo);
    glGetIntegerv(GL_SAMPLES, &samples);
    CacheKey key;
    key.mv = mv, key.proj = proj, key.wireframe = s.wireframe, key.color = s.color;
    key.levels = s.levels, key.x = x, key.y = y, key.mesh = referenceGeneration;
    const int cw = x + w, ch = y + h;
    const bool sameTargets = cacheFbo && cacheW == cw && cacheH == ch && cacheSamples == samples;
    if (!(cacheValid && sameTargets && key == cacheKey)) {
      const bool made = cacheTargets(cw, ch, samples);
      if (made) {
        glBindFramebuffer(GL_FRAMEBUFFER, samples > 0 ? cacheMsFbo : cacheFbo);
        glClearColor(0.16f, 0.17f, 0.19f, 1.0f);
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        glViewport(x, y, w, h);
        drawMesh(meshes[0], mv, proj, s);
        ++referenceRedraws;
        if (samples > 0) {
          glBindFramebuffer(GL_READ_FRAMEBUFFER, cacheMsFbo);
          glBindFramebuffer(GL_DRAW_FRAMEBUFFER, cacheFbo);
          glBlitFramebuffer(x, y, cw, ch, x, y, cw, ch, GL_COLOR_BUFFER_BIT, GL_NEAREST);
        }
        cacheKey = key;
        cacheValid = true;
      }
      glBindFramebuffer(GL_READ_FRAMEBUFFER, static_cast<GLuint>(readFbo));
      glBindFramebuffer(GL_DRAW_FRAMEBUFFER, static_cast<GLuint>(drawFbo));
      if (!made) return false;
    } else {
      ++referenceCacheHits;
    }
    glViewport(x, y, w, h);
    glDisable(GL_DEPTH_TEST);
    glUseProgram(imageProgram);
    glUniform1i(glGetUniformLocation(imageProgram, "uImage"), 0);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, cacheTexture);
    glBindVertexArray(emptyVao);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindVertexArray(0);
    glBindTexture(GL_TEXTURE_2D, 0);
    glEnable(GL_DEPTH_TEST);
    return true;
  }

  void deleteTargets() {
    if (!msFbo) return;
    const GLuint fbos[2] = {msFbo, resolveFbo};
    const GLuint rbs[3] = {msColor, msDepth, resolveColor};
    glDeleteFramebuffers(2, fbos);
    glDeleteRenderbuffers(3, rbs);
    msFbo = resolveFbo = 0;
  }

  Eigen::Matrix4f modelView(const Camera& camera) const {
    Eigen::Matrix4f model = Eigen::Matrix4f::Identity();
    model.topLeftCorner<3, 3>() *= 1.0f / radius;
    model.topRightCorner<3, 1>() = -center / radius;
    return camera.viewMatrix() * model;
  }

  GLuint patchProgram(Far::PatchDescriptor::Type type, std::string& error) {
    auto it = patchPrograms.find(type);
    if (it != patchPrograms.end()) return it->second;
    // One program per patch type: OpenSubdiv's sources select their stage and
    // patch type with the defines at the top of each stage's text.
    const std::string head = "#version 410\n#define OSD_PATCH_BASIS_GLSL\n";
    const std::string common = Osd::GLSLPatchShaderSource::GetPatchBasisShaderSource() +
                               Osd::GLSLPatchShaderSource::GetCommonShaderSource() + kOsdClient;
    const GLuint p =
        link({{GL_VERTEX_SHADER,
               head + common + Osd::GLSLPatchShaderSource::GetVertexShaderSource(type)},
              {GL_TESS_CONTROL_SHADER,
               head + common + Osd::GLSLPatchShaderSource::GetTessControlShaderSource(type)},
              {GL_TESS_EVALUATION_SHADER,
               head + common + Osd::GLSLPatchShaderSource::GetTessEvalShaderSource(type)},
              {GL_FRAGMENT_SHADER,
               std::string("#version 410\n") + kLighting + kColors + kPatchFragment}},
             "limit patch", error);
    if (p) patchPrograms[type] = p;
    return p;
  }

  void drawMesh(const GpuMesh& m, const Eigen::Matrix4f& mv, const Eigen::Matrix4f& proj,
                const DrawSettings& s) {
    if (!m.indexCount) return;
    glUseProgram(meshProgram);
    glUniformMatrix4fv(glGetUniformLocation(meshProgram, "uModelView"), 1, GL_FALSE, mv.data());
    glUniformMatrix4fv(glGetUniformLocation(meshProgram, "uProjection"), 1, GL_FALSE, proj.data());
    glUniform1i(glGetUniformLocation(meshProgram, "uColorMode"), static_cast<int>(s.color));
    glUniform1i(glGetUniformLocation(meshProgram, "uLevels"), s.levels);
    glUniform1i(glGetUniformLocation(meshProgram, "uFaceLevel"), 0);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_BUFFER, m.levelTexture);
    glBindVertexArray(m.vao);
    drawTwice(meshProgram, s.wireframe,
              [&] { glDrawElements(GL_TRIANGLES, m.indexCount, GL_UNSIGNED_INT, nullptr); });
    glBindVertexArray(0);
    glBindTexture(GL_TEXTURE_BUFFER, 0);
  }

  // Fills, then (with the wireframe on) draws the same primitives as lines; the
  // fill is pushed back in depth so the lines win the depth test.
  template <class F>
  void drawTwice(GLuint program, bool wireframe, F&& primitives) {
    const GLint wire = glGetUniformLocation(program, "uWire");
    glUniform1i(wire, 0);
    glEnable(GL_POLYGON_OFFSET_FILL);
    glPolygonOffset(1.0f, 1.0f);
    primitives();
    glDisable(GL_POLYGON_OFFSET_FILL);
    if (!wireframe) return;
    glUniform1i(wire, 1);
    glPolygonMode(GL_FRONT_AND_BACK, GL_LINE);
    primitives();
    glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
  }

  void drawPatches(const Eigen::Matrix4f& mv, const Eigen::Matrix4f& proj, const DrawSettings& s) {
    if (!patchTable) return;
    glBindVertexArray(patchVao);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_BUFFER, patchTable->GetPatchParamTextureBuffer());
    for (const Osd::PatchArray& array : patchTable->GetPatchArrays()) {
      const Far::PatchDescriptor desc = array.GetDescriptor();
      // setPatches compiled every program this table needs.
      std::string unused;
      const GLuint p = patchProgram(desc.GetType(), unused);
      if (!p) continue;
      const int cvs = desc.GetNumControlVertices();
      glUseProgram(p);
      glUniformMatrix4fv(glGetUniformLocation(p, "uModelView"), 1, GL_FALSE, mv.data());
      glUniformMatrix4fv(glGetUniformLocation(p, "uProjection"), 1, GL_FALSE, proj.data());
      glUniform1f(glGetUniformLocation(p, "uTessLevel"), s.tessLevel);
      glUniform1i(glGetUniformLocation(p, "uPrimitiveIdBase"), array.GetPrimitiveIdBase());
      glUniform1i(glGetUniformLocation(p, "OsdPatchParamBuffer"), 0);
      glPatchParameteri(GL_PATCH_VERTICES, cvs);
      const auto offset = static_cast<std::uintptr_t>(array.GetIndexBase()) * sizeof(unsigned);
      drawTwice(p, s.wireframe, [&] {
        glDrawElements(GL_PATCHES, array.GetNumPatches() * cvs, GL_UNSIGNED_INT,
                       reinterpret_cast<const void*>(offset));
      });
    }
    glBindTexture(GL_TEXTURE_BUFFER, 0);
    glBindVertexArray(0);
  }
};

Renderer::Renderer() : impl_(std::make_unique<Impl>()) {}
Renderer::~Renderer() = default;

bool Renderer::init(std::string& error) {
  if (contextVersion() < 33) {
    error = "OpenGL 3.3 or later is needed, the context has " +
            std::string(reinterpret_cast<const char*>(glGetString(GL_VERSION)));
    return false;
  }
  const std::string head = "#version 330 core\n";
  impl_->meshProgram = link({{GL_VERTEX_SHADER, head + kLighting + kMeshVertex},
                             {GL_FRAGMENT_SHADER, head + kColors + kMeshFragment}},
                            "mesh", error);
  if (!impl_->meshProgram) return false;
  impl_->imageProgram =
      link({{GL_VERTEX_SHADER, head + kImageVertex}, {GL_FRAGMENT_SHADER, head + kImageFragment}},
           "pane image", error);
  if (!impl_->imageProgram) return false;
  glGenVertexArrays(1, &impl_->emptyVao);
  return true;
}

void Renderer::setBounds(const Eigen::Vector3f& center, float radius) {
  impl_->center = center;
  impl_->radius = radius > 0 ? radius : 1.0f;
  ++impl_->referenceGeneration;
}

void Renderer::setMesh(Pane pane, const DrawMesh& mesh) {
  impl_->meshes[static_cast<int>(pane)].upload(mesh);
  if (pane == Pane::Reference) ++impl_->referenceGeneration;
}

bool Renderer::setPatches(const Far::PatchTable& table, const std::vector<float>& points,
                          std::string& error) {
  Impl& m = *impl_;
  if (m.patchShadersFailed) {
    error = m.patchShaderError;
    return false;
  }
  if (contextVersion() < 41) {
    error = "smooth mode needs OpenGL 4.1 (tessellation shaders); the context has " +
            std::string(reinterpret_cast<const char*>(glGetString(GL_VERSION)));
    return false;
  }
  OpenSubdiv::internal::GLLoader::libraryInitializeGL();
  // Compile every program this table needs before replacing anything, so a
  // failure leaves the previous state intact and is reported once.
  for (int i = 0; i < table.GetNumPatchArrays(); ++i) {
    if (!m.patchProgram(table.GetPatchArrayDescriptor(i).GetType(), error)) {
      m.patchShadersFailed = true;
      m.patchShaderError = error;
      return false;
    }
  }
  m.patchTable.reset(Osd::GLPatchTable::Create(&table));
  if (!m.patchTable) {
    error = "OpenSubdiv could not create the GL patch table";
    return false;
  }
  if (!m.patchVao) {
    glGenVertexArrays(1, &m.patchVao);
    glGenBuffers(1, &m.patchPoints);
  }
  glBindVertexArray(m.patchVao);
  glBindBuffer(GL_ARRAY_BUFFER, m.patchPoints);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(points.size() * sizeof(float)),
               points.data(), GL_DYNAMIC_DRAW);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
  glEnableVertexAttribArray(0);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, m.patchTable->GetPatchIndexBuffer());
  glBindVertexArray(0);
  m.patches = table.GetNumPatchesTotal();
  return true;
}

void Renderer::updatePatchPoints(const std::vector<float>& points) {
  if (!impl_->patchPoints) return;
  glBindBuffer(GL_ARRAY_BUFFER, impl_->patchPoints);
  glBufferSubData(GL_ARRAY_BUFFER, 0, static_cast<GLsizeiptr>(points.size() * sizeof(float)),
                  points.data());
  glBindBuffer(GL_ARRAY_BUFFER, 0);
}

bool Renderer::hasPatches() const {
  return impl_->patchTable != nullptr;
}
int Renderer::patchCount() const {
  return impl_->patchTable ? impl_->patches : 0;
}
long long Renderer::referenceRedraws() const {
  return impl_->referenceRedraws;
}
long long Renderer::referenceCacheHits() const {
  return impl_->referenceCacheHits;
}

void Renderer::draw(int x, int y, int w, int h, const Camera& camera, const DrawSettings& s) {
  Impl& m = *impl_;
  glEnable(GL_SCISSOR_TEST);
  glScissor(x, y, w, h);
  glClearColor(0.16f, 0.17f, 0.19f, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glDisable(GL_SCISSOR_TEST);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LEQUAL);
  glDisable(GL_CULL_FACE);

  const Eigen::Matrix4f mv = m.modelView(camera);
  const int paneW = s.split ? w / 2 : w;
  const Eigen::Matrix4f proj = camera.projection(static_cast<float>(paneW) / std::max(h, 1));
  if (s.split && !(s.cacheReference && m.drawReferenceCached(x, y, paneW, h, mv, proj, s))) {
    glViewport(x, y, paneW, h);
    m.drawMesh(m.meshes[0], mv, proj, s);
    ++m.referenceRedraws;
  }
  glViewport(x + (s.split ? paneW : 0), y, paneW, h);
  if (s.smooth && m.patchTable)
    m.drawPatches(mv, proj, s);
  else
    m.drawMesh(m.meshes[1], mv, proj, s);
  if (s.split) {
    // A thin divider between the panes.
    glEnable(GL_SCISSOR_TEST);
    glScissor(x + paneW - 1, y, 2, h);
    glClearColor(0.35f, 0.36f, 0.40f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);
    glDisable(GL_SCISSOR_TEST);
  }
  glViewport(x, y, w, h);
  glUseProgram(0);
}

bool Renderer::bindOffscreen(int w, int h, std::string& error) {
  Impl& m = *impl_;
  GLint maxSize = 0;
  glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &maxSize);
  if (w < 1 || h < 1 || w > maxSize || h > maxSize) {
    error = "image size " + std::to_string(w) + "x" + std::to_string(h) + " is outside 1.." +
            std::to_string(maxSize);
    return false;
  }
  if (m.fboW != w || m.fboH != h || !m.msFbo) {
    m.deleteTargets();
    GLint maxSamples = 0;
    glGetIntegerv(GL_MAX_SAMPLES, &maxSamples);
    const GLsizei samples = std::min(4, static_cast<int>(maxSamples));
    GLuint fbos[2], rbs[3];
    glGenFramebuffers(2, fbos);
    glGenRenderbuffers(3, rbs);
    m.msFbo = fbos[0], m.resolveFbo = fbos[1];
    m.msColor = rbs[0], m.msDepth = rbs[1], m.resolveColor = rbs[2];
    glBindRenderbuffer(GL_RENDERBUFFER, m.msColor);
    glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples, GL_RGBA8, w, h);
    glBindRenderbuffer(GL_RENDERBUFFER, m.msDepth);
    glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples, GL_DEPTH_COMPONENT24, w, h);
    glBindRenderbuffer(GL_RENDERBUFFER, m.resolveColor);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, w, h);
    glBindRenderbuffer(GL_RENDERBUFFER, 0);
    glBindFramebuffer(GL_FRAMEBUFFER, m.msFbo);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, m.msColor);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, m.msDepth);
    const bool msOk = glCheckFramebufferStatus(GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE;
    glBindFramebuffer(GL_FRAMEBUFFER, m.resolveFbo);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER,
                              m.resolveColor);
    const bool resolveOk = glCheckFramebufferStatus(GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE;
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    if (!msOk || !resolveOk) {
      m.deleteTargets();
      error = "cannot create an off-screen framebuffer";
      return false;
    }
    m.fboW = w, m.fboH = h;
  }
  glBindFramebuffer(GL_FRAMEBUFFER, m.msFbo);
  return true;
}

void Renderer::finish() {
  glFinish();
}

std::string Renderer::description() {
  auto text = [](GLenum name) {
    const auto* s = reinterpret_cast<const char*>(glGetString(name));
    return std::string(s ? s : "?");
  };
  return text(GL_RENDERER) + ", " + text(GL_VERSION);
}

bool Renderer::renderImage(int w, int h, const Camera& camera, const DrawSettings& s,
                           std::vector<unsigned char>& rgb, std::string& error) {
  Impl& m = *impl_;
  if (!bindOffscreen(w, h, error)) return false;
  draw(0, 0, w, h, camera, s);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, m.msFbo);
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, m.resolveFbo);
  glBlitFramebuffer(0, 0, w, h, 0, 0, w, h, GL_COLOR_BUFFER_BIT, GL_NEAREST);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, m.resolveFbo);
  std::vector<unsigned char> flipped(static_cast<std::size_t>(w) * h * 3);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, w, h, GL_RGB, GL_UNSIGNED_BYTE, flipped.data());
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  const std::string errors = glErrors();
  if (!errors.empty()) {
    error = "OpenGL reported " + errors + " while drawing";
    return false;
  }
  // GL's rows run bottom-up, images' top-down.
  const std::size_t row = static_cast<std::size_t>(w) * 3;
  rgb.resize(flipped.size());
  for (int yy = 0; yy < h; ++yy)
    std::copy_n(flipped.begin() + static_cast<std::ptrdiff_t>(row * (h - 1 - yy)), row,
                rgb.begin() + static_cast<std::ptrdiff_t>(row * yy));
  return true;
}

std::string Renderer::glErrors() {
  std::string out;
  for (int i = 0; i < 16; ++i) {
    const GLenum e = glGetError();
    if (e == GL_NO_ERROR) break;
    char code[16];
    std::snprintf(code, sizeof code, "0x%04x", e);
    out += out.empty() ? "" : ", ";
    out += e == GL_INVALID_ENUM                    ? "GL_INVALID_ENUM"
           : e == GL_INVALID_VALUE                 ? "GL_INVALID_VALUE"
           : e == GL_INVALID_OPERATION             ? "GL_INVALID_OPERATION"
           : e == GL_OUT_OF_MEMORY                 ? "GL_OUT_OF_MEMORY"
           : e == GL_INVALID_FRAMEBUFFER_OPERATION ? "GL_INVALID_FRAMEBUFFER_OPERATION"
                                                   : code;
  }
  return out;
}

bool writePng(const std::string& path, int w, int h, const std::vector<unsigned char>& rgb,
              std::string& error) {
  const std::string tmp = path + ".tmp.png";
  if (!stbi_write_png(tmp.c_str(), w, h, 3, rgb.data(), w * 3)) {
    std::remove(tmp.c_str());
    error = path + ": cannot write the PNG";
    return false;
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    std::remove(tmp.c_str());
    error = path + ": cannot write the PNG";
    return false;
  }
  return true;
}

}  // namespace viewer
