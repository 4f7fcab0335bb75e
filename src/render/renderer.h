// The frame: clears, runs the point pass for every view, then eye-dome lighting or a copy into
// the caller's framebuffer. Owns the intermediate framebuffer the passes share.
#pragma once

#include <epoxy/gl.h>

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "render/edl_pass.h"
#include "render/point_pass.h"
#include "render/view.h"

namespace parallax {

struct FrameStats {
  std::uint64_t points_drawn = 0;
  std::uint32_t chunks_drawn = 0;
  std::uint32_t chunks_culled = 0;
};

class Renderer {
 public:
  Renderer();  // needs a current 4.5 context for its whole life
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  // Renders `views` (viewports in pixels of the target, bottom-left origin) into framebuffer
  // `target` (0: the window's) of `width` x `height` pixels. Leaves glClipControl at OpenGL's
  // default so that other drawing (the on-screen panel) is unaffected.
  FrameStats render(const GpuPointCloud& cloud, std::span<const View> views,
                    const RenderSettings& settings, GLuint target, int width, int height);

  // The world position of the point drawn at pixel (x, y) (bottom-left origin) in the last
  // frame, std::nullopt where no point was drawn or (x, y) is outside every view.
  std::optional<glm::dvec3> pick(int x, int y) const;

 private:
  void resize(int width, int height);

  PointPass point_pass_;
  EdlPass edl_pass_;
  GLuint framebuffer_ = 0;
  GLuint color_ = 0, eye_depth_ = 0, depth_ = 0;
  int width_ = 0, height_ = 0;
  struct DrawnView {
    View view;
    ClipRange range;
  };
  std::vector<DrawnView> last_views_;
};

// An offscreen RGBA8 framebuffer for headless rendering, read back as a top-row-first image.
class RenderTarget {
 public:
  RenderTarget(int width, int height);
  ~RenderTarget();
  RenderTarget(const RenderTarget&) = delete;
  RenderTarget& operator=(const RenderTarget&) = delete;

  GLuint framebuffer() const { return framebuffer_; }
  int width() const { return width_; }
  int height() const { return height_; }
  // width * height * 4 bytes, RGBA, the first row the top of the picture (as PNG stores it).
  std::vector<std::uint8_t> readRgba() const;

 private:
  GLuint framebuffer_ = 0, color_ = 0;
  int width_, height_;
};

}  // namespace parallax
