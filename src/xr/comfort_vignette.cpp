#include "xr/comfort_vignette.h"

#include <cmath>

#include "render/fullscreen_triangle.h"

namespace parallax {
namespace {

constexpr const char* kFragment = R"glsl(#version 450 core
uniform vec2 u_forward;         // the forward direction's pixel (window coordinates)
uniform vec2 u_pixels_per_tan;  // pixels per unit of tangent, x and y
uniform vec2 u_ramp;            // inner, outer tangent
out vec4 out_color;
void main() {
  vec2 tangent = (gl_FragCoord.xy - u_forward) / u_pixels_per_tan;
  out_color = vec4(0.0, 0.0, 0.0, smoothstep(u_ramp.x, u_ramp.y, length(tangent)));
}
)glsl";

}  // namespace

ComfortVignette::ComfortVignette()
    : program_({{GL_VERTEX_SHADER, "comfort_vignette.vert", kFullscreenTriangleVertexShader},
                {GL_FRAGMENT_SHADER, "comfort_vignette.frag", kFragment}}) {
  glCreateVertexArrays(1, &vao_);
}

ComfortVignette::~ComfortVignette() {
  if (vao_) glDeleteVertexArrays(1, &vao_);
}

void ComfortVignette::draw(GLuint framebuffer, const Viewport& viewport, const EyeFov& fov,
                           const VignetteShape& shape) {
  const double tl = std::tan(fov.left), tr = std::tan(fov.right);
  const double tu = std::tan(fov.up), td = std::tan(fov.down);
  const double kx = viewport.width / (tr - tl), ky = viewport.height / (tu - td);
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, framebuffer);
  glViewport(viewport.x, viewport.y, viewport.width, viewport.height);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_SCISSOR_TEST);
  glEnable(GL_BLEND);
  glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
  glUseProgram(program_.id());
  glUniform2f(program_.uniform("u_forward"), float(viewport.x - tl * kx),
              float(viewport.y - td * ky));
  glUniform2f(program_.uniform("u_pixels_per_tan"), float(kx), float(ky));
  glUniform2f(program_.uniform("u_ramp"), float(shape.inner), float(shape.outer));
  glBindVertexArray(vao_);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
  glUseProgram(0);
  glDisable(GL_BLEND);
}

}  // namespace parallax
