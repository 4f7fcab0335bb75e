// The overlay's primitives projected for one view, on the CPU in double: triangles in the
// target's pixels that the overlay pass (render/overlay_pass.h) fills and depth-tests.
//
// Why on the CPU: an overlay is a few hundred vertices at most, at world (UTM) coordinates. The
// camera and the points are in double here, so nothing jitters, and a segment crossing the near
// plane is clipped in eye space before projection (a GPU expansion of wide lines in clip space
// would fold such a segment behind the camera).
//
// Depth: every vertex carries 1 / (linear eye depth), which is affine in screen space, so the
// rasterizer's noperspective interpolation gives the exact eye depth of each fragment of a line.
// A marker or label is tested at its anchor's pixel (`test_x`, `test_y`), so the points drawn
// around a picked point do not cut its marker or its text; a line is tested per fragment
// (test_x < 0).
#pragma once

#include <array>
#include <optional>
#include <vector>

#include "render/overlay.h"
#include "render/view.h"

namespace parallax {

struct OverlayVertex {
  float x = 0, y = 0;              // pixel of the target (bottom-left origin), fractional
  float inverse_depth = 0;         // 1 / linear eye depth (world units)
  float test_x = -1, test_y = -1;  // pixel whose scene depth decides; -1: the fragment's own
  float u = -1, v = -1;            // font atlas coordinates; u < 0: a solid colour
  std::array<float, 4> color{1, 1, 1, 1};
};

// Where a world position lands in a view: the pixel (bottom-left origin, fractional, in the
// target's coordinates: viewport offset included) and the linear eye depth. std::nullopt behind
// the near plane.
struct ProjectedPoint {
  double x = 0, y = 0, eye_depth = 0;
};
std::optional<ProjectedPoint> projectToView(const View& view, const ClipRange& range,
                                            const glm::dvec3& world);

// Glyph metrics and atlas coordinates of a font, for labels (render/overlay_font.h fills it).
struct OverlayGlyph {
  float x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // quad relative to the pen, pixels, y down
  float u0 = 0, v0 = 0, u1 = 0, v1 = 0;  // atlas coordinates
  float advance = 0;
};
class OverlayGlyphs {
 public:
  virtual ~OverlayGlyphs() = default;
  // The glyph of a code point, or of '?' where the font has none.
  virtual const OverlayGlyph& glyph(unsigned codepoint) const = 0;
  virtual float lineHeight() const = 0;
};

// The triangles of `scene` in `view` (three vertices each), clipped to the near plane. Labels
// need `glyphs`; without, they are left out.
std::vector<OverlayVertex> overlayTriangles(const OverlayScene& scene, const View& view,
                                            const ClipRange& range, const OverlayGlyphs* glyphs);

// The triangles of one image's quad in `view` (three vertices each; none when it is wholly
// behind the near plane), clipped to the near plane in eye space. Tested per fragment (test_x
// -1), coloured white. (u, v) are the picture's coordinates (0, 0 at its top-left corner, 1, 1 at
// its bottom-right, as a texture of its rows uploaded top row first samples them) divided by the
// eye depth in perspective, so that the pass's noperspective interpolation of (u, v) and of
// inverse_depth gives the perspective-correct coordinates (u, v) / inverse_depth; in
// orthographic (depth affine in screen space) they are (u, v) themselves.
std::vector<OverlayVertex> overlayImageTriangles(const OverlayImage& image, const View& view,
                                                 const ClipRange& range);

}  // namespace parallax
