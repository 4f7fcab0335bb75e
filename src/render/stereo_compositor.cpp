#include "render/stereo_compositor.h"

#include "render/fullscreen_triangle.h"

#include <cassert>

namespace parallax {

namespace {

// A run-time switch on the mode: a full-screen pass is a few million fragments at most, and the
// switch is uniform, so the variants are not worth their programs here (unlike the point pass).
const char* const kFragment = R"glsl(#version 450 core
layout(binding = 0) uniform sampler2D u_canvas;
uniform int u_mode;        // 0 anaglyph, 1 Dubois, 2 interlaced
uniform int u_width;       // the output's width: the right eye's picture starts there
uniform int u_height;      // the output's height: interlacing counts rows from the top
uniform mat3 u_left;       // Dubois' matrices (column-major here)
uniform mat3 u_right;
out vec4 out_color;

void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  vec3 left = texelFetch(u_canvas, p, 0).rgb;
  vec3 right = texelFetch(u_canvas, p + ivec2(u_width, 0), 0).rgb;
  vec3 color;
  if (u_mode == 0) {
    color = vec3(left.r, right.g, right.b);
  } else if (u_mode == 1) {
    color = clamp(u_left * left + u_right * right, 0.0, 1.0);
  } else {
    // Row 0 is the top one (as a passive 3D monitor counts), OpenGL's row 0 the bottom one.
    color = ((u_height - 1 - p.y) & 1) == 0 ? left : right;
  }
  out_color = vec4(color, 1.0);
}
)glsl";

}  // namespace

StereoCompositor::StereoCompositor()
    : program_({{GL_VERTEX_SHADER, "stereo_compositor.vert", kFullscreenTriangleVertexShader},
                {GL_FRAGMENT_SHADER, "stereo_compositor.frag", kFragment}}) {
  glCreateVertexArrays(1, &vao_);
}

StereoCompositor::~StereoCompositor() {
  if (vao_) glDeleteVertexArrays(1, &vao_);
}

void StereoCompositor::compose(Composition composition, GLuint canvas, GLuint canvas_framebuffer,
                               GLuint target, int width, int height) {
  assert(composition != Composition::Direct && "Direct frames are not composed");
  if (composition == Composition::QuadBuffer) {
    assert(target == 0 && "quad-buffer output goes to the default framebuffer's back buffers");
    // Each eye's half of the canvas into its back buffer: plain copies, no shader.
    glNamedFramebufferReadBuffer(canvas_framebuffer, GL_COLOR_ATTACHMENT0);
    glNamedFramebufferDrawBuffer(0, GL_BACK_LEFT);
    glBlitNamedFramebuffer(canvas_framebuffer, 0, 0, 0, width, height, 0, 0, width, height,
                           GL_COLOR_BUFFER_BIT, GL_NEAREST);
    glNamedFramebufferDrawBuffer(0, GL_BACK_RIGHT);
    glBlitNamedFramebuffer(canvas_framebuffer, 0, width, 0, 2 * width, height, 0, 0, width, height,
                           GL_COLOR_BUFFER_BIT, GL_NEAREST);
    // Later drawing (the on-screen panel) goes to both eyes.
    glNamedFramebufferDrawBuffer(0, GL_BACK);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    return;
  }
  const int mode = composition == Composition::Anaglyph         ? 0
                   : composition == Composition::AnaglyphDubois ? 1
                                                                : 2;
  glBindFramebuffer(GL_FRAMEBUFFER, target);
  glViewport(0, 0, width, height);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_BLEND);
  glUseProgram(program_.id());
  glBindTextureUnit(0, canvas);
  glUniform1i(program_.uniform("u_mode"), mode);
  glUniform1i(program_.uniform("u_width"), width);
  glUniform1i(program_.uniform("u_height"), height);
  glUniformMatrix3fv(program_.uniform("u_left"), 1, GL_TRUE, kDuboisLeft.data());
  glUniformMatrix3fv(program_.uniform("u_right"), 1, GL_TRUE, kDuboisRight.data());
  glBindVertexArray(vao_);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
  glUseProgram(0);
}

}  // namespace parallax
