#include "render/overlay_geometry.h"

#include <algorithm>
#include <cmath>
#include <string_view>

namespace parallax {

namespace {

constexpr float kLabelOffsetPx = 8.0f;   // the text's corner, up and right of its anchor
constexpr float kLabelPaddingPx = 3.0f;  // the dark box around the text

// A point in eye space and the view's matrices, kept together for clipping and projection.
struct ViewTransform {
  glm::dmat4 world_to_eye;
  glm::dmat4 projection;
  Viewport viewport;
  double near_plane;
  bool perspective;

  ViewTransform(const View& view, const ClipRange& range)
      : world_to_eye(view.camera.viewMatrix()),
        projection(view.camera.projectionMatrix(view.aspect(), range)),
        viewport(view.viewport),
        near_plane(range.near_plane),
        perspective(view.camera.projection == Projection::Perspective) {}

  glm::dvec3 eye(const glm::dvec3& world) const {
    return glm::dvec3(world_to_eye * glm::dvec4(world, 1.0));
  }
  double depth(const glm::dvec3& eye_point) const { return -eye_point.z; }
  bool inFront(const glm::dvec3& eye_point) const {
    // Perspective needs a depth strictly above 0 to divide by; the near plane is above 0 there.
    return depth(eye_point) >= near_plane && (!perspective || depth(eye_point) > 0);
  }
  ProjectedPoint project(const glm::dvec3& eye_point) const {
    const glm::dvec4 clip = projection * glm::dvec4(eye_point, 1.0);
    const double nx = clip.x / clip.w, ny = clip.y / clip.w;
    return {viewport.x + (nx * 0.5 + 0.5) * viewport.width,
            viewport.y + (ny * 0.5 + 0.5) * viewport.height, depth(eye_point)};
  }
  // What the vertex carries for the depth: affine in screen space (see the header).
  float depthVarying(double eye_depth) const {
    return perspective ? float(1.0 / eye_depth) : float(eye_depth);
  }
};

void pushQuad(std::vector<OverlayVertex>& out, const OverlayVertex& a, const OverlayVertex& b,
              const OverlayVertex& c, const OverlayVertex& d) {
  // a b c d counter-clockwise: two triangles a b c and a c d.
  out.insert(out.end(), {a, b, c, a, c, d});
}

void pushSegment(std::vector<OverlayVertex>& out, const ViewTransform& t, glm::dvec3 a,
                 glm::dvec3 b, const OverlayColor& color, float width_px) {
  // Clip to the near plane in eye space (the part behind it would project mirrored).
  const bool a_in = t.inFront(a), b_in = t.inFront(b);
  if (!a_in && !b_in) return;
  if (!a_in || !b_in) {
    // Just inside the near plane, so that the clipped end still passes inFront's test.
    const double limit = t.perspective ? std::max(t.near_plane, 1e-9) * (1.0 + 1e-9)
                                       : t.near_plane + 1e-9 * std::abs(t.near_plane) + 1e-12;
    glm::dvec3& out_end = a_in ? b : a;
    const glm::dvec3& in_end = a_in ? a : b;
    const double s = (limit - t.depth(in_end)) / (t.depth(out_end) - t.depth(in_end));
    out_end = in_end + s * (out_end - in_end);
  }
  const ProjectedPoint pa = t.project(a), pb = t.project(b);
  glm::dvec2 direction(pb.x - pa.x, pb.y - pa.y);
  const double length = glm::length(direction);
  if (!(length > 1e-6)) return;  // seen end on: the markers show it
  direction /= length;
  const glm::dvec2 side = glm::dvec2(-direction.y, direction.x) * (0.5 * width_px);
  auto vertex = [&](const ProjectedPoint& p, double sign) {
    OverlayVertex v;
    v.x = float(p.x + sign * side.x);
    v.y = float(p.y + sign * side.y);
    v.inverse_depth = t.depthVarying(p.eye_depth);
    v.color = color;
    return v;
  };
  pushQuad(out, vertex(pa, -1), vertex(pb, -1), vertex(pb, 1), vertex(pa, 1));
}

// A solid rectangle [x0, x1] x [y0, y1] in pixels at one depth, tested at (tx, ty).
void pushRect(std::vector<OverlayVertex>& out, float x0, float y0, float x1, float y1,
              float depth_varying, float tx, float ty, const OverlayColor& color, float u0 = -1,
              float v0 = -1, float u1 = -1, float v1 = -1) {
  auto vertex = [&](float x, float y, float u, float v) {
    OverlayVertex corner;
    corner.x = x, corner.y = y;
    corner.inverse_depth = depth_varying;
    corner.test_x = tx, corner.test_y = ty;
    corner.u = u, corner.v = v;
    corner.color = color;
    return corner;
  };
  pushQuad(out, vertex(x0, y0, u0, v1), vertex(x1, y0, u1, v1), vertex(x1, y1, u1, v0),
           vertex(x0, y1, u0, v0));
}

// The code points of UTF-8 text; a malformed byte stands for itself (Latin-1), never an error.
std::vector<unsigned> decodeUtf8(std::string_view text) {
  std::vector<unsigned> codepoints;
  for (std::size_t i = 0; i < text.size();) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    int extra = c >= 0xF0 ? 3 : c >= 0xE0 ? 2 : c >= 0xC0 ? 1 : 0;
    unsigned codepoint = extra == 3 ? c & 0x07u : extra == 2 ? c & 0x0Fu : c & 0x1Fu;
    bool valid = extra > 0 && i + std::size_t(extra) < text.size();
    for (int k = 1; valid && k <= extra; ++k) {
      const unsigned char next = static_cast<unsigned char>(text[i + std::size_t(k)]);
      valid = (next & 0xC0u) == 0x80u;
      codepoint = (codepoint << 6) | (next & 0x3Fu);
    }
    if (valid) {
      codepoints.push_back(codepoint);
      i += std::size_t(extra) + 1;
    } else {
      codepoints.push_back(c);
      ++i;
    }
  }
  return codepoints;
}

// A corner of an image's quad in eye space with its picture coordinates, for clipping.
struct ImageCorner {
  glm::dvec3 eye;
  glm::dvec2 uv;
};

}  // namespace

