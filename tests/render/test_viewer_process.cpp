// The viewer's Processing panel (issue 26 item 6), driven through the K key (run the panel's
// steps, given with --process-step) in a real window under Xvfb, as test_viewer_window.cpp:
// normals computed on a cloud that has none light it, and a distance-to result is shown coloured
// by its distance, the picture `parallax render --color distance` draws of the saved result; the
// Cancel button stops a run and leaves nothing behind.
// Skipped (with the reason) without the Debian packages xvfb and xdotool.
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "core/point_cloud.h"
#include "io/point_file.h"
#include "render/image_file.h"
#include "support/temp_dir.h"
#include "viewer_window_support.h"

namespace parallax::test {
namespace {

constexpr std::array<int, 3> kBackground{255, 0, 255};

// The colours of the cloud's pixels (all but the background).
std::set<std::array<int, 3>> cloudColours(const RgbaImage& image) {
  std::set<std::array<int, 3>> colours;
  for (std::size_t i = 0; i < image.pixels.size(); i += 4) {
    const std::array<int, 3> c{image.pixels[i], image.pixels[i + 1], image.pixels[i + 2]};
    if (c != kBackground) colours.insert(c);
  }
  return colours;
}

// A given camera (the same for `view` and `render`), fixed 3-pixel points, no panel in the way.
std::vector<std::string> sharedOptions() {
  return {"--width",      "480", "--height", "360",          "--background", "255,0,255",
          "--point-size", "3",   "--eye",    "0.9,-1.2,1.1", "--target",     "0,0,0.05"};
}

TEST(ViewerProcess, NormalsComputedInTheViewerLightTheCloud) {
  if (!onPath("Xvfb") || !onPath("xdotool")) {
    GTEST_SKIP() << "needs Xvfb and xdotool (Debian packages xvfb, xdotool)";
  }
  TempDir dir;
  const auto cloud = dir.write("grid.ply", gridPly());
  const auto output = dir / "grid-normals.ply";
  const auto shots = dir.path() / "shots";
  std::filesystem::create_directories(shots);
  Display display(dir);
  ASSERT_FALSE(display.name().empty()) << "Xvfb did not start: " << readFile(dir / "xvfb.log");
  std::vector<std::string> args = {
      cloud.string(), "--screenshot-dir", shots.string(), "--no-vsync",       "--color",
      "uniform",      "--process-step",   "normals 8",    "--process-output", output.string()};
  for (const std::string& option : sharedOptions()) args.push_back(option);
  ViewerProcess viewer(dir, display.name(), args, "viewer.log");
  ASSERT_TRUE(viewer.hasWindow()) << "no viewer window: " << viewer.log();
  EXPECT_TRUE(viewer.logged("parallax view: first picture after")) << viewer.log();
  viewer.key("g");  // hide the panel
  // Unlit, one uniform colour: the file has no normals.
  EXPECT_EQ(cloudColours(viewer.settledScreenshot(shots)).size(), 1u);

  viewer.key("k");
  EXPECT_TRUE(viewer.logged("parallax view: processed into " + output.string())) << viewer.log();
  const PointCloud saved = readPointFile(output);
  EXPECT_EQ(saved.count, 3600u);
  EXPECT_TRUE(saved.hasNormals());
  // Lit by its new normals: the dome shades from one side to the other.
  const auto lit = [](const RgbaImage& image) { return cloudColours(image).size() >= 20; };
  EXPECT_TRUE(lit(viewer.settledScreenshot(shots, lit))) << viewer.log();
  EXPECT_EQ(viewer.quit(), 0) << viewer.log();
}

// With the clip box on (here the command line's), the steps run on the points inside it only.
TEST(ViewerProcess, WithTheClipBoxOnOnlyItsPointsAreProcessed) {
  if (!onPath("Xvfb") || !onPath("xdotool")) {
    GTEST_SKIP() << "needs Xvfb and xdotool (Debian packages xvfb, xdotool)";
  }
  TempDir dir;
  const auto cloud = dir.write("grid.ply", gridPly());
  const PointCloud grid = readPointFile(cloud);
  std::uint64_t inside = 0;  // the grid's points in the box below, counted here
  for (std::size_t i = 0; i < grid.count; ++i) {
    const double x = grid.worldX(i), y = grid.worldY(i);
    inside += x >= -0.2 && x <= 0.3 && y >= -0.6 && y <= 0.1;
  }
  ASSERT_GT(inside, 300u);
  ASSERT_LT(inside, grid.count / 2);
  const auto output = dir / "box-normals.ply";
  const auto shots = dir.path() / "shots";
  std::filesystem::create_directories(shots);
  Display display(dir);
  ASSERT_FALSE(display.name().empty()) << "Xvfb did not start: " << readFile(dir / "xvfb.log");
  std::vector<std::string> args = {cloud.string(),   "--screenshot-dir", shots.string(),
                                   "--no-vsync",     "--clip-box",       "-0.2,-0.6,-1,0.3,0.1,1",
                                   "--process-step", "normals 8",        "--process-output",
                                   output.string()};
  for (const std::string& option : sharedOptions()) args.push_back(option);
  ViewerProcess viewer(dir, display.name(), args, "viewer.log");
  ASSERT_TRUE(viewer.hasWindow()) << "no viewer window: " << viewer.log();
  EXPECT_TRUE(viewer.logged("parallax view: first picture after")) << viewer.log();
  viewer.key("k");
  EXPECT_TRUE(viewer.logged("(its clip box) into " + output.string())) << viewer.log();
  EXPECT_TRUE(viewer.logged("parallax view: processed into " + output.string())) << viewer.log();
  const PointCloud saved = readPointFile(output);
  EXPECT_EQ(saved.count, inside);
  EXPECT_TRUE(saved.hasNormals());
  EXPECT_EQ(viewer.quit(), 0) << viewer.log();
}

// The panel's Cancel button: a run held at its first progress report (the test hook
// PARALLAX_VIEW_TEST_HOLD_PROCESS: the run waits there until Cancel is pressed, so the click
// always lands while it is under way, whatever the machine's speed), the button clicked where
// the viewer says it drew it: the panel says the run was cancelled, nothing is left in the
// output's folder (no output, no temporary or work file), the input file is as it was and the
// picture is the one before, pixel for pixel.
TEST(ViewerProcess, CancelStopsTheRunLeavesNothingAndKeepsTheCloudShown) {
  if (!onPath("Xvfb") || !onPath("xdotool")) {
    GTEST_SKIP() << "needs Xvfb and xdotool (Debian packages xvfb, xdotool)";
  }
  TempDir dir;
  const auto cloud = dir.write("grid.ply", gridPly());
  const std::string cloud_bytes = readFile(cloud);
  const auto out = dir.path() / "out";
  const auto shots = dir.path() / "shots";
  std::filesystem::create_directories(out);
  std::filesystem::create_directories(shots);
  const auto output = out / "grid-normals.ply";
  Display display(dir);
  ASSERT_FALSE(display.name().empty()) << "Xvfb did not start: " << readFile(dir / "xvfb.log");
  // A window tall enough for the panel's Processing part beside the cloud.
  const std::vector<std::string> args = {cloud.string(),
                                         "--screenshot-dir",
                                         shots.string(),
                                         "--no-vsync",
                                         "--process-step",
                                         "normals 8",
                                         "--process-output",
                                         output.string(),
                                         "--width",
                                         "900",
                                         "--height",
                                         "700",
                                         "--background",
                                         "255,0,255",
                                         "--point-size",
                                         "3",
                                         "--eye",
                                         "0.9,-1.2,1.1",
                                         "--target",
                                         "0,0,0.05"};
  ViewerProcess viewer(dir, display.name(), args, "viewer.log",
                       {"PARALLAX_VIEW_TEST_HOLD_PROCESS=1"});
  ASSERT_TRUE(viewer.hasWindow()) << "no viewer window: " << viewer.log();
  EXPECT_TRUE(viewer.logged("parallax view: first picture after")) << viewer.log();
  const RgbaImage before = viewer.settledScreenshot(shots);

  viewer.key("k");
  ASSERT_TRUE(viewer.logged("parallax view: processing held at its first progress report"))
      << viewer.log();
  const std::string button = "parallax view: Cancel button at ";
  ASSERT_TRUE(viewer.logged(button)) << viewer.log();
  const std::string log = viewer.log();
  int x = -1, y = -1;
  ASSERT_EQ(std::sscanf(log.c_str() + log.find(button) + button.size(), "%d %d", &x, &y), 2) << log;
  viewer.click(x, y);
  EXPECT_TRUE(
      viewer.logged("parallax view: processing cancelled: nothing written to " + output.string()))
      << viewer.log();
  EXPECT_EQ(viewer.log().find("processed into"), std::string::npos) << viewer.log();
  std::vector<std::string> left;
  for (const auto& entry : std::filesystem::directory_iterator(out)) {
    left.push_back(entry.path().filename().string());
  }
  EXPECT_TRUE(left.empty()) << left.front() << " is left in the output's folder";
  EXPECT_EQ(readFile(cloud), cloud_bytes);
  const RgbaImage after = viewer.settledScreenshot(shots);
  EXPECT_EQ(after.width, before.width);
  EXPECT_EQ(after.height, before.height);
  EXPECT_TRUE(after.pixels == before.pixels) << "the picture changed";
  EXPECT_EQ(viewer.quit(), 0) << viewer.log();
}

TEST(ViewerProcess, DistanceToAReferenceIsShownThroughTheRamp) {
  if (!onPath("Xvfb") || !onPath("xdotool")) {
    GTEST_SKIP() << "needs Xvfb and xdotool (Debian packages xvfb, xdotool)";
  }
  TempDir dir;
  const auto cloud = dir.write("grid.ply", gridPly());
  // The reference: the dome's plane (z 0), 30 x 30.
  std::ostringstream plane;
  plane << "ply\nformat ascii 1.0\nelement vertex 900\nproperty float x\nproperty float y\n"
           "property float z\nend_header\n";
  for (int j = 0; j < 30; ++j) {
    for (int i = 0; i < 30; ++i) plane << i / 29.0 - 0.5 << ' ' << j / 29.0 - 0.5 << " 0\n";
  }
  const auto reference = dir.write("plane.ply", plane.str());
  const auto output = dir / "grid-distance.ply";
  const auto shots = dir.path() / "shots";
  std::filesystem::create_directories(shots);
  Display display(dir);
  ASSERT_FALSE(display.name().empty()) << "Xvfb did not start: " << readFile(dir / "xvfb.log");
  std::vector<std::string> args = {cloud.string(),     "--screenshot-dir",
                                   shots.string(),     "--no-vsync",
                                   "--process-step",   "distance-to " + reference.string(),
                                   "--process-output", output.string()};
  for (const std::string& option : sharedOptions()) args.push_back(option);
  ViewerProcess viewer(dir, display.name(), args, "viewer.log");
  ASSERT_TRUE(viewer.hasWindow()) << "no viewer window: " << viewer.log();
  EXPECT_TRUE(viewer.logged("parallax view: first picture after")) << viewer.log();
  viewer.key("g");
  viewer.key("k");
  EXPECT_TRUE(viewer.logged("parallax view: processed into " + output.string())) << viewer.log();

  // What `render` draws of the saved result, coloured by its distance.
  const auto expected_png = dir / "render-distance.png";
  std::string command = std::string(PARALLAX_EXECUTABLE) + " render " + output.string() + " -o " +
                        expected_png.string() + " --quiet --color distance";
  for (const std::string& option : sharedOptions()) command += " " + option;
  ASSERT_EQ(run(command + " > " + (dir / "render.log").string() + " 2>&1"), 0)
      << readFile(dir / "render.log");
  const RgbaImage expected = readPng(expected_png);
  ASSERT_GE(cloudColours(expected).size(), 20u) << "the distances are not spread over the ramp";
  const auto matches = [&](const RgbaImage& image) { return sameFraction(image, expected) > 0.98; };
  const RgbaImage shown = viewer.settledScreenshot(shots, matches);
  EXPECT_GT(sameFraction(shown, expected), 0.98) << viewer.log();
  EXPECT_EQ(viewer.quit(), 0) << viewer.log();
}

}  // namespace
}  // namespace parallax::test
