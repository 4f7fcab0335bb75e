// The point pass: GL_POINTS from the chunks of a GpuPointCloud, one draw call per visible chunk.
#pragma once

#include <cstdint>
#include <map>

#include "render/point_buffers.h"
#include "render/render_settings.h"
#include "render/shader_program.h"
#include "render/view.h"

namespace parallax {

struct PointPassStats {
  std::uint64_t points_drawn = 0;
  std::uint32_t chunks_drawn = 0;
  std::uint32_t chunks_culled = 0;
};

class PointPass {
 public:
  PointPass();  // compiles the shaders; needs a current 4.5 context
  ~PointPass();
  PointPass(const PointPass&) = delete;
  PointPass& operator=(const PointPass&) = delete;

  // Draws into the bound framebuffer, inside `view.viewport`, with depth test (reversed, GREATER)
  // and the clip range given. The caller has cleared colour and depth (depth to 0) and set
  // glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE). With `eye_depth`, linear eye depth goes to
  // the second colour attachment (for eye-dome lighting).
  PointPassStats draw(const GpuPointCloud& cloud, const View& view, const ClipRange& range,
                      const RenderSettings& settings, bool eye_depth);

 private:
  // One program per combination of the modes (compiled on first use, then kept): the shaders
  // have no run-time branches on modes (see point_pass_glsl.cpp).
  const ShaderProgram& program(int color, int size, bool lighting, bool orthographic, bool round,
                               bool eye_depth);

  std::map<int, ShaderProgram> programs_;
  GLuint vao_ = 0;
};

}  // namespace parallax
