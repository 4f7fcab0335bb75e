// The frame: clears, runs the point pass for every view (into a multisampled framebuffer that is
// then resolved, when settings.samples asks for one), then eye-dome lighting or a copy into the
// caller's framebuffer, or, for the composed stereo modes, into a canvas that the stereo
// compositor turns into the output. Owns the intermediate framebuffers the passes share.
#pragma once

#include <epoxy/gl.h>

#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "render/compute_rasterizer.h"
#include "render/draw_set.h"
#include "render/edl_pass.h"
#include "render/overlay.h"
#include "render/overlay_pass.h"
#include "render/point_pass.h"
#include "render/stereo.h"
#include "render/stereo_compositor.h"
#include "render/view.h"

namespace parallax {

struct FrameStats {
  std::uint64_t points_drawn = 0;   // points of the chunks drawn (once, whatever the view count)
  std::uint32_t chunks_drawn = 0;   // chunks some view sees: bound once each
  std::uint32_t chunks_culled = 0;  // chunks no view sees: not touched
  std::uint32_t draw_calls = 0;     // GL_POINTS: per chunk and view; compute: dispatches
  RasterizerKind rasterizer = RasterizerKind::Points;  // who drew (never Auto)
  // Why the compute rasterizer did not draw although asked (explicitly or by auto); empty
  // otherwise. Also says when --hq was ignored.
  std::string fallback_reason;
};

// Which part of a draw set a frame draws: progressive refinement draws the most important items
// first, then the rest on top of the same picture (render/progressive.h).
struct FramePart {
  std::size_t first_item = 0, last_item = std::numeric_limits<std::size_t>::max();
  // Draw on top of the last frame's picture (same views, settings, size and composition) instead
  // of clearing it.
  bool accumulate = false;
};

// A picked point: where it is and, when the compute rasterizer drew it, exactly which point.
struct PickedPoint {
  glm::dvec3 position{0.0};       // world coordinates
  std::optional<PointRef> point;  // the point itself (compute only): item, chunk, index, id
  int view = 0;                   // the view the pixel belongs to
};
class Renderer {
 public:
  // Needs a current 4.5 context for its whole life. The compute rasterizer is made on first use.
  explicit Renderer(const ComputeRasterizerOptions& compute_options = {});
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  // Renders `draw_set` for every view into framebuffer `target` (0: the window's) of `width` x
  // `height` pixels. Composition::Direct: viewports in pixels of the target (bottom-left
  // origin). Otherwise the views are the two eyes of a StereoFrame, drawn into a canvas of
  // 2 * width x height (left eye at x 0, right eye at x width) that the stereo compositor turns
  // into the output. Leaves glClipControl at OpenGL's default so that other drawing (the
  // on-screen panel) is unaffected.
  //
  // settings.rasterizer picks who draws: GL_POINTS, the compute rasterizer, or (auto) compute
  // wherever it supports the settings; where it does not, GL_POINTS draws and
  // FrameStats::fallback_reason says why. `part` draws some items only (progressive refinement).
  FrameStats render(const DrawSet& draw_set, std::span<const View> views,
                    const RenderSettings& settings, GLuint target, int width, int height,
                    Composition composition = Composition::Direct, const FramePart& part = {});
  // All chunks of a whole uploaded cloud (GpuPointCloud::drawSet()).
  FrameStats render(const GpuPointCloud& cloud, std::span<const View> views,
                    const RenderSettings& settings, GLuint target, int width, int height,
                    Composition composition = Composition::Direct);
  // One frame of `frame` (stereoFrame's views and composition).
  FrameStats render(const DrawSet& draw_set, const StereoFrame& frame,
                    const RenderSettings& settings, GLuint target, int width, int height,
                    const FramePart& part = {}) {
    return render(draw_set, frame.views, settings, target, width, height, frame.composition, part);
  }

