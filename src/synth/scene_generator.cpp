// Block generation (a sensor casting beams into the site) and the ordered parallel pipeline that
// streams blocks to a PLY file.
#include "synth/scene_generator.h"

#include <tbb/global_control.h>
#include <tbb/parallel_pipeline.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <numbers>
#include <stdexcept>

#include "io/ply_writer.h"
#include "synth/scene_geometry.h"

namespace parallax::synth {
namespace {

constexpr double kStationRange = 150.0;  // metres; a mid-range phase-shift scanner
constexpr double kAerialAltitude = 250.0;
constexpr double kAerialHalfAngle = 0.38;  // radians across track (about +-22 degrees)
constexpr double kAerialStripSpacing = 60.0;
// Beams leave a station between these elevations (radians): the tripod hides the steepest
// downward cone, and beams far above the horizon would only meet the sky.
constexpr double kMinElevation = -1.05;
constexpr double kMaxElevation = 0.75;
// Azimuth bins per station: each lists the objects whose plan circle the bin's wedge touches, so
// a beam tests a handful of objects instead of all of them.
constexpr int kAzimuthBins = 720;

// Nearest integer, halves away from zero, without a library call (values are far inside int32).
std::int32_t roundToInt(double v) {
  return std::int32_t(v + (v >= 0 ? 0.5 : -0.5));
}

enum class SceneKind { Scan, Aerial };

// Quantization of the output: a power of two so that q * scale converts to float exactly when
// float has the precision, and fine enough (4 um) that float32 rounding dominates.
constexpr double kScale = 0x1p-18;

// The file's record is that of photogrammetry exports, x y z nx ny nz red green blue, but the
// writer puts the model's colour column before its normal column. So the written chunk carries
// normals and colours as plain scalar columns, which the writer emits in their own order (and a
// reader maps back to normals and colours by name).
PointCloud toExportLayout(PointCloud&& cloud) {
  PointCloud out;
  out.count = cloud.count;
  out.quantization = cloud.quantization;
  out.positions = std::move(cloud.positions);
  const std::size_t n = cloud.count;
  const char* normal_names[3] = {"nx", "ny", "nz"};
  for (int axis = 0; axis < 3; ++axis) {
    ScalarColumn column{normal_names[axis], ScalarType::Float32, ByteBuffer(n * sizeof(float))};
    float* values = column.as<float>();
    const Float3* normals = cloud.normals.data();
    for (std::size_t i = 0; i < n; ++i) {
      values[i] = axis == 0 ? normals[i].x : axis == 1 ? normals[i].y : normals[i].z;
    }
    out.scalars.push_back(std::move(column));
  }
  const char* color_names[3] = {"red", "green", "blue"};
  for (int channel = 0; channel < 3; ++channel) {
    ScalarColumn column{color_names[channel], ScalarType::UInt8, ByteBuffer(n)};
    std::uint8_t* values = column.as<std::uint8_t>();
    const Rgba8* colors = cloud.colors.data();
    for (std::size_t i = 0; i < n; ++i) {
      values[i] = channel == 0 ? colors[i].r : channel == 1 ? colors[i].g : colors[i].b;
    }
    out.scalars.push_back(std::move(column));
  }
  return out;
}

}  // namespace

struct SceneGenerator::Impl {
  SceneKind kind = SceneKind::Scan;
  std::uint64_t seed = 1;
  Site site;
  // For station s and bin b: objects in bin_objects[bin_start[s * kAzimuthBins + b] ...
  // bin_start[s * kAzimuthBins + b + 1]).
  std::vector<std::uint32_t> bin_start;
  std::vector<std::uint16_t> bin_objects;
  // Highest elevation (radians) at which a beam in the bin can meet an object; 0 for none. Beams
  // above it would only meet the sky, and are dropped before any ray casting.
  std::vector<double> bin_max_elevation;
  std::vector<std::uint16_t> all_objects;

