// The small clouds of the scalar colour and legend tests (test_scalar_colors.cpp,
// test_scalar_legend.cpp): one point per value along x, carrying the values as a float scalar.
#pragma once

#include <cstdint>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

#include "core/point_cloud.h"

namespace parallax::test {

// A cloud whose float scalar `name` holds `values`, one point each at x = 0, 1, 2, ...
inline PointCloud cloudWithFloatScalar(const std::string& name, const std::vector<float>& values) {
  PointCloud cloud;
  cloud.count = values.size();
  cloud.positions = Column<Int3>(cloud.count);
  ScalarColumn column{
      .name = name, .type = ScalarType::Float32, .data = ByteBuffer(cloud.count * sizeof(float))};
  for (std::size_t i = 0; i < cloud.count; ++i) {
    cloud.positions[i] = {std::int32_t(i), 0, 0};
    column.as<float>()[i] = values[i];
  }
  cloud.scalars.push_back(std::move(column));
  cloud.computeBounds();
  return cloud;
}

// The same points as a binary PLY file's bytes: x y z double (x = 0, 1, 2, ...), `name` float.
inline std::string floatScalarPly(const std::string& name, const std::vector<float>& values) {
  std::string ply = "ply\nformat binary_little_endian 1.0\nelement vertex " +
                    std::to_string(values.size()) +
                    "\nproperty double x\nproperty double y\nproperty double z\nproperty float " +
                    name + "\nend_header\n";
  for (std::size_t i = 0; i < values.size(); ++i) {
    const double xyz[3] = {double(i), 0.0, 0.0};
    char bytes[28];
    std::memcpy(bytes, xyz, 24);
    std::memcpy(bytes + 24, &values[i], 4);
    ply.append(bytes, sizeof bytes);
  }
  return ply;
}

}  // namespace parallax::test
