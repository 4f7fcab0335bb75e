#include "render/edl_pass.h"

#include "render/fullscreen_triangle.h"

namespace parallax {

namespace {

const char* const kFragment = R"glsl(#version 450 core
layout(binding = 0) uniform sampler2D u_color;
layout(binding = 1) uniform sampler2D u_eye_depth;
uniform float u_strength;
uniform float u_radius;
uniform vec3 u_background;
uniform ivec4 u_viewport;  // x, y, width, height: neighbours are read inside the view only
out vec4 out_color;

// Eye depth is stored with the pixel's coverage (see the point pass): dividing undoes the
// multisample resolve, whose average would otherwise pull edge pixels towards 0 (empty) and make
// their neighbours look like steps.
float eyeDepth(ivec2 q) {
  vec2 stored = texelFetch(u_eye_depth, q, 0).rg;
  return stored.g > 0.0 ? stored.r / stored.g : 0.0;
}

void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  float depth = eyeDepth(p);
  if (depth <= 0.0) {
    out_color = vec4(u_background, 1.0);
    return;
  }
  float log_depth = log2(depth);
  // Stereo views share one texture: a neighbour across a view's edge belongs to the other eye.
  ivec2 low = u_viewport.xy, high = u_viewport.xy + u_viewport.zw - 1;
  const vec2 directions[8] = vec2[8](vec2(1, 0), vec2(0.7071, 0.7071), vec2(0, 1),
                                     vec2(-0.7071, 0.7071), vec2(-1, 0), vec2(-0.7071, -0.7071),
                                     vec2(0, -1), vec2(0.7071, -0.7071));
  float response = 0.0;
  for (int i = 0; i < 8; ++i) {
    ivec2 q = clamp(p + ivec2(round(directions[i] * u_radius)), low, high);
    float neighbour = eyeDepth(q);
    // Empty neighbours say nothing: in a sparse scan most points have some, and counting them as
    // steps would blacken whole surfaces (Potree ignores them too).
    if (neighbour > 0.0) response += max(0.0, log_depth - log2(neighbour));
  }
  // Boucheny's exponential falloff; the 300 matches the look of Potree and CloudCompare at
  // strength 1.
  float shade = exp(-response / 8.0 * 300.0 * u_strength);
  out_color = vec4(texelFetch(u_color, p, 0).rgb * shade, 1.0);
}
)glsl";

}  // namespace

EdlPass::EdlPass()
    : program_({{GL_VERTEX_SHADER, "edl_pass.vert", kFullscreenTriangleVertexShader},
                {GL_FRAGMENT_SHADER, "edl_pass.frag", kFragment}}) {
  glCreateVertexArrays(1, &vao_);
}

EdlPass::~EdlPass() {
  if (vao_) glDeleteVertexArrays(1, &vao_);
}

void EdlPass::draw(GLuint color, GLuint eye_depth, const Viewport& viewport,
                   const RenderSettings& settings) {
  glViewport(viewport.x, viewport.y, viewport.width, viewport.height);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_BLEND);
  glUseProgram(program_.id());
  glBindTextureUnit(0, color);
  glBindTextureUnit(1, eye_depth);
  glUniform1f(program_.uniform("u_strength"), settings.edl_strength);
  glUniform1f(program_.uniform("u_radius"), settings.edl_radius_px);
  glUniform3fv(program_.uniform("u_background"), 1, settings.background.data());
  glUniform4i(program_.uniform("u_viewport"), viewport.x, viewport.y, viewport.width,
              viewport.height);
  glBindVertexArray(vao_);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
  glUseProgram(0);
}

}  // namespace parallax