  void buildAzimuthBins() {
    bin_start.assign(site.stations.size() * kAzimuthBins + 1, 0);
    std::vector<std::vector<std::uint16_t>> bins(site.stations.size() * kAzimuthBins);
    bin_max_elevation.assign(bins.size(), 0.0);
    for (std::size_t s = 0; s < site.stations.size(); ++s) {
      const Vec3& station = site.stations[s];
      for (std::size_t i = 0; i < site.objectCount(); ++i) {
        auto [cx, cy, r] = site.objectCircle(i);
        double dx = cx - station.x, dy = cy - station.y;
        double distance = std::hypot(dx, dy);
        int first = 0, last = kAzimuthBins - 1;
        if (distance > r + 0.01) {
          double centre = std::atan2(dy, dx);
          double half = std::asin(r / distance);
          double bin_width = 2 * std::numbers::pi / kAzimuthBins;
          first = int(std::floor((centre - half) / bin_width));
          last = int(std::floor((centre + half) / bin_width));
        }
        double top = i < site.buildings.size()
                         ? site.buildings[i].ridge_z
                         : site.trees[i - site.buildings.size()].crown_z +
                               site.trees[i - site.buildings.size()].crown_height;
        double elevation = std::atan2(top - station.z, std::max(distance - r, 0.05));
        for (int b = first; b <= last; ++b) {
          std::size_t wrapped =
              s * kAzimuthBins + ((b % kAzimuthBins) + kAzimuthBins) % kAzimuthBins;
          bins[wrapped].push_back(std::uint16_t(i));
          bin_max_elevation[wrapped] = std::max(bin_max_elevation[wrapped], elevation);
        }
      }
    }
    for (std::size_t i = 0; i < bins.size(); ++i) {
      bin_start[i + 1] = bin_start[i] + std::uint32_t(bins[i].size());
      bin_objects.insert(bin_objects.end(), bins[i].begin(), bins[i].end());
    }
    for (std::size_t i = 0; i < site.objectCount(); ++i) all_objects.push_back(std::uint16_t(i));
  }

