#include "viewer/xr_mirror_window.h"

#include <GLFW/glfw3.h>

#include <algorithm>
#include <cstdlib>
#include <string>

#include "render/gl_context.h"

namespace parallax {

XrMirrorWindow::XrMirrorWindow(int width, int height, const std::string& title) {
  if (!glfwInit()) {
    throw GlContextError("cannot open the XR mirror window: GLFW found no display (DISPLAY=" +
                         std::string(std::getenv("DISPLAY") ? std::getenv("DISPLAY") : "") +
                         "); --xr-no-mirror draws headless");
  }
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  // The Xlib binding hands the runtime a GLX context: GLFW's default on X11, asked for anyway.
  glfwWindowHint(GLFW_CONTEXT_CREATION_API, GLFW_NATIVE_CONTEXT_API);
  window_ = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
  if (!window_) {
    glfwTerminate();
    throw GlContextError(
        "cannot open the XR mirror window with an OpenGL 4.5 core context; --xr-no-mirror draws "
        "headless");
  }
  glfwMakeContextCurrent(window_);
  glfwSwapInterval(0);
}

XrMirrorWindow::~XrMirrorWindow() {
  glfwDestroyWindow(window_);
  glfwTerminate();
}

bool XrMirrorWindow::show(GLuint framebuffer, const Viewport& eye) {
  int width = 0, height = 0;
  glfwGetFramebufferSize(window_, &width, &height);
  const double fit = std::min(double(width) / eye.width, double(height) / eye.height);
  const int w = int(eye.width * fit), h = int(eye.height * fit);
  const int x = (width - w) / 2, y = (height - h) / 2;
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
  glDisable(GL_SCISSOR_TEST);
  glClearColor(0, 0, 0, 1);
  glClear(GL_COLOR_BUFFER_BIT);
  glBlitNamedFramebuffer(framebuffer, 0, eye.x, eye.y, eye.x + eye.width, eye.y + eye.height, x, y,
                         x + w, y + h, GL_COLOR_BUFFER_BIT, GL_LINEAR);
  glfwSwapBuffers(window_);
  glfwPollEvents();
  return !glfwWindowShouldClose(window_);
}

}  // namespace parallax
