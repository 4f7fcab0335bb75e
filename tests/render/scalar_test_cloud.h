// The small clouds of the scalar colour and legend tests (test_scalar_colors.cpp,
// test_scalar_legend.cpp): one point per value along x, carrying the values as a float scalar.
#pragma once

#include <cstdint>
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

}  // namespace parallax::test
