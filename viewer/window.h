// The GL context of both front ends of the viewer (interactive and headless): a
// GLFW window, visible or not.
#pragma once

struct GLFWwindow;

namespace viewer {

/// A window with a core-profile context, 4.1 (tessellation shaders for the smooth
/// mode) when the driver has it, 3.3 otherwise; made current. Throws osdmra::Error
/// when there is no display or no such context.
GLFWwindow* createWindow(int width, int height, bool visible);

/// Destroys the window and shuts GLFW down.
void closeWindow(GLFWwindow* window);

/// The interactive window's panel width (window coordinates); the scene is drawn to
/// its right. The slider benchmark uses the same layout.
float panelWidth(float windowWidth);

}  // namespace viewer
