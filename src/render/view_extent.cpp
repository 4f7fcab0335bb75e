#include "render/view_extent.h"

#include <algorithm>
#include <array>
#include <cstdint>

namespace parallax {

ViewExtent viewExtentOf(const PointCloud& cloud, std::size_t max_points) {
  ViewExtent extent;
  extent.bounds = cloud.bounds;
  if (cloud.count == 0 || max_points == 0) return extent;
  const std::size_t count = cloud.count;
  auto world = [&](std::size_t i) {
    return glm::dvec3(cloud.worldX(i), cloud.worldY(i), cloud.worldZ(i));
  };
  if (count <= max_points) {
    extent.points.reserve(count);
    for (std::size_t i = 0; i < count; ++i) extent.points.push_back(world(i));
    return extent;
  }
  // The points at the axis extremes, found on the quantized integers in one pass.
  auto coordinate = [&](std::size_t i, int axis) {
    const Int3& p = cloud.positions[i];
    return axis == 0 ? p.x : axis == 1 ? p.y : p.z;
  };
  std::array<std::size_t, 6> extreme{};  // min x, max x, min y, max y, min z, max z
  for (std::size_t i = 1; i < count; ++i) {
    for (int axis = 0; axis < 3; ++axis) {
      std::size_t& low = extreme[std::size_t(2 * axis)];
      std::size_t& high = extreme[std::size_t(2 * axis + 1)];
      if (coordinate(i, axis) < coordinate(low, axis)) low = i;
      if (coordinate(i, axis) > coordinate(high, axis)) high = i;
    }
  }
  const std::size_t stride_count = max_points - extreme.size();
  extent.points.reserve(max_points);
  for (std::size_t k = 0; k < stride_count; ++k) {
    extent.points.push_back(world(std::size_t(std::uint64_t(k) * count / stride_count)));
  }
  for (std::size_t i : extreme) extent.points.push_back(world(i));
  return extent;
}

ViewExtent viewExtentOf(const Octree& octree, std::size_t max_points) {
  ViewExtent extent;
  if (!octree.nodes().empty() && octree.nodes().front().point_count > 0) {
    extent = viewExtentOf(octree.loadNode(octree.nodes().front()), max_points);
  }
  extent.bounds = octree.info().bounds;
  return extent;
}

void fitCamera(Camera& camera, const ViewExtent& extent, double aspect, double x_from,
               double x_to) {
  if (!extent.points.empty()) {
    camera.fitToPoints(extent.points, aspect, Camera::kFitMargin, x_from, x_to);
  } else {
    camera.fitToBounds(extent.bounds, aspect);
  }
}

Camera defaultCameraFor(const ViewExtent& extent, double aspect, double x_from, double x_to) {
  Camera camera = defaultCameraFor(extent.bounds, aspect);
  fitCamera(camera, extent, aspect, x_from, x_to);
  return camera;
}

}  // namespace parallax
