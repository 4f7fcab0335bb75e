// What the overlay pass draws over the points: polylines, markers and text labels at 3D
// positions, in world coordinates (double). Built by the measurement module
// (measure/measurement_overlay.h) or by anything else that marks places in a cloud; drawn by
// render/overlay_pass.h, depth-tested against the points of the frame.
#pragma once

#include <array>
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace parallax {

using OverlayColor = std::array<float, 4>;  // RGBA, 0..1, not premultiplied

struct OverlayPolyline {
  std::vector<glm::dvec3> points;  // world coordinates
  bool closed = false;             // joins the last point to the first
  OverlayColor color{1, 1, 0, 1};
  float width_px = 2.0f;
};

struct OverlayMarker {
  glm::dvec3 position{0.0};
  OverlayColor color{1, 1, 0, 1};
  float size_px = 9.0f;  // the side of the square drawn around the position
};

struct OverlayLabel {
  glm::dvec3 anchor{0.0};  // the text's bottom-left corner sits a few pixels up-right of it
  std::string text;        // UTF-8; the PNG font covers ASCII and Latin-1
  OverlayColor color{1, 1, 1, 1};
};

struct OverlayScene {
  std::vector<OverlayPolyline> polylines;
  std::vector<OverlayMarker> markers;
  std::vector<OverlayLabel> labels;
  bool empty() const { return polylines.empty() && markers.empty() && labels.empty(); }
};

}  // namespace parallax
