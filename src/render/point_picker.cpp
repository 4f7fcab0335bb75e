#include "render/point_picker.h"

#include <algorithm>
#include <cassert>
#include <charconv>
#include <cmath>
#include <tuple>

#include "core/column_names.h"

namespace parallax {

std::string formatAttributeValue(double value) {
  char text[32];
  const auto end = std::to_chars(text, text + sizeof text, value).ptr;
  return std::string(text, end);
}

std::vector<PointAttribute> pointAttributes(const PointCloud& cloud, std::size_t index) {
  assert(index < cloud.count && "pointAttributes: index past the cloud's points");
  std::vector<PointAttribute> out = {{column_names::kX, cloud.worldX(index)},
                                     {column_names::kY, cloud.worldY(index)},
                                     {column_names::kZ, cloud.worldZ(index)}};
  if (cloud.hasColors()) {
    const Rgba8 c = cloud.colors[index];
    out.insert(out.end(), {{column_names::kRed, double(c.r)},
                           {column_names::kGreen, double(c.g)},
                           {column_names::kBlue, double(c.b)}});
    if (cloud.source.has_alpha) out.push_back({column_names::kAlpha, double(c.a)});
  }
  if (cloud.hasNormals()) {
    const Float3 n = cloud.normals[index];
    out.insert(out.end(), {{column_names::kNx, double(n.x)},
                           {column_names::kNy, double(n.y)},
                           {column_names::kNz, double(n.z)}});
  }
  if (cloud.hasIntensity())
    out.push_back({column_names::kIntensity, double(cloud.intensity[index])});
  if (cloud.hasClassification()) {
    out.push_back({column_names::kClassification, double(cloud.classification[index])});
  }
  for (const ScalarColumn& column : cloud.scalars) {
    out.push_back({column.name, column.valueAsDouble(index)});
  }
  return out;
}

const PointCloud& PickSource::nodePoints(std::int32_t node) {
  for (const auto& [index, points] : nodes_) {
    if (index == node) return points;
  }
  // Two nodes: clicks near each other often land in the same node, and a measurement's two
  // ends in at most two.
  if (nodes_.size() == 2) nodes_.pop_back();
  nodes_.emplace_front(node, octree_->loadNodeWhole(octree_->nodes()[std::size_t(node)]));
  return nodes_.front().second;
}

std::pair<glm::dvec3, std::vector<PointAttribute>> PickSource::point(const DrawItem& item,
                                                                     std::uint32_t index) {
  assert(item.chunk && item.chunk->source_indices && index < item.chunk->count &&
         "PickSource::point: a chunk staged by stagePointChunk and an index in it");
  const std::uint32_t source_index = (*item.chunk->source_indices)[index];
  assert((octree_ == nullptr || item.node >= 0) &&
         "PickSource::point: an octree's draw item names its node");
  const PointCloud& points = octree_ ? nodePoints(item.node) : *cloud_;
  std::vector<PointAttribute> attributes = pointAttributes(points, source_index);
  const glm::dvec3 position{attributes[0].value, attributes[1].value, attributes[2].value};
  return {position, std::move(attributes)};
}

namespace {

// The visibility buffer's point nearest (x, y) within the radius, in the same view.
std::optional<std::tuple<PickedPoint, int, int, double>> nearestDrawn(const Renderer& renderer,
                                                                      const PickRequest& request) {
  const int view = renderer.viewAt(request.x, request.y);
  if (view < 0) return std::nullopt;
  std::optional<std::tuple<PickedPoint, int, int, double>> best;
  const int r = std::max(request.radius_px, 0);
  for (int dy = -r; dy <= r; ++dy) {
    for (int dx = -r; dx <= r; ++dx) {
      const int d2 = dx * dx + dy * dy;
      if (d2 > r * r) continue;
      const int x = request.x + dx, y = request.y + dy;
      if (renderer.viewAt(x, y) != view) continue;
      const auto picked = renderer.pickPoint(x, y);
      if (!picked || !picked->point) continue;
      const double distance = std::sqrt(double(d2));
      if (best) {
        const double best_distance = std::get<3>(*best);
        // Reversed depth: larger is nearer.
        const bool nearer =
            distance < best_distance ||
            (distance == best_distance && picked->point->depth > std::get<0>(*best).point->depth);
        if (!nearer) continue;
      }
      best = std::make_tuple(*picked, x, y, distance);
    }
  }
  return best;
}

}  // namespace

std::optional<PickResult> pickPoint(Renderer& renderer, PickSource& source, const DrawSet& draw_set,
                                    std::span<const View> views, Composition composition,
                                    const RenderSettings& settings, int width, int height,
                                    const PickRequest& request) {
  if (!request.last_frame_matches || renderer.lastRasterizer() != RasterizerKind::Compute) {
    RenderSettings compute = settings;
    compute.rasterizer = RasterizerKind::Compute;
    compute.edl = false;  // a post pass: it changes no point's rank
    compute.samples = 0;
    if (renderer.chooseRasterizer(compute, width, height, composition) != RasterizerKind::Compute) {
      compute.size_mode = PointSizeMode::Fixed;
      compute.point_size_px = 1.0f;
      compute.hq = false;
    }
    RenderTarget scratch(width, height);
    renderer.render(draw_set, views, compute, scratch.framebuffer(), width, height, composition);
  }
  const auto found = nearestDrawn(renderer, request);
  if (!found) return std::nullopt;
  const auto& [picked, x, y, distance] = *found;
  PickResult result;
  std::tie(result.position, result.attributes) =
      source.point(draw_set.items[picked.point->item], picked.point->index);
  result.view = picked.view;
  result.pixel_x = x, result.pixel_y = y;
  result.distance_px = distance;
  return result;
}

}  // namespace parallax
