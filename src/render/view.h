// A view: one camera and the rectangle of the target it draws into. Mono rendering is a list of
// one view; stereo a list of two (left eye first, see render/stereo.h), and every pass loops over
// the list.
#pragma once

#include "render/camera.h"

namespace parallax {

// Pixels, origin at the target's bottom-left corner (OpenGL's convention).
struct Viewport {
  int x = 0, y = 0, width = 1, height = 1;
  double aspect() const { return double(width) / double(height > 0 ? height : 1); }
};

struct View {
  Camera camera;
  Viewport viewport;
  // The projection's width / height; 0: the viewport's. Side-by-side squeezed draws a picture
  // of the whole output's aspect into a half-width viewport (anamorphic, as 3D TVs expect).
  double projection_aspect = 0.0;
  // Where the view's picture lands on the output the user sees, which the point budget is for
  // (NodeSelectionSettings::point_budget): an sbs eye's half of the window, or the whole window
  // for an anaglyph eye drawn in a double-width canvas. Width 0: not stated (a headset's eye,
  // each its own picture); such a view gets the whole budget.
  Viewport output{0, 0, 0, 0};

  double aspect() const { return projection_aspect > 0 ? projection_aspect : viewport.aspect(); }
};

}  // namespace parallax
