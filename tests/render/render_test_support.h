// Shared helpers of the renderer's tests: one headless context per process, small clouds built
// in code, and rendering a cloud into an image.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <random>

#include "core/point_cloud.h"
#include "render/gl_context.h"
#include "render/image_file.h"
#include "render/point_buffers.h"
#include "render/renderer.h"

namespace parallax::test {

// The process's headless context, created on first use (EGL surfaceless on Mesa llvmpipe).
// Deliberately never destroyed: eglTerminate unloads Mesa's driver, after which LeakSanitizer
// cannot name the driver's frames and its suppressions (sanitizer_options.cpp) stop matching.
inline GlContext& headlessContext() {
  static GlContext* context = GlContext::createHeadless().release();
  return *context;
}

// A cloud from world positions, quantized with `scale` around `offset`; every attribute filled
// so that each colour mode has something to show.
inline PointCloud makeCloud(const std::vector<std::array<double, 3>>& world,
                            std::array<double, 3> offset, double scale) {
  PointCloud cloud;
  cloud.count = world.size();
  cloud.quantization.scale = {scale, scale, scale};
  cloud.quantization.offset = offset;
  cloud.positions = Column<Int3>(world.size());
  cloud.colors = Column<Rgba8>(world.size());
  cloud.normals = Column<Float3>(world.size());
  cloud.intensity = Column<float>(world.size());
  cloud.classification = Column<std::uint8_t>(world.size());
  for (std::size_t i = 0; i < world.size(); ++i) {
    const auto& p = world[i];
    cloud.positions[i] = {cloud.quantization.toQuantized(0, p[0]),
                          cloud.quantization.toQuantized(1, p[1]),
                          cloud.quantization.toQuantized(2, p[2])};
    cloud.colors[i] = {std::uint8_t(i * 37 % 256), std::uint8_t(i * 91 % 256),
                       std::uint8_t(255 - i % 256), 255};
    cloud.normals[i] = {0.0f, 0.0f, 1.0f};
    cloud.intensity[i] = float(i % 1000);
    cloud.classification[i] = std::uint8_t(i % 19);
  }
  cloud.computeBounds();
  return cloud;
}

// A wavy square sheet, side 2 units, centred at `center`, `side` x `side` points, with normals,
// colours, intensity and classification that vary smoothly across it (golden-image scenes).
inline PointCloud makeWavySheet(int side, std::array<double, 3> center) {
  std::vector<std::array<double, 3>> world;
  for (int j = 0; j < side; ++j) {
    for (int i = 0; i < side; ++i) {
      const double u = 2.0 * i / (side - 1) - 1.0, v = 2.0 * j / (side - 1) - 1.0;
      world.push_back(
          {center[0] + u, center[1] + v, center[2] + 0.25 * std::sin(3.0 * u) * std::cos(2.0 * v)});
    }
  }
  PointCloud cloud = makeCloud(world, center, 1.0 / 4096);
  for (std::size_t k = 0; k < world.size(); ++k) {
    const double u = world[k][0] - center[0], v = world[k][1] - center[1];
    // The surface's true normal: (-dz/du, -dz/dv, 1), normalised.
    const double du = 0.75 * std::cos(3.0 * u) * std::cos(2.0 * v);
    const double dv = -0.5 * std::sin(3.0 * u) * std::sin(2.0 * v);
    const double length = std::sqrt(du * du + dv * dv + 1.0);
    cloud.normals[k] = {float(-du / length), float(-dv / length), float(1.0 / length)};
    cloud.colors[k] = {std::uint8_t(127.5 + 127.5 * u), std::uint8_t(127.5 + 127.5 * v), 96, 255};
    cloud.intensity[k] = float(500.0 + 500.0 * std::sin(5.0 * u + 3.0 * v));
    cloud.classification[k] = std::uint8_t(int((u + 1.0) * 3.0) + 2 * int((v + 1.0) * 1.5));
  }
  return cloud;
}

// A frame asked of one rasterizer was drawn by it: none falls back silently (Auto may choose).
inline void expectDrawnBy(const FrameStats& stats, RasterizerKind asked) {
  if (asked == RasterizerKind::Auto) return;
  EXPECT_EQ(stats.rasterizer, asked) << "asked for " << rasterizerKindName(asked)
                                     << ", drawn by the other: " << stats.fallback_reason;
}

// Renders one mono view of `cloud` into a width x height image.
inline RgbaImage renderImage(const PointCloud& cloud, const Camera& camera, int width, int height,
                             const RenderSettings& settings,
                             const PointUploadOptions& upload = {}) {
  headlessContext();
  GpuPointCloud gpu(cloud, upload);
  Renderer renderer;
  RenderTarget target(width, height);
  const View view{camera, {0, 0, width, height}};
  expectDrawnBy(
      renderer.render(gpu, std::span(&view, 1), settings, target.framebuffer(), width, height),
      settings.rasterizer);
  return {width, height, target.readRgba()};
}

}  // namespace parallax::test