  std::size_t binIndex(std::size_t station, double azimuth) const {
    int bin =
        std::clamp(int(azimuth * (kAzimuthBins / (2 * std::numbers::pi))), 0, kAzimuthBins - 1);
    return station * kAzimuthBins + std::size_t(bin);
  }
  std::span<const std::uint16_t> objectsInBin(std::size_t index) const {
    return {bin_objects.data() + bin_start[index], bin_start[index + 1] - bin_start[index]};
  }
};

SceneGenerator::SceneGenerator(const SceneOptions& options) : impl_(std::make_unique<Impl>()) {
  if (options.scene == "scan") {
    impl_->kind = SceneKind::Scan;
  } else if (options.scene == "aerial") {
    impl_->kind = SceneKind::Aerial;
  } else {
    std::string names;
    for (const auto& name : sceneNames()) names += (names.empty() ? "" : ", ") + name;
    throw std::invalid_argument("unknown scene '" + options.scene + "'; known scenes: " + names);
  }
  impl_->seed = options.seed;
  impl_->site = buildSite(options.seed);
  impl_->buildAzimuthBins();
}

SceneGenerator::~SceneGenerator() = default;

std::vector<std::string> SceneGenerator::sceneNames() {
  return {"scan", "aerial"};
}

Quantization SceneGenerator::quantization() const {
  Quantization q;
  q.scale = {kScale, kScale, kScale};
  return q;
}

PointCloud SceneGenerator::layout() const {
  PointCloud cloud;
  cloud.quantization = quantization();
  cloud.source = SourceTypes{};  // float positions and normals, uchar colour, no alpha
  cloud.colors = Column<Rgba8>(1);
  cloud.normals = Column<Float3>(1);
  cloud.positions = Column<Int3>(1);
  cloud.count = 1;
  cloud.colors[0] = {0, 0, 0, 255};
  cloud.normals[0] = {0, 0, 1};
  cloud.positions[0] = {0, 0, 0};
  return cloud;
}

std::vector<std::array<double, 3>> SceneGenerator::stations() const {
  std::vector<std::array<double, 3>> out;
  if (impl_->kind != SceneKind::Scan) return out;
  for (const auto& s : impl_->site.stations) out.push_back({s.x, s.y, s.z});
  return out;
}

PointCloud SceneGenerator::generateBlock(std::uint64_t block, std::size_t count) const {
  const Impl& impl = *impl_;
  const Site& site = impl.site;
  PointCloud cloud;
  cloud.count = count;
  cloud.quantization = quantization();
  cloud.positions = Column<Int3>(count);
  cloud.normals = Column<Float3>(count);
  cloud.colors = Column<Rgba8>(count);
  Random random(mixSeed(impl.seed, block + 1));

  // A block is one station's (or one flight strip's) work, so the file, like a real export, runs
  // through the stations in turn.
  std::size_t station = block % std::max<std::size_t>(1, site.stations.size());
  double strip_y = 0;
  if (impl.kind == SceneKind::Aerial) {
    int strips = int(2 * Site::kHalfSize / kAerialStripSpacing) + 1;
    strip_y = -Site::kHalfSize + kAerialStripSpacing * double(block % strips) + 15.0;
  }
  const double q = 1.0 / kScale;
  std::size_t done = 0;
  while (done < count) {
    Vec3 origin, direction;
    std::span<const std::uint16_t> objects;
    double max_range, ground_hint;
    if (impl.kind == SceneKind::Scan) {
      origin = site.stations[station];
      double azimuth = random.uniform(0, 2 * std::numbers::pi);
      double elevation = random.uniform(kMinElevation, kMaxElevation);
      std::size_t bin = impl.binIndex(station, azimuth);
      if (elevation > impl.bin_max_elevation[bin]) continue;  // into the sky: no return
      double sin_e, cos_e, sin_a, cos_a;
      fastSinCos(elevation, sin_e, cos_e);
      fastSinCos(azimuth, sin_a, cos_a);
      direction = {cos_e * cos_a, cos_e * sin_a, sin_e};
      ground_hint = origin.z - kStationHeight;
      objects = impl.objectsInBin(bin);
      max_range = kStationRange;
    } else {
      origin = {random.uniform(-Site::kHalfSize, Site::kHalfSize), strip_y, kAerialAltitude};
      double across = random.uniform(-kAerialHalfAngle, kAerialHalfAngle);
      double sin_c, cos_c;
      fastSinCos(across, sin_c, cos_c);
      direction = normalized({0.02, sin_c, -cos_c});
      ground_hint = 0;
      objects = impl.all_objects;
      max_range = 2 * kAerialAltitude;
    }
    Hit hit;
    if (!castRay(site, origin, direction, max_range, ground_hint, objects, random, hit)) continue;
    double range = hit.t + random.normal() * (0.002 + 50e-6 * hit.t);
    Vec3 p = origin + direction * range;
    cloud.positions[done] = {roundToInt(p.x * q), roundToInt(p.y * q), roundToInt(p.z * q)};
    cloud.normals[done] = {float(hit.normal.x), float(hit.normal.y), float(hit.normal.z)};
    cloud.colors[done] = surfaceColor(site, hit, p, random);
    ++done;
  }
  return cloud;
}

GenerateStats generatePly(const std::filesystem::path& path, const GenerateOptions& options) {
  auto start = std::chrono::steady_clock::now();
  SceneGenerator generator(options.scene);
  PlyWriteOptions write_options;
  write_options.format = options.format;
  write_options.progress = options.progress;
  write_options.comments.push_back("scene " + options.scene.scene + " seed " +
                                   std::to_string(options.scene.seed));
  PlyStreamWriter writer(path, toExportLayout(generator.layout()), options.points, write_options);

  std::unique_ptr<tbb::global_control> limit;
  if (options.max_threads > 0) {
    limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                  std::size_t(options.max_threads));
  }
  const std::uint64_t block_count =
      (options.points + SceneGenerator::kBlockPoints - 1) / SceneGenerator::kBlockPoints;
  // Tokens bound the memory: at most this many blocks (about 1.8 MB each) exist at once.
  const std::size_t tokens = 4 * std::size_t(std::max(1, tbb::this_task_arena::max_concurrency()));
  std::uint64_t next_block = 0;
  tbb::parallel_pipeline(
      tokens,
      tbb::make_filter<void, std::uint64_t>(tbb::filter_mode::serial_in_order,
                                            [&](tbb::flow_control& control) -> std::uint64_t {
                                              if (next_block == block_count) {
                                                control.stop();
                                                return 0;
                                              }
                                              return next_block++;
                                            }) &
          tbb::make_filter<std::uint64_t, std::shared_ptr<PointCloud>>(
              tbb::filter_mode::parallel,
              [&](std::uint64_t block) {
                std::uint64_t first = block * SceneGenerator::kBlockPoints;
                std::size_t count = std::size_t(
                    std::min<std::uint64_t>(SceneGenerator::kBlockPoints, options.points - first));
                return std::make_shared<PointCloud>(
                    toExportLayout(generator.generateBlock(block, count)));
              }) &
          tbb::make_filter<std::shared_ptr<PointCloud>, void>(
              tbb::filter_mode::serial_in_order,
              [&](const std::shared_ptr<PointCloud>& chunk) { writer.write(*chunk); }));
  writer.finish();

  GenerateStats stats;
  stats.points = options.points;
  stats.bytes = std::filesystem::file_size(path);
  stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return stats;
}

}  // namespace parallax::synth
