// Progressive refinement for level-of-detail frames and whole clouds (as CloudCompare and Potree do): while the
// camera moves, each frame draws the most important items of the draw set (a LodScene lists its
// nodes in priority order) that fit a time budget at the rate measured on the last frames; once
// the camera stops, the rest is drawn on top of the same picture, a budget at a time, until the
// picture is complete. Either rasterizer can draw on top (FramePart::accumulate), and the
// finished picture is the one a single frame would draw.
//
// Pure CPU bookkeeping (no GL): tests/render/test_progressive.cpp.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "render/draw_set.h"
#include "render/renderer.h"
#include "render/view.h"

namespace parallax {

struct ProgressiveSettings {
  // Seconds of drawing per frame: 1/15 s keeps a moving camera at about 15 frames a second.
  double frame_budget_s = 1.0 / 15.0;
  // Rate assumed before the first frame is measured (points/s): the compute rasterizer's on
  // two cores of llvmpipe, so the first frame is about the budget there and far under it on a GPU.
  double initial_points_per_second = 30e6;
};

// A whole cloud's draw set (a GpuPointCloud's chunks, in file order) reordered for progressive
// refinement, as a LodScene orders its nodes: the chunks that look largest first (their box's
// diagonal over the distance from the nearest eye to the box, which is 0 for an eye inside it),
// those outside every view's frustum last (the renderer skips them; they cost the budget
// nothing). Everything else is `draw_set`'s. The same camera gives the same order, so a still
// camera's picture is completed on top of the parts already drawn, and the finished picture is
// that of the whole set: chunks do not overlap in depth order differently by being drawn later
// (the depth test decides, and equal depths are rare enough to be a few pixels at most).
DrawSet prioritizedDrawSet(const DrawSet& draw_set, std::span<const View> views);

class ProgressiveRefinement {
 public:
  explicit ProgressiveRefinement(const ProgressiveSettings& settings = {})
      : settings_(settings), points_per_second_(settings.initial_points_per_second) {}

  // The part of `draw_set` the next frame draws. `changed`: the camera, a setting or the size
  // changed since the last frame (the picture starts again). The draw set may have changed too
  // (a streaming LodScene): when the items already drawn are no longer its first items, the
  // picture starts again as well. An empty part (first_item == last_item) means the picture is
  // complete: nothing to draw.
  FramePart plan(const DrawSet& draw_set, bool changed);
  // What the planned frame drew and how long it took (drawing only), for the rate.
  void record(std::uint64_t points, double seconds);

  // The last planned part reaches the end of the draw set.
  bool complete() const { return complete_; }
  double pointsPerSecond() const { return points_per_second_; }
  const ProgressiveSettings& settings() const { return settings_; }
  void setSettings(const ProgressiveSettings& settings) { settings_ = settings; }

 private:
  ProgressiveSettings settings_;
  double points_per_second_;
  // The items drawn into the current picture, as (chunk, spacing), in draw-set order.
  std::vector<std::pair<const PointChunk*, float>> drawn_;
  bool complete_ = false;
};

}  // namespace parallax
