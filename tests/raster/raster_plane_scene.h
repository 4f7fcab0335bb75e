// The tilted plane raster of the raster-layer tests (test_raster_layer.cpp: `render --raster`;
// tests/render/test_viewer_panels.cpp: the viewer's layer in a window), with the colours a cell
// must get worked out from the plane's equation, and two points that set the camera's extent.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <numbers>
#include <string>

#include <gtest/gtest.h>

#include "core/point_cloud.h"
#include "raster/raster_image.h"
#include "render/image_file.h"

namespace parallax::test {

// The plane z = 0.5 x + 0.25 y over 20 x 10 cells of 1 unit from (0, 0).
constexpr double kDzDx = 0.5, kDzDy = 0.25;
constexpr int kColumns = 20, kRows = 10;

inline double plane(double x, double y) {
  return kDzDx * x + kDzDy * y;
}

inline RasterImage planeRaster() {
  RasterImage image;
  image.grid = {
      .left = 0.0, .top = double(kRows), .resolution = 1.0, .columns = kColumns, .rows = kRows};
  image.values.resize(std::size_t(kColumns) * kRows);
  for (int row = 0; row < kRows; ++row) {
    for (int column = 0; column < kColumns; ++column) {
      image.at(column, row) = float(plane(column + 0.5, kRows - row - 0.5));
    }
  }
  image.at(3, 4) = image.nodata;  // a hole: no point there
  return image;
}

// gdaldem's hillshade of the plane (light from the north-west, 45 degrees up): 1 + 254 times the
// cosine between the light and the plane's normal (-dz/dx, -dz/dy, 1).
inline double planeShade() {
  const double altitude = std::numbers::pi / 4, azimuth = 315.0 * std::numbers::pi / 180.0;
  const std::array<double, 3> light{std::cos(altitude) * std::sin(azimuth),
                                    std::cos(altitude) * std::cos(azimuth), std::sin(altitude)};
  const double norm = std::sqrt(kDzDx * kDzDx + kDzDy * kDzDy + 1.0);
  const double cosine = (-kDzDx * light[0] - kDzDy * light[1] + light[2]) / norm;
  return 1.0 + 254.0 * cosine;
}

// The grey the layer gives a cell of height z, shaded by `shade` (0..255).
inline int expectedGrey(double z, double shade) {
  const double low = plane(0.5, 0.5), high = plane(kColumns - 0.5, kRows - 0.5);
  const double grey = std::round(255.0 * (z - low) / (high - low));
  return int(std::lround(grey * (0.4 + 0.6 * shade / 255.0)));
}

inline Rgba8 greyRamp(double t) {
  const auto v = std::uint8_t(std::lround(255.0 * t));
  return {v, v, v, 255};
}

// Two points that set the camera's extent: 30 x 20 units around the raster.
inline std::string cornersPly() {
  return "ply\nformat ascii 1.0\nelement vertex 2\nproperty double x\nproperty double y\n"
         "property double z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\n"
         "end_header\n-5 -5 0 255 0 0\n25 15 0 255 0 0\n";
}

// How `render --raster` and the viewer's window draw the layer for expectPlaneLayerPicture:
// orthographic from above, the view's height the extent's largest side (30 units) over 300
// pixels, centred on (10, 5); squares of 12 pixels (GL_POINTS), on magenta.
inline const std::string kPlaneLayerLook =
    "--raster-ramp grey --width 300 --height 300 --point-size 12 --ortho --eye 10,5,100 "
    "--target 10,5,0 --up 0,1,0 --background 255,0,255 --rasterizer points";

// The picture of the plane's layer drawn with kPlaneLayerLook: at the pixel where each cell's
// centre projects, the cell's grey shaded by the plane's hillshade (the border and the hole's
// neighbours by the flat shade gdaldem gives an edge), and the background in the hole.
inline void expectPlaneLayerPicture(const RgbaImage& image) {
  constexpr int kSize = 300;
  constexpr double kPixelsPerUnit = kSize / 30.0, kCentreX = 10.0, kCentreY = 5.0;
  ASSERT_EQ(image.width, kSize);
  const double flat = 1.0 + 254.0 * std::sin(std::numbers::pi / 4);
  int checked = 0;
  for (int row = 0; row < kRows; ++row) {
    for (int column = 0; column < kColumns; ++column) {
      const double x = column + 0.5, y = kRows - row - 0.5;
      const int px = int(std::floor(kSize / 2.0 + (x - kCentreX) * kPixelsPerUnit));
      const int py = int(std::floor(kSize / 2.0 - (y - kCentreY) * kPixelsPerUnit));
      const std::uint8_t* p = &image.pixels[(std::size_t(py) * kSize + px) * 4];
      if (column == 3 && row == 4) {  // the hole: its neighbours' squares reach 1 pixel in
        EXPECT_EQ((std::array<int, 3>{p[0], p[1], p[2]}), (std::array<int, 3>{255, 0, 255}));
        continue;
      }
      const bool border = row == 0 || column == 0 || row == kRows - 1 || column == kColumns - 1;
      const bool by_hole = std::abs(row - 4) <= 1 && std::abs(column - 3) <= 1;
      const int grey = expectedGrey(plane(x, y), border || by_hole ? flat : planeShade());
      EXPECT_NEAR(p[0], grey, 2) << column << ',' << row;
      EXPECT_EQ(p[0], p[1]) << column << ',' << row;
      EXPECT_EQ(p[1], p[2]) << column << ',' << row;
      ++checked;
    }
  }
  EXPECT_EQ(checked, kColumns * kRows - 1);
}

}  // namespace parallax::test