std::vector<OverlayVertex> overlayImageTriangles(const OverlayImage& image, const View& view,
                                                 const ClipRange& range) {
  const ViewTransform t(view, range);
  // bottom-left, bottom-right, top-right, top-left; v = 0 is the picture's top row.
  const glm::dvec2 uv[4] = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
  std::vector<ImageCorner> polygon;
  for (int i = 0; i < 4; ++i) polygon.push_back({t.eye(image.corners[std::size_t(i)]), uv[i]});
  // Sutherland-Hodgman against the near plane alone (the scissor and the viewport cut the rest),
  // just inside it as pushSegment clips, so that every kept corner passes inFront.
  const double limit = t.perspective ? std::max(t.near_plane, 1e-9) * (1.0 + 1e-9)
                                     : t.near_plane + 1e-9 * std::abs(t.near_plane) + 1e-12;
  std::vector<ImageCorner> clipped;
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    const ImageCorner& a = polygon[i];
    const ImageCorner& b = polygon[(i + 1) % polygon.size()];
    const bool a_in = t.inFront(a.eye), b_in = t.inFront(b.eye);
    if (a_in) clipped.push_back(a);
    if (a_in != b_in) {
      const double s = (limit - t.depth(a.eye)) / (t.depth(b.eye) - t.depth(a.eye));
      clipped.push_back({a.eye + s * (b.eye - a.eye), a.uv + s * (b.uv - a.uv)});
    }
  }
  std::vector<OverlayVertex> out;
  if (clipped.size() < 3) return out;
  std::vector<OverlayVertex> corners;
  for (const ImageCorner& c : clipped) {
    const ProjectedPoint p = t.project(c.eye);
    OverlayVertex v;
    v.x = float(p.x);
    v.y = float(p.y);
    v.inverse_depth = t.depthVarying(p.eye_depth);
    const double per_depth = t.perspective ? 1.0 / p.eye_depth : 1.0;
    v.u = float(c.uv.x * per_depth);
    v.v = float(c.uv.y * per_depth);
    corners.push_back(v);
  }
  // A convex polygon (a quad cut by one plane): a fan from its first corner.
  for (std::size_t i = 1; i + 1 < corners.size(); ++i) {
    out.insert(out.end(), {corners[0], corners[i], corners[i + 1]});
  }
  return out;
}

std::optional<ProjectedPoint> projectToView(const View& view, const ClipRange& range,
                                            const glm::dvec3& world) {
  const ViewTransform t(view, range);
  const glm::dvec3 eye = t.eye(world);
  if (!t.inFront(eye)) return std::nullopt;
  return t.project(eye);
}

