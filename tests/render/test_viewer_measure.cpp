// The measurement tools in a real window under Xvfb, driven with xdotool, against `parallax
// pick` at the same pixel of the same picture: in the viewer's own look on the demo scene the
// distance tool's clicks land on the points pick names, and an annotation saved with Ctrl + S is
// drawn by `parallax render --measurements` where the viewer showed it. The distance, height,
// area, angle and profile tools against oracles of the test's own: test_viewer_tools.cpp.
//
// Needs the Debian packages xvfb and xdotool; skipped (with the reason) where they are missing.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "render/image_file.h"
#include "support/temp_dir.h"
#include "viewer_window_support.h"

namespace parallax::test {
namespace {

using namespace std::chrono_literals;

// With the distance tool: the panel off the picture, a click on each pick's pixel (each logged
// as a point of the measurement), Enter, and the distance logged.
void measureBetweenTwoPicks(ViewerProcess& viewer, const nlohmann::json& first,
                            const nlohmann::json& second) {
  viewer.key("g");
  const nlohmann::json* picks[] = {&first, &second};
  for (int i = 0; i < 2; ++i) {
    viewer.click(picks[i]->at("point_pixel")[0], picks[i]->at("point_pixel")[1]);
    ASSERT_TRUE(viewer.logged("parallax view: distance point " + std::to_string(i + 1) + ": "))
        << viewer.log();
  }
  viewer.key("Return");
  ASSERT_TRUE(viewer.logged("parallax view: distance ", 10s) && viewer.logged(" m (2 points)", 10s))
      << viewer.log();
}

// The distance tool's lines for a measurement of two points: each point as the file holds it
// (exactly `points`, what `parallax pick` gave), then their distance, printed with six decimals.
void expectTwoPointDistanceLogged(const std::string& log,
                                  const std::array<std::array<double, 3>, 2>& points,
                                  double distance) {
  for (int i = 0; i < 2; ++i) {
    const std::string prefix = "parallax view: distance point " + std::to_string(i + 1) + ": ";
    std::istringstream line(log.substr(log.find(prefix) + prefix.size()));
    double x = 0, y = 0, z = 0;
    line >> x >> y >> z;
    EXPECT_EQ(x, points[i][0]) << log;
    EXPECT_EQ(y, points[i][1]) << log;
    EXPECT_EQ(z, points[i][2]) << log;
  }
  const std::string prefix = "parallax view: distance ";
  const auto at = log.find(" m (2 points)");
  const auto start = log.rfind(prefix, at) + prefix.size();
  EXPECT_NEAR(std::stod(log.substr(start, at - start)), distance, 5e-7) << log;
}

// The viewer's own look (no size, shape or lighting option: round points sized to the local
// spacing, lit) on the demo's scanned scene: the distance tool's two clicks land on the points
// drawn there, which `parallax pick` with the same look finds at exactly those pixels (the splat
// covers them, distance_px 0), and the distance is theirs.
TEST(ViewerWindow, DistanceOnTheDemoSceneInTheViewersDefaultLook) {
  if (!onPath("Xvfb") || !onPath("xdotool")) {
    GTEST_SKIP() << "needs Xvfb and xdotool (Debian packages xvfb, xdotool)";
  }
  TempDir dir;
  const auto cloud = dir / "scene.ply";
  ASSERT_EQ(run(std::string(PARALLAX_EXECUTABLE) + " generate -q -o " + cloud.string() +
                " --points 300000"),
            0);
  const std::vector<std::string> camera = {"--width",    "640",      "--height", "400",   "--eye",
                                           "10,-120,45", "--target", "0,0,0",    "--fov", "50"};
  // What the viewer chooses for a cloud with normals, spelled out for `pick` (whose default look
  // is render's 1-pixel points).
  const std::string viewer_look = " --size-mode adaptive --shape round --lighting";
  std::array<nlohmann::json, 2> expected;
  const std::array<std::string, 2> pixels = {"260,250", "400,300"};
  for (int i = 0; i < 2; ++i) {
    std::string args = " pick " + cloud.string() + " --pixel " + pixels[i] + " --json" +
                       " --radius 0" + viewer_look;
    for (const std::string& option : camera) args += " " + option;
    const auto json = dir / ("pick" + std::to_string(i) + ".json");
    ASSERT_EQ(run(std::string(PARALLAX_EXECUTABLE) + args + " > " + json.string()), 0);
    expected[i] = nlohmann::json::parse(readFile(json));
    ASSERT_TRUE(expected[i].at("found").get<bool>()) << pixels[i] << ": " << expected[i].dump();
    EXPECT_EQ(expected[i].at("distance_px").get<double>(), 0.0) << expected[i].dump();
  }
  auto point = [&](int i) {
    const nlohmann::json& p = expected[i].at("point");
    return std::array<double, 3>{p.at("x").get<double>(), p.at("y").get<double>(),
                                 p.at("z").get<double>()};
  };
  const auto a = point(0), b = point(1);
  const double distance = std::sqrt((b[0] - a[0]) * (b[0] - a[0]) + (b[1] - a[1]) * (b[1] - a[1]) +
                                    (b[2] - a[2]) * (b[2] - a[2]));
  ASSERT_GT(distance, 1.0) << "the two pixels picked nearly the same point";

  Display display(dir);
  ASSERT_FALSE(display.name().empty()) << "Xvfb did not start: " << readFile(dir / "xvfb.log");
  std::vector<std::string> view_args = {cloud.string(), "--no-vsync", "--tool", "distance"};
  view_args.insert(view_args.end(), camera.begin(), camera.end());
  ViewerProcess viewer(dir, display.name(), view_args, "viewer.log");
  ASSERT_TRUE(viewer.hasWindow()) << "no viewer window: " << viewer.log();
  EXPECT_TRUE(viewer.logged("parallax view: first picture after")) << viewer.log();
  ASSERT_NO_FATAL_FAILURE(measureBetweenTwoPicks(viewer, expected[0], expected[1]));
  EXPECT_EQ(viewer.log().find("picked nothing"), std::string::npos) << viewer.log();
  expectTwoPointDistanceLogged(viewer.log(), {point(0), point(1)}, distance);
  EXPECT_EQ(viewer.quit(), 0) << "the viewer did not quit on Escape: " << viewer.log();
}

// The annotation tool places a labelled point where the click picks one; Ctrl + S saves it with
// the camera, and `parallax render --measurements` draws it from that camera where the viewer
// showed it.
TEST(ViewerWindow, AnnotationSavedFromTheViewerIsDrawnByRender) {
  if (!onPath("Xvfb") || !onPath("xdotool")) {
    GTEST_SKIP() << "needs Xvfb and xdotool (Debian packages xvfb, xdotool)";
  }
  TempDir dir;
  const auto cloud = dir.write("grid.ply", gridPly());
  const std::vector<std::string> look = {"--width",      "640",   "--height", "400",
                                         "--point-size", "4",     "--eye",    "0.4,-1.6,1.2",
                                         "--target",     "0,0,0", "--fov",    "30"};
  std::string args = " pick " + cloud.string() + " --pixel 300,200 --json";
  for (const std::string& option : look) args += " " + option;
  ASSERT_EQ(run(std::string(PARALLAX_EXECUTABLE) + args + " > " + (dir / "pick.json").string()), 0);
  const nlohmann::json expected = nlohmann::json::parse(readFile(dir / "pick.json"));
  ASSERT_TRUE(expected.at("found").get<bool>()) << expected.dump();
  const int x = expected.at("point_pixel")[0], y = expected.at("point_pixel")[1];

  Display display(dir);
  ASSERT_FALSE(display.name().empty()) << "Xvfb did not start: " << readFile(dir / "xvfb.log");
  std::vector<std::string> view_args = {cloud.string(), "--no-vsync",       "--tool",
                                        "annotation",   "--screenshot-dir", dir.path().string()};
  view_args.insert(view_args.end(), look.begin(), look.end());
  ViewerProcess viewer(dir, display.name(), view_args, "viewer.log");
  ASSERT_TRUE(viewer.hasWindow()) << "no viewer window: " << viewer.log();
  EXPECT_TRUE(viewer.logged("parallax view: first picture after")) << viewer.log();
  viewer.key("g");
  viewer.click(x, y);
  ASSERT_TRUE(viewer.logged("parallax view: annotation 'Annotation 1' at ")) << viewer.log();
  viewer.key("ctrl+s");
  ASSERT_TRUE(viewer.logged("parallax view: measurements saved to ")) << viewer.log();
  EXPECT_EQ(viewer.quit(), 0) << viewer.log();

  const nlohmann::json saved = nlohmann::json::parse(readFile(dir / "measurements.json"));
  ASSERT_EQ(saved.at("annotations").size(), 1u) << saved.dump();
  const nlohmann::json& annotation = saved.at("annotations")[0];
  EXPECT_EQ(annotation.at("label"), "Annotation 1");
  for (int axis = 0; axis < 3; ++axis) {
    EXPECT_EQ(annotation.at("position")[axis].get<double>(),
              expected.at("point").at(std::string(1, char('x' + axis))).get<double>());
  }
  ASSERT_TRUE(annotation.contains("camera"));
  ASSERT_TRUE(saved.contains("camera"));
  EXPECT_EQ(saved.at("camera").at("position")[1].get<double>(), -1.6);

  // The same picture from the saved camera: the annotation's marker (cyan) on the point's pixel.
  const auto png = dir / "annotated.png";
  ASSERT_EQ(run(std::string(PARALLAX_EXECUTABLE) + " render " + cloud.string() + " -o " +
                png.string() + " --width 640 --height 400 --point-size 4 --measurements " +
                (dir / "measurements.json").string() + " 2> " + (dir / "render.log").string()),
            0)
      << readFile(dir / "render.log");
  EXPECT_NE(readFile(dir / "render.log").find("from its camera"), std::string::npos);
  const RgbaImage image = readPng(png);
  const std::size_t pixel = (std::size_t(y) * std::size_t(image.width) + std::size_t(x + 2)) * 4;
  EXPECT_NEAR(image.pixels[pixel], 51, 1);
  EXPECT_NEAR(image.pixels[pixel + 1], 255, 1);
  EXPECT_NEAR(image.pixels[pixel + 2], 255, 1);
}

}  // namespace
}  // namespace parallax::test
