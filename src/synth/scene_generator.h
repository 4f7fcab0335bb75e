// Synthetic point clouds of any size, streamed to a PLY file in bounded memory.
//
// Scenes (see sceneNames()):
//   scan    a terrestrial laser scan: five scanner stations on a 200 m x 200 m site of rolling
//           terrain, a road, buildings and trees; beams cast at uniform angular steps, so density
//           falls with the square of the range, objects cast scan shadows, ranges carry noise
//           (2 mm + 50 ppm, one sigma).
//   aerial  the same site seen by an airborne scanner flying parallel strips at 250 m: nearly even
//           density on the ground and roofs, few points on walls.
//
// Coordinates are local metres (x east, y north, z up) within [-100, 100] in x and y, so float32
// output keeps sub-millimetre precision. Each point has a unit outward surface normal and a colour.
//
// Determinism: points are generated in blocks of kBlockPoints; block b is computed from
// (seed, b) alone, so a seed gives the same bytes whatever the thread count. The block size is
// therefore part of the output's definition: changing it changes every file.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "core/point_cloud.h"
#include "core/progress.h"
#include "io/ply_header.h"

namespace parallax::synth {

struct SceneOptions {
  std::string scene = "scan";
  std::uint64_t seed = 1;
};

class SceneGenerator {
 public:
  static constexpr std::size_t kBlockPoints = std::size_t{1} << 16;

  // Throws std::invalid_argument naming the known scenes when `options.scene` is not one.
  explicit SceneGenerator(const SceneOptions& options);
  ~SceneGenerator();
  SceneGenerator(const SceneGenerator&) = delete;
  SceneGenerator& operator=(const SceneGenerator&) = delete;

  static std::vector<std::string> sceneNames();

  // The `count` (at most kBlockPoints) points of block `block`: positions (quantized with
  // quantization()), normals and colours, in the layout of layout(). Thread-safe.
  PointCloud generateBlock(std::uint64_t block, std::size_t count) const;

  // A one-point cloud (at the origin) with generateBlock's attributes: positions, normals (float)
  // and colours (uchar, no alpha). The file writes them as x y z nx ny nz red green blue.
  PointCloud layout() const;
  // Fixed for every scene: 2^-18 m steps (4 um) around the origin.
  Quantization quantization() const;
  // Scanner positions of the `scan` scene (empty for `aerial`), in metres.
  std::vector<std::array<double, 3>> stations() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

struct GenerateOptions {
  SceneOptions scene;
  std::uint64_t points = 0;
  PlyFormat format = PlyFormat::BinaryLittleEndian;
  Progress* progress = nullptr;  // advanced by points written
  int max_threads = 0;           // 0: all cores (TBB's default); the output does not depend on it
};

struct GenerateStats {
  std::uint64_t points = 0;
  std::uint64_t bytes = 0;  // size of the file written
  double seconds = 0;
};

// Generates `options.points` points block by block (in parallel, written in order through
// PlyStreamWriter, holding a few blocks at a time) into the PLY file `path`. Throws
// std::invalid_argument for an unknown scene and std::runtime_error for I/O failures (the target
// is then left untouched).
GenerateStats generatePly(const std::filesystem::path& path, const GenerateOptions& options);

}  // namespace parallax::synth
