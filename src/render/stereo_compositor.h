// Turns a stereo canvas (both eyes' pictures side by side, see StereoFrame) into the output of
// the composed display modes: anaglyph (red-cyan, plain or Dubois), row-interlaced, and the two
// back buffers of a quad-buffered (GL_STEREO) window. The side-by-side and top-bottom modes need
// no composition: their views draw straight into the halves of the output.
#pragma once

#include <epoxy/gl.h>

#include <array>

#include "render/shader_program.h"
#include "render/stereo.h"

namespace parallax {

// Dubois' least-squares red-cyan anaglyph matrices (E. Dubois, "A projection method to generate
// anaglyph stereo images", ICASSP 2001; the values his page publishes for red-cyan glasses),
// row-major: output channel r, g, b by rows, input r, g, b by columns. Applied here to the
// stored (sRGB-encoded) values, as most viewers do; Dubois derived them for linear light, so the
// colours are slightly off, the ghosting reduction is not.
inline constexpr std::array<float, 9> kDuboisLeft{0.437f,  0.449f,  0.164f,  -0.062f, -0.062f,
                                                  -0.024f, -0.048f, -0.050f, -0.017f};
inline constexpr std::array<float, 9> kDuboisRight{-0.011f, -0.032f, -0.007f, 0.377f, 0.761f,
                                                   0.009f,  -0.026f, -0.093f, 1.234f};

class StereoCompositor {
 public:
  StereoCompositor();  // needs a current 4.5 context
  ~StereoCompositor();
  StereoCompositor(const StereoCompositor&) = delete;
  StereoCompositor& operator=(const StereoCompositor&) = delete;

  // Reads `canvas` (an RGBA8 texture of 2 * width x height, the left eye's picture at x 0, the
  // right eye's at x width; `canvas_framebuffer` has it as colour attachment 0) and writes the
  // width x height output of `composition` into framebuffer `target`. QuadBuffer needs `target`
  // 0 with a stereo (GL_STEREO) default framebuffer. Composition::Direct is a caller's mistake.
  void compose(Composition composition, GLuint canvas, GLuint canvas_framebuffer, GLuint target,
               int width, int height);

 private:
  ShaderProgram program_;
  GLuint vao_ = 0;  // empty: the full-screen triangle comes from gl_VertexID
};

}  // namespace parallax
