#include "render/frame_step.h"

#include <algorithm>
#include <chrono>

namespace parallax {

FrameStepResult drawFrameStep(Renderer& renderer, ProgressiveRefinement* progressive,
                              const DrawSet& draw_set, const StereoFrame& frame,
                              const RenderSettings& settings, GLuint target, int width, int height,
                              bool changed) {
  FrameStepResult result;
  if (progressive) result.part = progressive->plan(draw_set, changed);
  const auto start = std::chrono::steady_clock::now();  // drawing only, as record() asks
  const FramePart& part = result.part;
  const bool nothing_new =
      part.accumulate && part.first_item >= std::min(part.last_item, draw_set.items.size());
  if (nothing_new) {
    // Complete already (a streaming scene whose selection has not changed): show it again.
    renderer.composite(frame.views, settings, target, width, height, frame.composition);
  } else {
    result.stats = renderer.render(draw_set, frame, settings, target, width, height, part);
    result.drew = true;
  }
  if (progressive) {
    // The rate is measured on finished drawing (a GPU queues the work otherwise).
    glFinish();
    result.draw_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    progressive->record(result.stats.points_drawn, result.draw_s);
  }
  return result;
}

}  // namespace parallax
