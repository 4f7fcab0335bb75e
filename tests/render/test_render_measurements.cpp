// `parallax render --measurements FILE` end to end: the file's camera is used, a distance
// measurement's line lands on the pixels the test's own projection in double of its endpoints
// gives (UTM coordinates), faded behind a nearer point, and a malformed file is a clear error.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "render/camera.h"
#include "render/image_file.h"
#include "support/reference_projection.h"
#include "support/run_parallax.h"
#include "support/temp_dir.h"

namespace parallax::test {
namespace {

using test::readText;
using test::runWithoutLeakCheck;

constexpr double kEast = 432100.0, kNorth = 5123400.0, kUp = 250.0;
constexpr int kWidth = 320, kHeight = 240;

// A flat grey ground grid (every 0.5 units over 10 x 10) and one red point 10 units above the
// ground at (5, 5): nearer the camera than the ground under it.
std::string scenePly() {
  std::ostringstream ply;
  ply.precision(12);
  ply << "ply\nformat ascii 1.0\nelement vertex " << 21 * 21 + 1
      << "\nproperty double x\nproperty double y\nproperty double z\nproperty uchar red\n"
         "property uchar green\nproperty uchar blue\nend_header\n";
  for (int j = 0; j <= 20; ++j) {
    for (int i = 0; i <= 20; ++i) {
      ply << kEast + 0.5 * i << ' ' << kNorth + 0.5 * j << ' ' << kUp << " 90 90 90\n";
    }
  }
  ply << kEast + 5 << ' ' << kNorth + 5 << ' ' << kUp + 10 << " 255 0 0\n";
  return ply.str();
}

Camera topCamera() {
  Camera camera;
  camera.lookAt({kEast + 5, kNorth + 5, kUp + 40}, {kEast + 5, kNorth + 5, kUp}, {0, 1, 0});
  camera.fov_y_deg = 30;
  return camera;
}

// The measurement: a distance along y = 5 from x 1 to x 9 (through the red point's pixel).
nlohmann::json document() {
  return {{"format", "parallax-measurements"},
          {"version", 1},
          {"camera", cameraToJson(topCamera())},
          {"measurements",
           {{{"kind", "distance"},
             {"points", {{kEast + 1, kNorth + 5, kUp}, {kEast + 9, kNorth + 5, kUp}}}}}}};
}

// Where topCamera() puts a point, projected by the test's own matrix from the same eye, target, up
// and field of view (support/reference_projection.h), not by the product's camera.
std::pair<int, int> cpuPixel(double x, double y, double z) {
  ReferenceView view;
  view.eye = {kEast + 5, kNorth + 5, kUp + 40}, view.target = {kEast + 5, kNorth + 5, kUp};
  view.up = {0, 1, 0}, view.fov_y_deg = 30;
  view.width = kWidth, view.height = kHeight;
  const auto projected = referenceProject(view, {x, y, z});
  EXPECT_TRUE(projected.has_value()) << x << " " << y << " " << z << " is out of view";
  if (!projected) return {0, 0};
  return {projected->column(), projected->row(kHeight)};
}

std::array<int, 3> rgbAt(const RgbaImage& image, std::pair<int, int> pixel) {
  const std::size_t at =
      (std::size_t(pixel.second) * std::size_t(image.width) + std::size_t(pixel.first)) * 4;
  return {image.pixels[at], image.pixels[at + 1], image.pixels[at + 2]};
}

void expectColor(const std::array<int, 3>& got, const std::array<int, 3>& want, int tolerance,
                 const std::string& what) {
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(got[c], want[c], tolerance)
        << what << ": (" << got[0] << ", " << got[1] << ", " << got[2] << ")";
  }
}

TEST(RenderMeasurements, DistanceLineOnTheProjectedPixelsFadedBehindANearerPoint) {
  TempDir dir;
  const auto ply = dir.write("scene.ply", scenePly());
  const auto json = dir.write("measure.json", document().dump(2));
  const auto png = dir / "out.png";
  const std::string command =
      std::string(PARALLAX_EXECUTABLE) + " render " + ply.string() + " -o " + png.string() +
      " --width " + std::to_string(kWidth) + " --height " + std::to_string(kHeight) +
      " --point-size 9 --measurements " + json.string() + " 2> " + (dir / "log").string();
  ASSERT_EQ(runWithoutLeakCheck(command), 0) << readText(dir / "log");
  EXPECT_NE(readText(dir / "log").find("drew 1 measurements and 0 annotations"), std::string::npos)
      << readText(dir / "log");
  const RgbaImage image = readPng(png);
  ASSERT_EQ(image.width, kWidth);
  // The distance colour (measure/measurement_overlay.cpp): 1, 0.85, 0.1.
  const std::array<int, 3> line{255, 217, 26};
  for (double x : {2.0, 3.0, 7.0, 8.0}) {
    expectColor(rgbAt(image, cpuPixel(kEast + x, kNorth + 5, kUp)), line, 1,
                "the line at x " + std::to_string(x));
  }
  // Three pixels off the line (2 pixels wide) is the ground or the background, not the line.
  const auto off = cpuPixel(kEast + 3, kNorth + 5, kUp);
  EXPECT_NE(rgbAt(image, {off.first, off.second - 3}), line);
  EXPECT_NE(rgbAt(image, {off.first, off.second + 3}), line);
  // Under the red point 10 units above the ground the line is hidden: faded to 30 %.
  expectColor(rgbAt(image, cpuPixel(kEast + 5, kNorth + 5, kUp)),
              {int(0.7 * 255 + 0.3 * 255 + 0.5), int(0.3 * 217 + 0.5), int(0.3 * 26 + 0.5)}, 2,
              "the line behind the red point");
}

TEST(RenderMeasurements, CameraOptionsWinOverTheFilesCamera) {
  TempDir dir;
  const auto ply = dir.write("scene.ply", scenePly());
  const auto json = dir.write("measure.json", document().dump(2));
  const auto png = dir / "out.png";
  // Looking at the far corner from the side: the file's top view would put the line elsewhere.
  const std::string command = std::string(PARALLAX_EXECUTABLE) + " render " + ply.string() +
                              " -o " + png.string() + " --width " + std::to_string(kWidth) +
                              " --height " + std::to_string(kHeight) + " --eye " +
                              std::to_string(kEast + 30) + "," + std::to_string(kNorth + 30) + "," +
                              std::to_string(kUp + 20) + " --target " + std::to_string(kEast + 10) +
                              "," + std::to_string(kNorth + 10) + "," + std::to_string(kUp) +
                              " --measurements " + json.string() + " 2> " + (dir / "log").string();
  ASSERT_EQ(runWithoutLeakCheck(command), 0) << readText(dir / "log");
  EXPECT_EQ(readText(dir / "log").find("from its camera"), std::string::npos);
  const RgbaImage image = readPng(png);
  const auto where = cpuPixel(kEast + 3, kNorth + 5, kUp);
  EXPECT_NE(rgbAt(image, where), (std::array<int, 3>{255, 217, 26}));
}

TEST(RenderMeasurements, MalformedFileIsAnErrorNamingTheFileAndThePath) {
  TempDir dir;
  const auto ply = dir.write("scene.ply", scenePly());
  nlohmann::json bad = document();
  bad["measurements"][0]["points"][1] = {1, 2};
  const auto json = dir.write("bad.json", bad.dump());
  const std::string command = std::string(PARALLAX_EXECUTABLE) + " render " + ply.string() +
                              " -o " + (dir / "out.png").string() + " --measurements " +
                              json.string() + " 2> " + (dir / "log").string();
  EXPECT_EQ(runWithoutLeakCheck(command), 2);
  const std::string log = readText(dir / "log");
  EXPECT_NE(log.find("bad.json"), std::string::npos) << log;
  EXPECT_NE(log.find("measurements[0].points[1]"), std::string::npos) << log;
  EXPECT_NE(log.find("an array of 3 numbers"), std::string::npos) << log;
  EXPECT_FALSE(std::filesystem::exists(dir / "out.png"));
}

TEST(RenderMeasurements, ViewReadsTheFileBeforeOpeningAWindow) {
  // A malformed file stops `view` before it looks for a display: the same error as render's.
  TempDir dir;
  const auto ply = dir.write("scene.ply", scenePly());
  nlohmann::json bad = document();
  bad["measurements"][0]["kind"] = "volume";
  const auto json = dir.write("bad.json", bad.dump());
  const std::string command = "DISPLAY= " + std::string(PARALLAX_EXECUTABLE) + " view " +
                              ply.string() + " --measurements " + json.string() + " 2> " +
                              (dir / "log").string();
  EXPECT_EQ(runWithoutLeakCheck(command), 2);
  const std::string log = readText(dir / "log");
  EXPECT_NE(log.find("bad.json"), std::string::npos) << log;
  EXPECT_NE(log.find("measurements[0].kind"), std::string::npos) << log;
  EXPECT_NE(log.find("'volume'"), std::string::npos) << log;
  // An unknown tool is an option error (status 1) naming the tools there are.
  EXPECT_EQ(runWithoutLeakCheck("DISPLAY= " + std::string(PARALLAX_EXECUTABLE) + " view " +
                                ply.string() + " --tool ruler 2> " + (dir / "log").string()),
            1);
  EXPECT_NE(readText(dir / "log").find("distance, height, area"), std::string::npos)
      << readText(dir / "log");
}

}  // namespace
}  // namespace parallax::test
