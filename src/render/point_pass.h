// The point pass: GL_POINTS from the chunks of a DrawSet, for every view (one for mono, two for
// stereo): each chunk is culled against every view's frustum, and a chunk some view sees has
// its buffers bound once and is drawn once per view that sees it (the viewport, projection and
// model-view change between the draws, nothing else). A chunk no view sees is not touched.
#pragma once

#include <cstdint>
#include <map>
#include <span>

#include "render/draw_set.h"
#include "render/rasterizer.h"
#include "render/render_settings.h"
#include "render/shader_program.h"
#include "render/view.h"

namespace parallax {

using PointPassStats = RasterStats;

class PointPass final : public Rasterizer {
 public:
  static constexpr std::size_t kMaxViews = 32;  // views are a bit mask per chunk

  PointPass();  // compiles the shaders; needs a current 4.5 context
  ~PointPass() override;
  PointPass(const PointPass&) = delete;
  PointPass& operator=(const PointPass&) = delete;

  // Draws into the bound framebuffer, each view inside its viewport with its clip range
  // (`ranges[i]` for `views[i]`), with depth test (reversed, GREATER). The views share the
  // projection kind (perspective or orthographic: stereo eyes do). The caller has cleared colour
  // and depth (depth to 0) and set glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE). With
  // `eye_depth`, linear eye depth goes to the second colour attachment (for eye-dome lighting).
  // An item with node_spacing > 0 is sized (adaptive mode) by that spacing instead of its
  // per-point spacing attribute.
  PointPassStats draw(const DrawSet& draw_set, std::span<const View> views,
                      std::span<const ClipRange> ranges, const RenderSettings& settings,
                      bool eye_depth);

  RasterizerKind kind() const override { return RasterizerKind::Points; }
  // GL_POINTS draws every setting but --hq (which it ignores: HQ blending needs the compute
  // rasterizer's visibility buffer).
  std::string unsupported(const RenderSettings&, int, int) const override { return {}; }
  // The frame's items (a range or a list), as draw() above.
  RasterStats draw(const RasterFrame& frame) override;

 private:
  // One program per combination of the modes (compiled on first use, then kept): the shaders
  // have no run-time branches on modes (see point_pass_glsl.cpp).
  const ShaderProgram& program(int color, int size, bool lighting, bool orthographic, bool round,
                               bool eye_depth, unsigned filter);

  std::map<int, ShaderProgram> programs_;
  GLuint vao_ = 0;
};

}  // namespace parallax
