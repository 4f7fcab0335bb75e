// Registration of two whole clouds, and its preview: what `parallax register` and the viewer's
// registration preview (`view SOURCE --register-with TARGET`) both call.
#pragma once

#include <filesystem>
#include <vector>

#include "core/point_cloud.h"
#include "registration/point_to_plane_icp.h"
#include "registration/rigid_transform.h"

namespace parallax {

// The cloud's positions in world units (double).
std::vector<Point3> positionsOf(const PointCloud& cloud);
// The cloud's own normals where it has them (any not zero), else none (ICP estimates them).
std::vector<Point3> normalsOf(const PointCloud& cloud);

// Point-to-plane ICP of `source` onto `target` (registration/point_to_plane_icp.h), with the
// target's own normals where it has them. Throws InputError naming the file (`source_name`,
// `target_name`) of a cloud with fewer than 3 points, and RegistrationError as
// alignPointToPlane does, prefixed with both names.
IcpResult registerClouds(const PointCloud& source, const PointCloud& target,
                         const IcpOptions& options, const std::string& source_name,
                         const std::string& target_name);

// The colours the preview gives each cloud: the source orange, the target blue (apart for
// colour-blind readers too: they differ in lightness and in the blue-yellow axis).
inline constexpr Rgba8 kPreviewSourceColor{255, 140, 0, 255};
inline constexpr Rgba8 kPreviewTargetColor{30, 110, 255, 255};

// One side of the preview: `cloud`'s points moved by `transform`, all in `color`, in the cloud's
// order (index i is cloud point i), positions only, quantized at the cloud's scale over its moved
// bounds. The viewer uploads each side apart and draws them together (the target first): sized by
// one cloud's spacing, and each side can be picked alone (point pairs) where the two overlap.
PointCloud registrationPreviewSide(const PointCloud& cloud, const RigidTransform& transform,
                                   Rgba8 color);

// Writes the transform as `parallax register` prints it and --init reads it (four lines of four
// numbers), to a temporary name beside `path` renamed at the end. Throws std::runtime_error
// naming the path where it cannot be written.
void writeRigidTransform(const RigidTransform& transform, const std::filesystem::path& path);

}  // namespace parallax
