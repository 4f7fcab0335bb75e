// Writing PointClouds as PCD 0.7 files (pcd_header.h), in any of the three encodings.
//
// Fields, in the order of PointCloud::attributeOrder (the source's, or the chosen properties):
//   x y z        F 4 when the source held float32 positions, else F 8 (world coordinates: a float
//                is only good to 6 cm at a UTM easting)
//   red green blue [alpha] -> one field rgb (or rgba with alpha) packed 0xAARRGGBB: rgb as
//                F 4 in binary encodings (PCL's PointXYZRGB: a float holding the bits), U 4 in
//                ascii (an integer, as PCL prints it); rgba U 4
//   nx ny nz     normal_x normal_y normal_z, F 4
//   intensity    F 4; classification U 1
//   scalars      under their names in their types (I/U 1, 2, 4; F 4, 8)
// WIDTH is the point count and HEIGHT 1 (an unorganised cloud); VIEWPOINT from the options.
// binary_compressed holds at most 4 GiB of uncompressed data (its sizes are 32-bit).
#pragma once

#include <array>
#include <filesystem>
#include <string>
#include <vector>

#include "core/point_cloud.h"
#include "core/progress.h"
#include "io/pcd_header.h"

namespace parallax {

struct PcdWriteOptions {
  PcdData data = PcdData::Binary;
  Progress* progress = nullptr;         // advanced by points written
  std::vector<std::string> properties;  // as PlyWriteOptions::properties; empty: every attribute
  std::array<double, 7> viewpoint{0, 0, 0, 1, 0, 0, 0};  // tx ty tz qw qx qy qz
};

// Writes to a temporary file beside `path`, renamed at the end. Throws std::invalid_argument for
// an unknown property and for binary_compressed data over 4 GiB, std::runtime_error on I/O
// failure.
void writePcd(const PointCloud& cloud, const std::filesystem::path& path,
              const PcdWriteOptions& options = {});

}  // namespace parallax