  // Who would draw a frame with these settings into a width x height output with this
  // composition, and why not compute where it was asked for (empty: no fall-back).
  RasterizerKind chooseRasterizer(const RenderSettings& settings, int width, int height,
                                  Composition composition, std::string* reason = nullptr);

  // Writes the last frame's picture into `target` again (eye-dome lighting, a copy or the stereo
  // composition) without drawing a point: what a window shows while nothing changed. False (and
  // nothing written) when the last frame had another size or composition, or there was none.
  bool composite(std::span<const View> views, const RenderSettings& settings, GLuint target,
                 int width, int height, Composition composition = Composition::Direct);

  // The world position of the point drawn at pixel (x, y) of the output (bottom-left origin) in
  // the last frame, std::nullopt where no point was drawn or (x, y) is outside every view. In the
  // composed stereo modes (anaglyph, interlaced, quad-buffer) the left eye's picture is read.
  std::optional<glm::dvec3> pick(int x, int y) const;
  // As pick(), with the point itself where the compute rasterizer drew the pixel: its position
  // is then the point's own (not the pixel centre at its depth), exactly as the GPU holds it.
  std::optional<PickedPoint> pickPoint(int x, int y) const;
  // The index of the last frame's view whose viewport holds pixel (x, y) (bottom-left origin),
  // -1 where none does.
  int viewAt(int x, int y) const;
  // Who drew the last frame (Points also when there was none).
  RasterizerKind lastRasterizer() const { return last_rasterizer_; }

  // The compute rasterizer, made on first use (needs the current context).
  ComputeRasterizer& computeRasterizer();

  // Lines, markers and labels drawn over every picture from now on (render/overlay_pass.h): by
  // render() and composite() alike, each view with its own camera, depth-tested against the
  // frame's points, before the stereo composition (so each eye has its own). An empty scene
  // draws nothing. Changing it needs no new frame: composite() shows it.
  void setOverlay(OverlayScene scene) { overlay_ = std::move(scene); }
  const OverlayScene& overlay() const { return overlay_; }
  void setOverlayDepth(const OverlayDepthSettings& depth) { overlay_depth_ = depth; }

 private:
  // (Re)creates the framebuffers for a size and a sample count (0: no multisampled one).
  void resize(int width, int height, int samples);
  // settings.samples made valid: 0 (off) or 2..GL_MAX_SAMPLES.
  int samplesFor(const RenderSettings& settings);
  // Copies the multisampled colour and depth (and eye depth) into `framebuffer_`, averaging
  // colour over each pixel's samples.
  void resolve(bool eye_depth);

  // The single-sample canvas with eye-dome lighting applied, for the compositor to read
  // (composed stereo modes with EDL only); made on first use.
  void ensurePostTarget();

  // Draws overlay_ for the last frame's views into the bound framebuffer (the canvas's size).
  void drawOverlay();

  PointPass point_pass_;
  OverlayScene overlay_;
  OverlayDepthSettings overlay_depth_;
  std::unique_ptr<OverlayPass> overlay_pass_;  // made on the first overlay drawn
  ComputeRasterizerOptions compute_options_;
  std::unique_ptr<ComputeRasterizer> compute_;
  RasterizerKind last_rasterizer_ = RasterizerKind::Points;
  EdlPass edl_pass_;
  std::optional<StereoCompositor> compositor_;  // made on the first composed frame
  GLuint post_framebuffer_ = 0, post_color_ = 0;
  // The single-sample picture that eye-dome lighting, the copy to the target and picking read.
  GLuint framebuffer_ = 0;
  GLuint color_ = 0, eye_depth_ = 0, depth_ = 0;
  // With multisampling, points are drawn here and resolved into `framebuffer_`.
  GLuint ms_framebuffer_ = 0;
  GLuint ms_color_ = 0, ms_eye_depth_ = 0, ms_depth_ = 0;
  int width_ = 0, height_ = 0, samples_ = 0;
  int max_samples_ = -1;  // GL_MAX_SAMPLES, queried on first use
  bool last_edl_ = false;
  Composition last_composition_ = Composition::Direct;
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
