// The rasterizer plug-in interface: what turns a DrawSet's points into pixels for a list of
// views. Two implement it: PointPass (GL_POINTS, render/point_pass.h) and ComputeRasterizer (an
// atomic minimum per pixel in compute shaders, render/compute_rasterizer.h). Both draw into the
// renderer's framebuffer (RGBA8 colour, RG32F eye depth, 32-bit float reversed depth), so that
// eye-dome lighting, the stereo compositor, picking and screenshots do not know which one drew.
//
// Per-point filters (classes, a clip region inside or outside; later returns and attribute
// ranges) are part of the settings (RenderSettings::filter, core/point_filter.h) and are applied
// in both rasterizers' shaders through keepPoint() (point_pass_glsl.cpp); a new filter adds its
// uniforms there and its test to PointFilter::keepsAll, and both rasterizers pick it up.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "render/camera.h"
#include "render/draw_set.h"
#include "render/render_settings.h"
#include "render/view.h"

namespace parallax {

struct RasterStats {
  std::uint64_t points_drawn = 0;   // points of the chunks drawn, each chunk counted once
  std::uint32_t chunks_drawn = 0;   // chunks that at least one view sees
  std::uint32_t chunks_culled = 0;  // chunks that no view sees
  std::uint32_t draw_calls = 0;     // GL_POINTS: one per chunk and view; compute: dispatches
};

// One frame's input to a rasterizer.
struct RasterFrame {
  const DrawSet* draw_set = nullptr;
  std::span<const View> views;        // share one projection kind; at most kMaxViews
  std::span<const ClipRange> ranges;  // one per view
  const RenderSettings* settings = nullptr;
  bool eye_depth = false;  // write linear eye depth (colour attachment 1) for eye-dome lighting
  int canvas_width = 0, canvas_height = 0;  // the framebuffer's size
  // Items [first_item, last_item) of the draw set, or, when `items` is not empty, those items
  // only. Point ids count from the start of the draw set, whatever is drawn.
  std::size_t first_item = 0, last_item = std::numeric_limits<std::size_t>::max();
  std::span<const std::size_t> items;
  // Draw on top of the previous frame's picture (progressive refinement): the caller did not
  // clear, and the views, settings and canvas are those of the previous frame.
  bool accumulate = false;
};

class Rasterizer {
 public:
  virtual ~Rasterizer() = default;
  virtual RasterizerKind kind() const = 0;
  // Empty when this rasterizer draws frames with these settings on a canvas of this size;
  // otherwise why not, in words for the user (the renderer then falls back to GL_POINTS).
  virtual std::string unsupported(const RenderSettings& settings, int canvas_width,
                                  int canvas_height) const = 0;
  // Draws into the bound framebuffer, each view inside its viewport, with reversed depth (the
  // caller has cleared colour to the background and depth to 0, unless frame.accumulate, and
  // set glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE)).
  virtual RasterStats draw(const RasterFrame& frame) = 0;
};

// The filter's world-space clip planes in a chunk's coordinates, four floats a plane (unused
// planes zero): a p_world + d = a p_chunk + (a origin + d), the offset summed in double so that
// a plane at UTM coordinates keeps its precision.
inline std::array<float, 4 * PointFilter::kMaxClipPlanes> chunkClipPlanes(
    const PointFilter& filter, const glm::dvec3& origin) {
  std::array<float, 4 * PointFilter::kMaxClipPlanes> planes{};
  const std::size_t count = std::min(filter.clip_planes.size(), PointFilter::kMaxClipPlanes);
  for (std::size_t i = 0; i < count; ++i) {
    const auto& p = filter.clip_planes[i];
    planes[4 * i + 0] = float(p[0]), planes[4 * i + 1] = float(p[1]);
    planes[4 * i + 2] = float(p[2]);
    planes[4 * i + 3] = float(p[0] * origin.x + p[1] * origin.y + p[2] * origin.z + p[3]);
  }
  return planes;
}

// The class words the shaders test. Without a classification attribute the buffers hold class 1
// (what the classification colour shows), but the filter counts such points as class 0
// (core/point_filter.h): decided here for the whole draw set, all words set or none.
inline std::array<std::uint32_t, 8> filterClassWords(const PointFilter& filter,
                                                     bool has_classification) {
  if (has_classification) return filter.classes;
  std::array<std::uint32_t, 8> words{};
  words.fill(filter.keepsClass(0) ? ~0u : 0u);
  return words;
}

}  // namespace parallax