std::vector<OverlayVertex> overlayTriangles(const OverlayScene& scene, const View& view,
                                            const ClipRange& range, const OverlayGlyphs* glyphs) {
  const ViewTransform t(view, range);
  std::vector<OverlayVertex> out;
  for (const OverlayPolyline& line : scene.polylines) {
    const std::size_t n = line.points.size();
    if (n < 2) continue;
    const std::size_t segments = line.closed && n >= 3 ? n : n - 1;
    for (std::size_t i = 0; i < segments; ++i) {
      pushSegment(out, t, t.eye(line.points[i]), t.eye(line.points[(i + 1) % n]), line.color,
                  line.width_px);
    }
  }
  // Labels (they need a font), then markers on top: a label's box may fall on a vertex of
  // another segment, whose marker must stay visible. Labels never overlap: each is placed at its
  // anchor or, where an earlier-placed one is, moved a line up or down (a polygon's short edges
  // and its area, side by side); one that finds no free place within a few lines is left out.
  // The scene's last labels are placed first: a measurement lists its totals last
  // (measurementLabels), and they matter more than its segments.
  const std::vector<OverlayLabel> no_labels;
  const std::vector<OverlayLabel>& labels = glyphs ? scene.labels : no_labels;
  struct Box {
    float x0, y0, x1, y1;
  };
  std::vector<Box> placed;
  for (std::size_t k = labels.size(); k-- > 0;) {
    const OverlayLabel& label = labels[k];
    const glm::dvec3 eye = t.eye(label.anchor);
    if (!t.inFront(eye) || label.text.empty()) continue;
    const ProjectedPoint p = t.project(eye);
    const float depth = t.depthVarying(p.eye_depth);
    const float tx = std::floor(float(p.x)), ty = std::floor(float(p.y));
    const std::vector<unsigned> codepoints = decodeUtf8(label.text);
    float width = 0;
    for (unsigned c : codepoints) width += glyphs->glyph(c).advance;
    // Whole pixels: the atlas's texels land on the target's pixels, so the text stays crisp.
    const float left = std::round(float(p.x) + kLabelOffsetPx);
    const float step = glyphs->lineHeight() + 2 * kLabelPaddingPx + 1;
    std::optional<Box> free_box;
    for (int attempt = 0; attempt < 7 && !free_box; ++attempt) {
      const float shift = float((attempt + 1) / 2) * (attempt % 2 ? -step : step);
      const float bottom = std::round(float(p.y) + kLabelOffsetPx) + shift;
      const Box box{left - kLabelPaddingPx, bottom - kLabelPaddingPx,
                    left + width + kLabelPaddingPx,
                    bottom + glyphs->lineHeight() + kLabelPaddingPx};
      const bool overlaps = std::any_of(placed.begin(), placed.end(), [&](const Box& other) {
        return box.x0 < other.x1 && other.x0 < box.x1 && box.y0 < other.y1 && other.y0 < box.y1;
      });
      if (!overlaps) free_box = box;
    }
    if (!free_box) continue;
    placed.push_back(*free_box);
    const float bottom = free_box->y0 + kLabelPaddingPx;
    const float top = bottom + glyphs->lineHeight();
    pushRect(out, free_box->x0, free_box->y0, free_box->x1, free_box->y1, depth, tx, ty,
             {0, 0, 0, 0.6f * label.color[3]});
    float pen = left;
    for (unsigned c : codepoints) {
      const OverlayGlyph& g = glyphs->glyph(c);
      if (g.x1 > g.x0 && g.y1 > g.y0) {
        // Glyph boxes are y down from the line's top; pixels here are y up.
        pushRect(out, pen + g.x0, top - g.y1, pen + g.x1, top - g.y0, depth, tx, ty, label.color,
                 g.u0, g.v0, g.u1, g.v1);
      }
      pen += g.advance;
    }
  }
  for (const OverlayMarker& marker : scene.markers) {
    const glm::dvec3 eye = t.eye(marker.position);
    if (!t.inFront(eye)) continue;
    const ProjectedPoint p = t.project(eye);
    const float depth = t.depthVarying(p.eye_depth);
    const float tx = std::floor(float(p.x)), ty = std::floor(float(p.y));
    const float h = 0.5f * marker.size_px;
    // A dark rim, then the colour: visible on any background.
    pushRect(out, float(p.x) - h - 1, float(p.y) - h - 1, float(p.x) + h + 1, float(p.y) + h + 1,
             depth, tx, ty, {0, 0, 0, marker.color[3]});
    pushRect(out, float(p.x) - h, float(p.y) - h, float(p.x) + h, float(p.y) + h, depth, tx, ty,
             marker.color);
  }
  return out;
}

}  // namespace parallax
