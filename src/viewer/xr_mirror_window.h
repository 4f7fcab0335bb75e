// The XR mirror (issue 24): a GLFW window whose OpenGL context draws the headset's frames (so
// the runtime gets the Xlib/GLX binding of XR_KHR_opengl_enable) and which shows one eye's
// picture, letterboxed, for the people around the headset.
#pragma once

#include <epoxy/gl.h>

#include <memory>
#include <string>

#include "render/view.h"

struct GLFWwindow;

namespace parallax {

class XrMirrorWindow {
 public:
  // Opens a width x height window on $DISPLAY with an OpenGL 4.5 core context and makes it
  // current on this thread; no vsync (the headset's frame loop sets the pace). Throws
  // GlContextError (render/gl_context.h) without a display or such a context.
  XrMirrorWindow(int width, int height, const std::string& title);
  ~XrMirrorWindow();
  XrMirrorWindow(const XrMirrorWindow&) = delete;
  XrMirrorWindow& operator=(const XrMirrorWindow&) = delete;

  // Shows `eye` (pixels of `framebuffer`, bottom-left origin) scaled to fit the window, swaps
  // and handles the window's events. False once the user has closed the window.
  bool show(GLuint framebuffer, const Viewport& eye);

 private:
  GLFWwindow* window_ = nullptr;
};

}  // namespace parallax
