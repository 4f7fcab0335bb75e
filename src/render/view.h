// A view: one camera and the rectangle of the target it draws into. Mono rendering is a list of
// one view; stereo (a later step) is a list of two, and every pass loops over the list.
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
};

}  // namespace parallax
