#include "registration/cloud_registration.h"

#include <algorithm>
#include <cmath>
#include <fstream>
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

PointCloud registrationPreviewSide(const PointCloud& cloud, const RigidTransform& transform,
                                   Rgba8 color) {
  std::vector<Point3> moved = positionsOf(cloud);
  Bounds3 bounds;
  for (Point3& p : moved) {
    p = transform.apply(p);
    bounds.extend(p[0], p[1], p[2]);
  }
  PointCloud preview;
  preview.count = cloud.count;
  if (preview.count == 0) return preview;
  for (int axis = 0; axis < 3; ++axis) {
    const double scale = cloud.quantization.scale[std::size_t(axis)];
    preview.quantization.scale[std::size_t(axis)] = scale;
    // The offset at the bounds' centre, on a whole step: the integers reach half the span.
    const double centre = 0.5 * (bounds.min[std::size_t(axis)] + bounds.max[std::size_t(axis)]);
    preview.quantization.offset[std::size_t(axis)] = std::round(centre / scale) * scale;
    if (!preview.quantization.fits(axis, bounds.min[std::size_t(axis)]) ||
        !preview.quantization.fits(axis, bounds.max[std::size_t(axis)])) {
      throw std::invalid_argument(
          "registration preview: the moved cloud spans too far for its scale (is the transform "
          "in the clouds' coordinate system?)");
    }
  }
  preview.positions = Column<Int3>(preview.count);
  preview.colors = Column<Rgba8>(preview.count);
  const Quantization& q = preview.quantization;
  for (std::size_t i = 0; i < preview.count; ++i) {
    const Point3& p = moved[i];
    preview.positions[i] = {q.toQuantized(0, p[0]), q.toQuantized(1, p[1]), q.toQuantized(2, p[2])};
    preview.colors[i] = color;
  }
  preview.computeBounds();
  return preview;
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
