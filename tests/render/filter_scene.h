// The scene of the render filter tests (test_render_filters*.cpp): about 2 000 points placed one
// to a pixel, away from pixel edges, so that every kept point lights exactly one pixel of its
// own colour; each point has a class, an intensity, a return of a number of returns and a GPS
// time. A filter's render of the whole scene must equal the render of the points kept by hand.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "render/camera.h"
#include "render/image_file.h"
#include "support/run_parallax.h"
#include "support/temp_dir.h"

namespace parallax::test::filter_scene {

constexpr int kWidth = 160, kHeight = 120;

// GPS times are kGpsBase + gps_us microseconds: 100 s of them, so that one float relative to a
// chunk's base (7.6 us steps at 100 s) could not tell neighbours apart.
constexpr double kGpsBase = 400000000.0;

struct Point {
  long long mm[3];  // world position in millimetres
  int cls;
  int r, g, b;
  int intensity = 0;         // 0-999
  int ret = 1, returns = 1;  // return `ret` of `returns` (1-4)
  long long gps_us = 0;      // 0-1e8
};

struct Scene {
  std::array<double, 3> center;  // world, a whole number of millimetres
  std::array<double, 3> eye;
  std::vector<Point> points;
  bool classified = true;
  bool attributes = false;  // intensity, returns and GPS time in the file

  std::string cameraOptions() const {
    std::ostringstream o;
    o << std::fixed << std::setprecision(3) << "--eye " << eye[0] << ',' << eye[1] << ',' << eye[2]
      << " --target " << center[0] << ',' << center[1] << ',' << center[2]
      << " --up 0,0,1 --fov 50";
    return o.str();
  }
};

inline std::string plyOf(const std::vector<Point>& points, bool classified,
                         bool attributes = false) {
  std::ostringstream ply;
  ply << "ply\nformat ascii 1.0\nelement vertex " << points.size()
      << "\nproperty double x\nproperty double y\nproperty double z\nproperty uchar red\n"
         "property uchar green\nproperty uchar blue\n"
      << (classified ? "property uchar classification\n" : "")
      << (attributes ? "property ushort intensity\nproperty uchar return_number\n"
                       "property uchar number_of_returns\nproperty double gps_time\n"
                     : "")
      << "end_header\n";
  for (const Point& p : points) {
    // Millimetres printed exactly: the integer metres, then three digits.
    for (int a = 0; a < 3; ++a) {
      ply << p.mm[a] / 1000 << '.' << std::setw(3) << std::setfill('0') << p.mm[a] % 1000
          << std::setfill(' ') << ' ';
    }
    ply << p.r << ' ' << p.g << ' ' << p.b;
    if (classified) ply << ' ' << p.cls;
    if (attributes) {
      ply << ' ' << p.intensity << ' ' << p.ret << ' ' << p.returns << ' '
          << std::llround(kGpsBase) + p.gps_us / 1000000 << '.' << std::setw(6) << std::setfill('0')
          << p.gps_us % 1000000 << std::setfill(' ');
    }
    ply << '\n';
  }
  return ply.str();
}

// About 2 000 points in a 4 x 3 x 1 m box around `center` on a millimetre grid, classes 0-12,
// kept only where they project one to a pixel at least 0.1 pixel from its edges (the same
// camera as the renders, in double).
inline Scene makeScene(std::array<double, 3> center, bool classified) {
  Scene scene;
  scene.center = center;
  scene.eye = {center[0] + 1.0, center[1] - 3.5, center[2] + 3.0};
  scene.classified = classified;
  Camera camera;
  camera.lookAt({scene.eye[0], scene.eye[1], scene.eye[2]}, {center[0], center[1], center[2]},
                {0, 0, 1});
  camera.fov_y_deg = 50;
  Bounds3 bounds;  // (the clip range does not move points across the picture)
  bounds.extend(center[0] - 2.0, center[1] - 1.5, center[2] - 0.5);
  bounds.extend(center[0] + 2.0, center[1] + 1.5, center[2] + 0.5);
  const glm::dmat4 to_clip =
      camera.projectionMatrix(double(kWidth) / kHeight, camera.clipRange(bounds)) *
      camera.viewMatrix();
  std::uint32_t state = 12345;
  auto next = [&] {  // xorshift32
    state ^= state << 13;
    state ^= state >> 17;
    state ^= state << 5;
    return state;
  };
  std::set<std::pair<int, int>> taken;
  for (int i = 0; i < 4000; ++i) {
    Point p{};
    const long long extent[3] = {4000, 3000, 1000};
    for (int a = 0; a < 3; ++a) {
      p.mm[a] = std::llround(center[std::size_t(a)] * 1000.0) - extent[a] / 2 +
                (long long)(next() % std::uint32_t(extent[a] + 1));
    }
    p.cls = classified ? int(next() % 13) : 0;
    p.r = 40 + i % 200, p.g = 40 + (i / 200) % 200, p.b = 60 + 10 * p.cls;
    p.intensity = int(next() % 1000);
    p.returns = 1 + int(next() % 4);
    p.ret = 1 + int(next() % std::uint32_t(p.returns));
    // Half of the points within 8 us of 20 s or 70 s past the base, where the GPS tests put
    // their bounds, the rest anywhere in the 100 s.
    const long long mark = i % 4 == 0 ? 20000000 : 70000000;
    p.gps_us = i % 2 ? (long long)(next() % 100000001u) : mark - 8 + (long long)(next() % 17u);
    const glm::dvec4 clip =
        to_clip * glm::dvec4(p.mm[0] / 1000.0, p.mm[1] / 1000.0, p.mm[2] / 1000.0, 1.0);
    if (clip.w <= 0) continue;
    const double x = (clip.x / clip.w + 1) * 0.5 * kWidth,
                 y = (clip.y / clip.w + 1) * 0.5 * kHeight;
    const double fx = x - std::floor(x), fy = y - std::floor(y);
    if (x < 1 || y < 1 || x > kWidth - 1 || y > kHeight - 1) continue;
    if (fx < 0.1 || fx > 0.9 || fy < 0.1 || fy > 0.9) continue;
    if (!taken.insert({int(x), int(y)}).second) continue;
    scene.points.push_back(p);
  }
  EXPECT_GT(scene.points.size(), 1500u);
  return scene;
}

// The filtered render against the render of the points kept by hand: every kept point lights
// its own pixel (`kept` pixels lit) and no pixel differs.
inline void expectSamePicture(const RgbaImage& filtered, const RgbaImage& expected,
                              std::size_t kept, const std::string& options) {
  ASSERT_EQ(filtered.pixels.size(), expected.pixels.size());
  std::size_t lit = 0, different = 0;
  for (std::size_t i = 0; i < expected.pixels.size(); i += 4) {
    lit += (expected.pixels[i] | expected.pixels[i + 1] | expected.pixels[i + 2]) != 0;
    different += !std::equal(&expected.pixels[i], &expected.pixels[i] + 4, &filtered.pixels[i]);
  }
  EXPECT_EQ(lit, kept) << options;
  EXPECT_EQ(different, 0u) << options << ": pixels that differ from the CPU-filtered render";
}

}  // namespace parallax::test::filter_scene
