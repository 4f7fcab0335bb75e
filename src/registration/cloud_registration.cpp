#include "registration/cloud_registration.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <limits>
#include <span>
#include <stdexcept>
#include <system_error>

#include "core/error.h"

namespace parallax {

std::vector<Point3> positionsOf(const PointCloud& cloud) {
  std::vector<Point3> out(cloud.count);
  for (std::size_t i = 0; i < cloud.count; ++i) {
    out[i] = {cloud.worldX(i), cloud.worldY(i), cloud.worldZ(i)};
  }
  return out;
}

std::vector<Point3> normalsOf(const PointCloud& cloud) {
  std::vector<Point3> out;
  if (!cloud.hasNormals()) return out;
  bool any = false;
  out.resize(cloud.count);
  for (std::size_t i = 0; i < cloud.count; ++i) {
    const Float3& n = cloud.normals[i];
    out[i] = {n.x, n.y, n.z};
    any = any || n.x != 0.0f || n.y != 0.0f || n.z != 0.0f;
  }
  if (!any) out.clear();
  return out;
}

IcpResult registerClouds(const PointCloud& source, const PointCloud& target,
                         const IcpOptions& options, const std::string& source_name,
                         const std::string& target_name) {
  for (const auto& [cloud, name] : {std::pair{&source, &source_name}, {&target, &target_name}}) {
    if (cloud->count < 3) {
      throw InputError({.file = *name,
                        .expected = "at least 3 points to register",
                        .found = std::to_string(cloud->count) + " points"});
    }
  }
  try {
    return alignPointToPlane(positionsOf(source), positionsOf(target), normalsOf(target), options);
  } catch (const RegistrationError& e) {
    throw RegistrationError("register " + source_name + " to " + target_name + ": " + e.what());
  }
}

namespace {

// One cloud of the preview's parts (each cloud moved by its transform, all of it in its colour),
// positions and colours only, quantized at the finest of the parts' scales over the union of their
// moved bounds.
struct RegistrationPreviewPart {
  const PointCloud* cloud = nullptr;
  RigidTransform transform;
  Rgba8 color;
};

PointCloud registrationPreviewOfParts(std::span<const RegistrationPreviewPart> parts) {
  std::vector<std::vector<Point3>> moved;
  Bounds3 bounds;
  PointCloud preview;
  for (const RegistrationPreviewPart& part : parts) {
    moved.push_back(positionsOf(*part.cloud));
    for (Point3& p : moved.back()) {
      p = part.transform.apply(p);
      bounds.extend(p[0], p[1], p[2]);
    }
    preview.count += part.cloud->count;
  }
  if (preview.count == 0) return preview;
  for (int axis = 0; axis < 3; ++axis) {
    double scale = std::numeric_limits<double>::infinity();
    for (const RegistrationPreviewPart& part : parts) {
      scale = std::min(scale, part.cloud->quantization.scale[std::size_t(axis)]);
    }
    preview.quantization.scale[std::size_t(axis)] = scale;
    // The offset at the bounds' centre, on a whole step: the integers reach half the span.
    const double centre = 0.5 * (bounds.min[std::size_t(axis)] + bounds.max[std::size_t(axis)]);
    preview.quantization.offset[std::size_t(axis)] = std::round(centre / scale) * scale;
    if (!preview.quantization.fits(axis, bounds.min[std::size_t(axis)]) ||
        !preview.quantization.fits(axis, bounds.max[std::size_t(axis)])) {
      throw std::invalid_argument(
          "registration preview: the two clouds span too far apart for one cloud at their "
          "scale (are they in the same coordinate system?)");
    }
  }
  preview.positions = Column<Int3>(preview.count);
  preview.colors = Column<Rgba8>(preview.count);
  const Quantization& q = preview.quantization;
  std::size_t at = 0;
  for (std::size_t k = 0; k < parts.size(); ++k) {
    for (const Point3& p : moved[k]) {
      preview.positions[at] = {q.toQuantized(0, p[0]), q.toQuantized(1, p[1]),
                               q.toQuantized(2, p[2])};
      preview.colors[at] = parts[k].color;
      ++at;
    }
  }
  preview.computeBounds();
  return preview;
}

}  // namespace

PointCloud registrationPreview(const PointCloud& source, const PointCloud& target,
                               const RigidTransform& transform) {
  const std::array<RegistrationPreviewPart, 2> parts{
      RegistrationPreviewPart{&target, RigidTransform{}, kPreviewTargetColor},
      RegistrationPreviewPart{&source, transform, kPreviewSourceColor}};
  return registrationPreviewOfParts(parts);
}

PointCloud registrationPreviewSide(const PointCloud& cloud, const RigidTransform& transform,
                                   Rgba8 color) {
  const std::array<RegistrationPreviewPart, 1> parts{
      RegistrationPreviewPart{&cloud, transform, color}};
  return registrationPreviewOfParts(parts);
}

void writeRigidTransform(const RigidTransform& transform, const std::filesystem::path& path) {
  std::filesystem::path temp = path;
  temp += ".partial";
  {
    std::ofstream out(temp, std::ios::binary | std::ios::trunc);
    out << formatRigidTransform(transform);
    out.flush();
    if (!out) throw std::runtime_error("cannot write the transform to " + temp.string());
  }
  std::error_code error;
  std::filesystem::rename(temp, path, error);
  if (error) {
    std::filesystem::remove(temp, error);
    throw std::runtime_error("cannot write the transform to " + path.string());
  }
}

}  // namespace parallax
