#include "bench_render_filter.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "bench_timing.h"
#include "core/column_names.h"
#include "render/gl_context.h"
#include "render/point_buffers.h"
#include "render/renderer.h"

namespace parallax::cli {
namespace {

// A scanned-looking random cloud: a 100 m box of coloured points with whole intensities, 1-4
// returns and GPS times over an hour, so that every filter has something to keep and to drop.
PointCloud attributedCloud(std::uint64_t count) {
  PointCloud cloud;
  cloud.count = count;
  cloud.quantization.scale = {0.001, 0.001, 0.001};
  cloud.positions = Column<Int3>(count);
  cloud.colors = Column<Rgba8>(count);
  cloud.intensity = Column<float>(count);
  cloud.classification = Column<std::uint8_t>(count);
  ScalarColumn r{
      .name = column_names::kReturnNumber, .type = ScalarType::UInt8, .data = ByteBuffer(count)};
  ScalarColumn n{
      .name = column_names::kNumberOfReturns, .type = ScalarType::UInt8, .data = ByteBuffer(count)};
  ScalarColumn gps{
      .name = column_names::kGpsTime, .type = ScalarType::Float64, .data = ByteBuffer(count * 8)};
  std::mt19937 random(1234);
  std::uniform_int_distribution<std::int32_t> coordinate(-50'000, 50'000);
  for (std::uint64_t i = 0; i < count; ++i) {
    cloud.positions[i] = {coordinate(random), coordinate(random), coordinate(random) / 4};
    const std::uint32_t bits = random();
    cloud.colors[i] = {std::uint8_t(bits), std::uint8_t(bits >> 8), std::uint8_t(bits >> 16), 255};
    cloud.intensity[i] = float(bits >> 16);
    cloud.classification[i] = std::uint8_t(bits % 7);
    const std::uint8_t returns = std::uint8_t(1 + (bits >> 24) % 4);
    n.as<std::uint8_t>()[i] = returns;
    r.as<std::uint8_t>()[i] = std::uint8_t(1 + (bits >> 28) % returns);
    gps.as<double>()[i] = 400000000.0 + 3600.0 * double(i) / double(count);
  }
  cloud.scalars.push_back(std::move(r));
  cloud.scalars.push_back(std::move(n));
  cloud.scalars.push_back(std::move(gps));
  cloud.computeBounds();
  return cloud;
}

}  // namespace

int runBenchRenderFilter(const FilterRenderBenchOptions& o) {
  PointFilter filter = o.filter;
  if (filter.keepsAll()) filter.keepOnlyReturns({ReturnKind::First}, {});
  const std::vector<double> load_before = loadAverage();
  auto context = GlContext::createHeadless();
  const PointCloud cloud = attributedCloud(o.points);
  const PointCloud kept = filterPoints(cloud, filter);
  Camera camera;
  camera.lookAt({0.0, -80.0, 60.0}, {0.0, 0.0, 0.0}, {0, 0, 1});
  camera.fitToBounds(cloud.bounds, double(o.width) / o.height);
  const View view{camera, {0, 0, o.width, o.height}};
  RenderTarget target(o.width, o.height);
  Renderer renderer;
  GpuPointCloud gpu(cloud);
  RenderSettings plain = o.settings, filtered = o.settings;
  plain.filter = {};
  filtered.filter = filter;
  const auto draw = [&](const RenderSettings& settings) {
    renderer.render(gpu, std::span(&view, 1), settings, target.framebuffer(), o.width, o.height);
    glFinish();
  };
  // Warm-up: both shader variants compiled, the framebuffer touched.
  draw(filtered);
  const std::vector<std::uint8_t> filtered_picture = target.readRgba();
  draw(plain);
  const std::vector<std::uint8_t> plain_picture = target.readRgba();
  std::size_t changed = 0;
  for (std::size_t i = 0; i < plain_picture.size(); i += 4) {
    changed += !std::equal(&plain_picture[i], &plain_picture[i] + 4, &filtered_picture[i]);
  }

  // Rounds of four frames, each timed: plain after plain (steady), filtered after plain (the
  // toggle on), filtered after filtered, plain after filtered (the toggle off). One round after
  // another, so that a change in the machine's load hits every kind alike.
  enum Kind { kPlain, kToggleOn, kFiltered, kToggleOff, kKinds };
  const std::array<const char*, kKinds> names{"without filter", "first with filter", "with filter",
                                              "first without filter"};
  std::array<std::vector<double>, kKinds> wall, cpu;
  const std::uint64_t uploaded = uploadedPointBytes();
  for (int round = 0; round < o.repeat; ++round) {
    for (const auto& [kind, settings] :
         {std::pair{kPlain, &plain}, std::pair{kToggleOn, &filtered},
          std::pair{kFiltered, &filtered}, std::pair{kToggleOff, &plain}}) {
      const auto start = std::chrono::steady_clock::now();
      const double cpu_start = processCpuSeconds();
      draw(*settings);
      wall[kind].push_back(
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
      cpu[kind].push_back(processCpuSeconds() - cpu_start);
    }
  }
  const std::uint64_t uploaded_while_toggling = uploadedPointBytes() - uploaded;

  // Picking, as the viewer does on a click: read from the frame just drawn (the filtered one),
  // before the next is drawn. 100 pixels of a fixed random sequence; a hit returns the point.
  draw(filtered);
  std::vector<double> pick_wall;
  int hits = 0;
  std::mt19937 pixels(99);
  for (int i = 0; i < 100; ++i) {
    const int x = int(pixels() % std::uint32_t(o.width)),
              y = int(pixels() % std::uint32_t(o.height));
    const auto start = std::chrono::steady_clock::now();
    hits += renderer.pickPoint(x, y).has_value();
    pick_wall.push_back(
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }

  std::printf(
      "bench render --filter-toggle: %llu points (%llu kept by the filter), %dx%d, %s, "
      "median of %d rounds, on %s\n",
      static_cast<unsigned long long>(cloud.count), static_cast<unsigned long long>(kept.count),
      o.width, o.height,
      rasterizerKindName(
          renderer.chooseRasterizer(filtered, o.width, o.height, Composition::Direct))
          .data(),
      o.repeat, context->renderer().c_str());
  for (int kind = 0; kind < kKinds; ++kind) {
    std::printf("  %-22s %7.1f ms (cpu %7.1f ms)\n", names[std::size_t(kind)],
                median(wall[std::size_t(kind)]) * 1e3, median(cpu[std::size_t(kind)]) * 1e3);
  }
  std::printf("  toggle on / steady with filter %.2f, toggle off / steady without %.2f\n",
              median(wall[kToggleOn]) / median(wall[kFiltered]),
              median(wall[kToggleOff]) / median(wall[kPlain]));
  std::printf("  uploaded while toggling: %llu bytes; pixels the filter changes: %zu\n",
              static_cast<unsigned long long>(uploaded_while_toggling), changed);
  std::printf(
      "  a pick from the frame drawn: median %.3f ms, slowest %.3f ms (100 pixels, %d on a "
      "point), %.3f of a filtered frame\n",
      median(pick_wall) * 1e3, *std::max_element(pick_wall.begin(), pick_wall.end()) * 1e3, hits,
      median(pick_wall) / median(wall[kFiltered]));
  const std::vector<double> load_after = loadAverage();
  std::printf("  load average %.2f before, %.2f after\n", load_before[0], load_after[0]);
  return 0;
}

}  // namespace parallax::cli
