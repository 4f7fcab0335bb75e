// A rigid transform as a 4x4 matrix in double (row-major, the last row 0 0 0 1), the text form
// `parallax register` reads with --init and prints, and its application to a point cloud.
//
// Coordinates are world units; a transform taking SOURCE to TARGET maps a source point p to
// R p + t. Georeferenced coordinates are large (UTM eastings of 500 000 m), so everything here is
// double and compositions with translations to and from a local origin are exact enough for
// millimetres at that scale.
#pragma once

#include <array>
#include <filesystem>
#include <string>

#include "core/point_cloud.h"

namespace parallax {

struct RigidTransform {
  std::array<std::array<double, 4>, 4> m{{{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}}};

  static RigidTransform translation(double x, double y, double z);
  // Rotation by `degrees` about the axis (x, y, z) (normalized here; not zero).
  static RigidTransform rotation(double x, double y, double z, double degrees);
  // Rz(gamma) Ry(beta) Rx(alpha): the small-angle update of a point-to-plane step, radians.
  static RigidTransform fromEuler(double alpha, double beta, double gamma);

  // this, then `first` applied before it: (this * first) p = this(first(p)).
  RigidTransform operator*(const RigidTransform& first) const;
  // The inverse of a rigid transform (R^T, -R^T t).
  RigidTransform inverse() const;
  std::array<double, 3> apply(const std::array<double, 3>& p) const;
  std::array<double, 3> rotate(const std::array<double, 3>& v) const;

  // The rotation's angle in degrees (0 to 180) and the translation's length.
  double angleDegrees() const;
  double translationLength() const;
};

// Four lines of four numbers (spaces, tabs or commas between them; blank lines and lines starting
// with '#' skipped), as `parallax register` prints and as CloudCompare and Open3D write them.
// Throws InputError naming `source` (a file name, for messages), the line and what was found:
// fewer or more numbers, a last row other than 0 0 0 1, or a 3x3 part that is not a rotation
// (R^T R off the identity by more than 1e-6, or a reflection).
RigidTransform parseRigidTransform(const std::string& text, const std::string& source);
RigidTransform readRigidTransform(const std::filesystem::path& path);

// Four lines of four numbers with 17 significant digits (reads back exactly).
std::string formatRigidTransform(const RigidTransform& transform);

// Moves every point of `cloud` by `transform`: positions in double, requantized on the cloud's
// scale (its offset moved by the translation's whole steps, so a cloud far from the origin keeps
// its integers in range), normals rotated. Bounds recomputed.
void transformCloud(PointCloud& cloud, const RigidTransform& transform);

}  // namespace parallax
