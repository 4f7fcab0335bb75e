// The vertex shader of the full-screen passes (eye-dome lighting, the stereo compositor): one
// triangle that covers the viewport, drawn with glDrawArrays(GL_TRIANGLES, 0, 3) and no vertex
// buffer. One triangle rather than two: no diagonal seam where fragments are shaded twice.
#pragma once

namespace parallax {

inline constexpr const char* kFullscreenTriangleVertexShader = R"glsl(#version 450 core
void main() {
  // (-1,-1), (3,-1), (-1,3).
  vec2 p = vec2(float((gl_VertexID & 1) << 2) - 1.0, float((gl_VertexID & 2) << 1) - 1.0);
  gl_Position = vec4(p, 0.0, 1.0);
}
)glsl";

}  // namespace parallax
