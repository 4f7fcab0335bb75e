// What the overlay pass draws over the points: polylines, markers, text labels and pictures on
// flat quads (panels) at 3D positions, in world coordinates (double). Built by the measurement module
// (measure/measurement_overlay.h) or by anything else that marks places in a cloud; drawn by
// render/overlay_pass.h, depth-tested against the points of the frame.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
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

// A picture on a flat quad standing in the scene (a panel: the headset's profile plot). The
// picture's corners go to `corners` in the order bottom-left, bottom-right, top-right, top-left
// (as the picture is seen from the side it faces; any parallelogram, drawn with perspective-correct
// texture coordinates), depth-tested per pixel like a line. The pixels are shared, not copied, so
// a scene rebuilt every frame does not copy them; the pass uploads them once while the same
// block is in its scenes (the block's address is the key: replace the pointer, never the pixels
// behind it, to change a picture).
struct OverlayImage {
  std::array<glm::dvec3, 4> corners{};  // world coordinates
  int width = 0, height = 0;            // pixels, > 0
  // width * height RGBA8 pixels, the top row first, straight (not premultiplied) alpha.
  std::shared_ptr<const std::vector<std::uint8_t>> rgba;
};

struct OverlayScene {
  std::vector<OverlayPolyline> polylines;
  std::vector<OverlayMarker> markers;
  std::vector<OverlayLabel> labels;
  std::vector<OverlayImage> images;  // drawn first: the lines and labels go over them
  bool empty() const {
    return polylines.empty() && markers.empty() && labels.empty() && images.empty();
  }
};

}  // namespace parallax
