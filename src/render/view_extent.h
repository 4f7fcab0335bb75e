// What a default view is fitted to: a cloud's bounds and a sample of its points. The fit frames
// the sample as it projects (Camera::fitToPoints), so the first picture shows the points filling
// the view rather than their box, which for a real scan is mostly empty sky and corners.
#pragma once

#include <cstddef>
#include <glm/glm.hpp>
#include <vector>

#include "core/bounds.h"
#include "core/point_cloud.h"
#include "lod/octree.h"
#include "render/camera.h"

namespace parallax {

struct ViewExtent {
  Bounds3 bounds;                  // world coordinates; empty for no points
  std::vector<glm::dvec3> points;  // world coordinates; may be empty (then the bounds are fitted)
};

// Enough points to find a cloud's outline within a fraction of a percent, few enough (3 MB) to
// keep beside the GPU copy for the viewer's F key.
constexpr std::size_t kViewExtentPoints = 1 << 17;

// The cloud's bounds and at most `max_points` of its points: every point of a small cloud; of a
// larger one an even stride through the file order, plus the points at the minimum and maximum
// of each axis (so that the extremes of the bounds are always among them).
ViewExtent viewExtentOf(const PointCloud& cloud, std::size_t max_points = kViewExtentPoints);
// An octree's bounds and the points of its root node, an even sample of the whole cloud spaced
// by the root spacing (1/128 of the cube). Reads the root node: throws InputError as loadNode.
ViewExtent viewExtentOf(const Octree& octree, std::size_t max_points = kViewExtentPoints);

// Fits `camera` (its orientation kept) to the extent's points, or to its bounds when it has none.
// [x_from, x_to]: the part of the view's width to fit into (Camera::fitToPoints; the bounds'
// fit ignores it).
void fitCamera(Camera& camera, const ViewExtent& extent, double aspect, double x_from = -1.0,
               double x_to = 1.0);

// The default view (render/camera.h defaultCameraFor's direction), fitted to the extent.
Camera defaultCameraFor(const ViewExtent& extent, double aspect, double x_from = -1.0,
                        double x_to = 1.0);

}  // namespace parallax
