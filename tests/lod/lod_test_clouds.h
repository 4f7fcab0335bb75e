// Small synthetic clouds for the LOD tests, the multiset of a cloud's points to compare a build's
// output with its input, and two octrees compared byte for byte.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>
#include <tuple>
#include <vector>

#include "core/point_cloud.h"
#include "lod/potree_converter.h"
#include "support/file_bytes.h"

namespace parallax::test {

// `count` points on a few surfaces (a floor, a wall, a sphere) in a 100 m cube, quantized at
// 1 mm, with colours, normals, an integer intensity and a float scalar "quality". Deterministic.
inline PointCloud makeSurfaceCloud(std::uint64_t count, std::uint32_t seed = 1) {
  PointCloud cloud;
  cloud.count = count;
  cloud.quantization.scale = {0.001, 0.001, 0.001};
  cloud.quantization.offset = {1000.0, 2000.0, 0.0};
  cloud.positions = Column<Int3>(count);
  cloud.colors = Column<Rgba8>(count);
  cloud.normals = Column<Float3>(count);
  cloud.intensity = Column<float>(count);
  cloud.source.intensity = ScalarType::UInt16;
  ScalarColumn quality{
      .name = "quality", .type = ScalarType::Float32, .data = ByteBuffer(count * 4)};
  std::uint32_t state = seed;
  auto next = [&] {  // xorshift32: the same points on every platform
    state ^= state << 13;
    state ^= state >> 17;
    state ^= state << 5;
    return double(state) / 4294967296.0;
  };
  for (std::uint64_t i = 0; i < count; ++i) {
    double x = next() * 100.0, y = next() * 100.0, z = 0.0;
    switch (i % 3) {
      case 0:
        break;  // floor
      case 1:
        z = y * 0.5, y = 50.0;
        break;    // wall
      default: {  // sphere of radius 20 around (50, 50, 30)
        const double u = next() * 2.0 - 1.0, a = next() * 6.283185307179586;
        const double r = std::sqrt(1.0 - u * u);
        x = 50.0 + 20.0 * r * std::cos(a), y = 50.0 + 20.0 * r * std::sin(a), z = 30.0 + 20.0 * u;
      }
    }
    cloud.positions[i] = {cloud.quantization.toQuantized(0, x + 1000.0),
                          cloud.quantization.toQuantized(1, y + 2000.0),
                          cloud.quantization.toQuantized(2, z)};
    cloud.colors[i] = {std::uint8_t(i * 7), std::uint8_t(i * 13), std::uint8_t(i * 29), 255};
    cloud.normals[i] = {float(i % 5) * 0.25f, 0.5f, -1.0f};
    cloud.intensity[i] = float(i % 65536);
    quality.as<float>()[i] = float(i) * 0.5f;
  }
  cloud.scalars.push_back(std::move(quality));
  cloud.computeBounds();
  return cloud;
}

// Shrinks every fourth point towards the cloud's centre by 1000 times: a dense 10 cm cluster,
// which makes the octree deep (more than one hierarchy chunk of 4 levels).
inline void addDenseCluster(PointCloud& cloud) {
  const Int3 c = cloud.positions[0];
  for (std::uint64_t i = 0; i < cloud.count; i += 4) {
    const Int3 p = cloud.positions[i];
    cloud.positions[i] = {c.x + (p.x - c.x) / 1000, c.y + (p.y - c.y) / 1000,
                          c.z + (p.z - c.z) / 1000};
  }
  cloud.computeBounds();
}

// makeSurfaceCloud's points with what a LAS point format 3 or 7 holds besides positions and
// colour: classification (i % `classes`), return numbers 1-3 and a GPS time; no normals.
inline PointCloud makeLasLikeCloud(std::uint64_t count, int classes) {
  PointCloud cloud = makeSurfaceCloud(count);
  cloud.normals = {};
  cloud.scalars.clear();
  cloud.classification = Column<std::uint8_t>(cloud.count);
  ScalarColumn returns{
      .name = "return_number", .type = ScalarType::UInt8, .data = ByteBuffer(cloud.count)};
  ScalarColumn gps{
      .name = "gps_time", .type = ScalarType::Float64, .data = ByteBuffer(cloud.count * 8)};
  for (std::uint64_t i = 0; i < cloud.count; ++i) {
    cloud.classification[i] = std::uint8_t(i % std::uint64_t(classes));
    returns.as<std::uint8_t>()[i] = std::uint8_t(1 + i % 3);
    gps.as<double>()[i] = 1000.0 + double(i) * 0.25;
  }
  cloud.scalars.push_back(std::move(returns));
  cloud.scalars.push_back(std::move(gps));
  return cloud;
}

// Conversion options that split a small cloud into several chunks and many nodes: what the
// twin-file tests (a LAZ and its LAS, a selection and the whole) build both octrees with.
inline PotreeConvertOptions smallChunks() {
  PotreeConvertOptions options;
  options.build.max_node_points = 300;
  options.build.max_chunk_points = 3000;
  options.name = "twin";
  return options;
}

// The three files of two Potree octrees, byte for byte.
inline void expectSameOctree(const std::filesystem::path& a, const std::filesystem::path& b) {
  for (const char* file : {"octree.bin", "hierarchy.bin", "metadata.json"}) {
    const std::string bytes_a = fileBytes(a / file);
    EXPECT_FALSE(bytes_a.empty()) << file;
    const std::string bytes_b = fileBytes(b / file);
    EXPECT_TRUE(bytes_a == bytes_b)
        << file << " differs: " << bytes_a.size() << " and " << bytes_b.size() << " bytes";
  }
}

// One point as a comparable tuple: world position (exact for the 1 mm grid here), colour,
// normal, intensity, the classification and every scalar's bytes.
using PointKey = std::tuple<long long, long long, long long, std::uint32_t, float, float, float,
                            float, std::string>;

inline std::vector<PointKey> pointMultiset(const PointCloud& cloud) {
  std::vector<PointKey> keys;
  keys.reserve(cloud.count);
  for (std::uint64_t i = 0; i < cloud.count; ++i) {
    const Rgba8 c = cloud.hasColors() ? cloud.colors[i] : Rgba8{0, 0, 0, 255};
    const Float3 n = cloud.hasNormals() ? cloud.normals[i] : Float3{0, 0, 0};
    std::string scalars;
    if (cloud.hasClassification()) scalars += char(cloud.classification[i]);
    for (const ScalarColumn& column : cloud.scalars) {
      const std::size_t size = scalarSize(column.type);
      scalars.append(reinterpret_cast<const char*>(column.data.data()) + i * size, size);
    }
    keys.emplace_back(std::llround(cloud.worldX(i) * 1000.0),
                      std::llround(cloud.worldY(i) * 1000.0),
                      std::llround(cloud.worldZ(i) * 1000.0),
                      std::uint32_t(c.r) << 16 | std::uint32_t(c.g) << 8 | c.b, n.x, n.y, n.z,
                      cloud.hasIntensity() ? cloud.intensity[i] : 0.0f, scalars);
  }
  std::sort(keys.begin(), keys.end());
  return keys;
}

}  // namespace parallax::test
