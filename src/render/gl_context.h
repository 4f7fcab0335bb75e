// An OpenGL 4.5 core context: headless through EGL, or a window's context adopted from GLFW.
//
// Functions are loaded with libepoxy, which resolves entry points through whichever of EGL or
// GLX made the context current, so the renderer's code is the same in both cases.
#pragma once

#include <memory>
#include <stdexcept>
#include <string>

namespace parallax {

// No OpenGL 4.5 core context could be created: the message says what the driver offered (or why
// none was found) and what Parallax needs.
class GlContextError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct GlContextOptions {
  // Ask for a debug context and print KHR_debug messages on stderr. Defaults to on in builds
  // without NDEBUG; PARALLAX_GL_DEBUG=1 in the environment turns it on anywhere.
  bool debug = false;
};

// Owns a current OpenGL context. Not copyable; one per thread.
class GlContext {
 public:
  // A context with no window and no default framebuffer (render into framebuffer objects).
  // Tries, in order: Mesa's surfaceless platform, the EGL device platform (NVIDIA), the default
  // display. Throws GlContextError when none gives a 4.5 core context.
  static std::unique_ptr<GlContext> createHeadless(const GlContextOptions& options = {});

  // Wraps the context the caller (a GLFW window) has already made current, after checking its
  // version; the caller keeps ownership of the window and the context.
  static std::unique_ptr<GlContext> adoptCurrent(const GlContextOptions& options = {});

  ~GlContext();
  GlContext(const GlContext&) = delete;
  GlContext& operator=(const GlContext&) = delete;

  // "4.5 (Core Profile) Mesa 22.3.6", "llvmpipe (LLVM 15.0.6, 256 bits)", "EGL surfaceless", ...
  const std::string& version() const { return version_; }
  const std::string& renderer() const { return renderer_; }
  const std::string& platform() const { return platform_; }

 private:
  GlContext() = default;
  void describe(std::string platform, bool debug);

  struct Egl;
  std::unique_ptr<Egl> egl_;  // null for an adopted context
  std::string version_;
  std::string renderer_;
  std::string platform_;
};

// True when debug output should be on by default (debug build or PARALLAX_GL_DEBUG=1).
bool glDebugRequested();

}  // namespace parallax
