// Picking a point with all its attributes: which point of the source is drawn at a pixel (or
// nearest to it), read back from the source at the file's precision.
//
// The GPU holds each point as a Morton-reordered, chunk-relative float: good for a picture, not
// for a measurement (a float is 6 cm at a UTM easting). So the pick goes pixel -> draw-set item and
// index in its chunk (the compute rasterizer's visibility buffer names the front-most point of
// every pixel) -> the source's index (PointChunk::source_indices) -> the source: the PointCloud
// that was uploaded whole, or the octree node (DrawItem::node) that Octree::loadNodeWhole() reads
// again (the last two nodes read are kept). Positions are the source's quantized integers times
// its scale plus its offset, in double: exactly the file's values.
#pragma once

#include <cstdint>
#include <deque>
#include <glm/glm.hpp>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "core/point_cloud.h"
#include "lod/octree.h"
#include "render/draw_set.h"
#include "render/renderer.h"
#include "render/stereo.h"

namespace parallax {

// One attribute of a picked point, under PointCloud::attributeNames()'s name (x, y, z first).
// Colours are the model's 8 bits; other scalars as the source typed them, converted to double.
struct PointAttribute {
  std::string name;
  double value = 0.0;
};

// The shortest text that reads back as exactly `value` ("500000.137", "2", "1e-07").
std::string formatAttributeValue(double value);

// Every attribute of the source's point `index` (index < cloud.count), x y z in world units.
std::vector<PointAttribute> pointAttributes(const PointCloud& cloud, std::size_t index);

struct PickResult {
  glm::dvec3 position{0.0};                // world coordinates, the source's own values
  std::vector<PointAttribute> attributes;  // x, y, z, then the rest
  int view = 0;                            // the view (eye) the pixel belongs to
  int pixel_x = 0, pixel_y = 0;            // where the point was found (bottom-left origin)
  double distance_px = 0.0;                // from the asked pixel to that one
};

// What a draw set's chunks were staged from. Holds references: the cloud or octree must outlive
// it. Not thread-safe (the node cache).
class PickSource {
 public:
  explicit PickSource(const PointCloud& cloud) : cloud_(&cloud) {}
  explicit PickSource(const Octree& octree) : octree_(&octree) {}

  // The source point that item `item`'s chunk holds at `index`. Throws InputError where the octree
  // node cannot be read again.
  std::pair<glm::dvec3, std::vector<PointAttribute>> point(const DrawItem& item,
                                                           std::uint32_t index);

 private:
  const PointCloud& nodePoints(std::int32_t node);

  const PointCloud* cloud_ = nullptr;
  const Octree* octree_ = nullptr;
  std::deque<std::pair<std::int32_t, PointCloud>> nodes_;  // most recent first, at most 2
};

struct PickRequest {
  int x = 0, y = 0;  // pixel of the output, bottom-left origin
  // Where no point covers the pixel: the nearest point drawn within this many pixels (in the
  // same view), nearest on screen first, then nearest in depth.
  int radius_px = 3;
  // True when `renderer`'s last frame drew exactly `draw_set` with these views and settings, in
  // one whole part: its visibility buffer is used as it is if the compute rasterizer drew it.
  bool last_frame_matches = false;
};

// The point under the request's pixel of the frame (draw_set, views, settings) at width x height,
// or std::nullopt where no point is drawn within the radius.
//
// Exactness: only the compute rasterizer knows which point won a pixel (its ids), and GL_POINTS
// gives a depth only. When the last frame was not the compute rasterizer's (or not this frame),
// the frame is drawn again with it, offscreen: the same settings give the same points, sizes and
// front-most order (the compute shader sizes and tests points as the GL_POINTS shader does), so
// the id read is the point the picture shows, not a guess from a depth: every pixel a splat
// covers (any size mode, square or round, each stereo eye) names its front-most point. Where the
// compute rasterizer cannot draw the frame at all (a canvas beyond one binding of its visibility
// buffer), it draws 1-pixel points: the pick is then the point whose centre is nearest the
// pixel, front-most first, which is still one exact source point. That redraw becomes the
// renderer's last frame: a caller that composites the last frame again (Renderer::composite)
// must draw its own frame again instead.
std::optional<PickResult> pickPoint(Renderer& renderer, PickSource& source, const DrawSet& draw_set,
                                    std::span<const View> views, Composition composition,
                                    const RenderSettings& settings, int width, int height,
                                    const PickRequest& request);

}  // namespace parallax
