// Point-to-plane ICP (Chen & Medioni 1992; the linearized step of Low 2004): the rigid transform
// that takes SOURCE's points onto TARGET's surface, coarse to fine.
//
// Each iteration pairs every source point (moved by the current transform) with its nearest
// target point within `max_distance`, and solves the 6x6 least-squares problem of the point-to-
// plane residuals (p - q) . n_q linearized in three small angles and a translation; the update is
// the exact rotation of those angles (Rz Ry Rx), composed before the current transform. Coarse to
// fine: the source is first reduced to the centroids of voxels 2^(levels-1), ..., 2 times the
// target's point spacing, the last level is every point, each level starting from the one
// before's transform; the target is searched at full resolution throughout (one k-d tree).
//
// Coordinates are world units in double. All the work happens around a local origin (the
// target's bounds' centre), so georeferenced coordinates keep their millimetres; the result is
// given back in world coordinates.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "registration/rigid_transform.h"

namespace parallax {

using Point3 = std::array<double, 3>;

struct IcpOptions {
  // Pairs farther apart are not used (world units). 0: a twentieth of the target's bounds'
  // diagonal.
  double max_distance = 0.0;
  RigidTransform init;                 // SOURCE -> TARGET to start from
  std::uint32_t levels = 3;            // voxel levels, the last one every point
  std::uint32_t max_iterations = 100;  // a level
  std::uint32_t normal_k = 16;         // target normals by PCA of this many nearest points
};

struct IcpResult {
  RigidTransform transform;  // SOURCE -> TARGET, world coordinates
  // Over the source's points paired with a target point within max_distance at the end:
  double rms = 0.0;      // root mean square of their point-to-point distances
  double overlap = 0.0;  // their fraction of the source's points
  std::uint64_t correspondences = 0;
  std::uint32_t iterations = 0;  // over all levels
  double max_distance = 0.0;     // as used
};

// No pairs within max_distance (the clouds do not overlap where --init puts them), or too few to
// fix the six degrees of freedom.
class RegistrationError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// `target_normals`: one a target point (the file's own), or empty for PCA of options.normal_k
// nearest points. Throws RegistrationError; std::invalid_argument for empty clouds or a bad
// option.
IcpResult alignPointToPlane(std::span<const Point3> source, std::span<const Point3> target,
                            std::span<const Point3> target_normals, const IcpOptions& options);

// PCA normals of `points` from their k nearest (the point itself included); (0, 0, 0) where the
// neighbours do not fix a plane.
std::vector<Point3> estimateNormals(std::span<const Point3> points, std::uint32_t k);

}  // namespace parallax
