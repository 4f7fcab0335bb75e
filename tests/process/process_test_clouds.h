// The process tests' clouds: PLY files of given double positions, and the positions of a file
// read back as the process reads them.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "core/point_cloud.h"
#include "io/ply_writer.h"
#include "lod/convert_stages.h"
#include "support/temp_dir.h"

namespace parallax::test {

using Xyz = std::array<double, 3>;

// A PLY of double positions and an "id" column (each point's index), so outputs can be matched
// to inputs.
inline std::filesystem::path writeCloud(const TempDir& dir, const std::string& name,
                                        const std::vector<Xyz>& points) {
  PointCloud cloud;
  cloud.count = points.size();
  cloud.quantization.scale = {1e-6, 1e-6, 1e-6};
  cloud.positions = Column<Int3>(points.size());
  ScalarColumn id{"id", ScalarType::UInt32, ByteBuffer(points.size() * 4)};
  for (std::size_t i = 0; i < points.size(); ++i) {
    cloud.positions[i] = {cloud.quantization.toQuantized(0, points[i][0]),
                          cloud.quantization.toQuantized(1, points[i][1]),
                          cloud.quantization.toQuantized(2, points[i][2])};
    id.as<std::uint32_t>()[i] = std::uint32_t(i);
  }
  cloud.scalars.push_back(std::move(id));
  cloud.source.position = ScalarType::Float64;
  cloud.computeBounds();
  const std::filesystem::path path = dir / name;
  writePly(cloud, path);
  return path;
}

// The positions exactly as the process reads them (the same stream).
inline std::vector<Xyz> readPositions(const std::filesystem::path& path) {
  PointStream stream(path, {});
  std::vector<Xyz> out;
  PointCloud batch;
  while (stream.next(batch, 1 << 20)) {
    for (std::size_t i = 0; i < batch.count; ++i)
      out.push_back({batch.worldX(i), batch.worldY(i), batch.worldZ(i)});
  }
  return out;
}

}  // namespace parallax::test
