// One frame of the interactive loop, what `parallax view` draws each frame and what `parallax
// bench render --orbit` measures: the part of the draw set progressive refinement plans, drawn
// (or, when the picture is already complete, shown again), and the drawing timed for the next
// plan. One place, so that the bench measures the viewer's own step.
#pragma once

#include <cstdint>

#include "render/draw_set.h"
#include "render/progressive.h"
#include "render/renderer.h"
#include "render/stereo.h"

namespace parallax {

struct FrameStepResult {
  FrameStats stats;     // of the part drawn (zero when nothing new was drawn)
  FramePart part;       // the part planned (the whole draw set without refinement)
  bool drew = false;    // false: the last picture was shown again (composite)
  double draw_s = 0.0;  // drawing time, to glFinish when refining
};

// Draws one frame of `draw_set` into `target`. With `progressive` (refinement on), its plan says
// which items (`changed`: the view changed since the last frame, the picture starts again); a
// plan with nothing new shows the last picture again, and the drawing is finished (glFinish) and
// recorded for the rate. Without, the whole draw set is drawn.
FrameStepResult drawFrameStep(Renderer& renderer, ProgressiveRefinement* progressive,
                              const DrawSet& draw_set, const StereoFrame& frame,
                              const RenderSettings& settings, GLuint target, int width, int height,
                              bool changed);

}  // namespace parallax
