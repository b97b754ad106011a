#include "window.h"

#include <GLFW/glfw3.h>

#include <algorithm>
#include <string>
#include <utility>

#include "osdmra/base/error.h"

namespace viewer {
namespace {

std::string glfwError;

void onGlfwError(int, const char* description) {
  glfwError = description;
}

}  // namespace

GLFWwindow* createWindow(int width, int height, bool visible) {
  glfwSetErrorCallback(onGlfwError);
  if (!glfwInit()) throw osdmra::Error("no OpenGL: cannot initialise GLFW (" + glfwError + ")");
  for (const auto& [major, minor] : {std::pair{4, 1}, std::pair{3, 3}}) {
    glfwDefaultWindowHints();
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, major);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, minor);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    glfwWindowHint(GLFW_VISIBLE, visible ? GLFW_TRUE : GLFW_FALSE);
    glfwWindowHint(GLFW_SAMPLES, visible ? 4 : 0);
    if (GLFWwindow* w = glfwCreateWindow(width, height, "osdmra-viewer", nullptr, nullptr)) {
      glfwMakeContextCurrent(w);
      return w;
    }
  }
  const std::string why = glfwError;
  glfwTerminate();
  throw osdmra::Error("no OpenGL 3.3 core context (" + why + ")");
}

void closeWindow(GLFWwindow* window) {
  glfwDestroyWindow(window);
  glfwTerminate();
}

float panelWidth(float windowWidth) {
  return std::min(380.0f, windowWidth * 0.4f);
}

}  // namespace viewer
