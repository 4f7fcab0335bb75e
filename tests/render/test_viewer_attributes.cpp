// The viewer reads a COPC octree's nodes with what its look draws (issue 25 item 4): the first
// load of an RGB picture decodes no intensity, and switching the colour mode (the C key: rgb,
// elevation, intensity, normal, classification) reads the nodes again with what the new mode
// shows, so that the picture after each switch is the one `parallax render` draws with the same
// settings. A plain LAZ of format 7 drawn whole is read the same way (cloud_attributes.cpp):
// first with what the picture draws, then the layers a colour mode or a pick asks for. On
// copc.js's ellipsoid.copc.laz (format 7, 100 000 points), in a real window under
// Xvfb driven with xdotool as in test_viewer_window.cpp; skipped (with the reason) without the
// Debian packages xvfb and xdotool.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "render/image_file.h"
#include "support/temp_dir.h"
#include "support/test_data.h"
#include "viewer_window_support.h"

namespace parallax::test {
namespace {

// The same camera, size and look for `view` and `render`: a camera given (not fitted beside the
// panel), fixed 3-pixel square points, no lighting choice (the file has no normals).
std::vector<std::string> sharedOptions() {
  return {"--width",      "480",
          "--height",     "360",
          "--background", "255,0,255",
          "--point-size", "3",
          "--eye",        "-8242596,4966300,250",
          "--target",     "-8242596,4966606,0"};
}

RgbaImage renderWith(const TempDir& dir, const std::filesystem::path& input,
                     const std::string& color) {
  const auto out = dir / ("render-" + color + ".png");
  std::string command = std::string(PARALLAX_EXECUTABLE) + " render " + input.string() + " -o " +
                        out.string() + " --quiet --color " + color;
  for (const std::string& option : sharedOptions()) command += " " + option;
  command += " > " + (dir / ("render-" + color + ".log")).string() + " 2>&1";
  EXPECT_EQ(run(command), 0) << command << ": " << readFile(dir / ("render-" + color + ".log"));
  return readPng(out);
}

// The pixels the cloud covers: those not of the background colour (255, 0, 255).
std::size_t cloudPixels(const RgbaImage& image) {
  std::size_t count = 0;
  for (std::size_t i = 0; i < image.pixels.size(); i += 4) {
    count += !(image.pixels[i] == 255 && image.pixels[i + 1] == 0 && image.pixels[i + 2] == 255);
  }
  return count;
}

// The "octree nodes read with ..." lines of the log, in order.
std::vector<std::string> readLines(const std::string& log) {
  std::vector<std::string> lines;
  const std::string prefix = "parallax view: octree nodes read with ";
  for (auto at = log.find(prefix); at != std::string::npos; at = log.find(prefix, at + 1)) {
    lines.push_back(log.substr(at + prefix.size(), log.find('\n', at) - at - prefix.size()));
  }
  return lines;
}

// The window's arguments: `input` in the shared look, P screenshots written into `shots`.
std::vector<std::string> viewerArgs(const std::filesystem::path& input,
                                    const std::filesystem::path& shots) {
  std::filesystem::create_directories(shots);
  std::vector<std::string> args = {input.string(), "--screenshot-dir", shots.string(),
                                   "--no-vsync"};
  for (const std::string& option : sharedOptions()) args.push_back(option);
  return args;
}

// Whether a screenshot shows `expected`: 98 % of its pixels the same (edges may differ).
std::function<bool(const RgbaImage&)> showing(const RgbaImage& expected) {
  return [&expected](const RgbaImage& image) { return sameFraction(image, expected) > 0.98; };
}

// The "parallax view: picked ..." line of the log, or "" when there is none.
std::string pickedLine(const std::string& log) {
  const std::size_t picked = log.find("parallax view: picked ");
  if (picked == std::string::npos) return "";
  return log.substr(picked, log.find('\n', picked) - picked);
}

TEST(ViewerAttributes, ColourSwitchesReadTheNodesAgainAndDrawWhatRenderDraws) {
  if (!onPath("Xvfb") || !onPath("xdotool")) {
    GTEST_SKIP() << "needs Xvfb and xdotool (Debian packages xvfb, xdotool)";
  }
  TempDir dir;
  const std::filesystem::path copc = testDataFile("laz/ellipsoid.copc.laz");
  const RgbaImage rgb = renderWith(dir, copc, "rgb");
  const RgbaImage intensity = renderWith(dir, copc, "intensity");
  const RgbaImage classification = renderWith(dir, copc, "classification");
  ASSERT_GT(cloudPixels(rgb), 15000u) << "the camera does not see the cloud";
  // Three different pictures, or the comparisons below prove nothing.
  EXPECT_LT(sameFraction(rgb, intensity), 0.8);
  EXPECT_LT(sameFraction(intensity, classification), 0.8);

  const auto shots = dir.path() / "shots";
  Display display(dir);
  ASSERT_FALSE(display.name().empty()) << "Xvfb did not start: " << readFile(dir / "xvfb.log");
  ViewerProcess viewer(dir, display.name(), viewerArgs(copc, shots), "viewer.log");
  ASSERT_TRUE(viewer.hasWindow()) << "no viewer window: " << viewer.log();
  EXPECT_TRUE(viewer.logged("parallax view: first picture after")) << viewer.log();
  viewer.key("g");  // hide the panel

  // The first load: positions and colour, not one intensity or classification layer.
  ASSERT_EQ(readLines(viewer.log()).size(), 1u) << viewer.log();
  const std::string first = readLines(viewer.log())[0];
  EXPECT_EQ(first.substr(0, first.find(';')), "x y z red green blue") << viewer.log();
  EXPECT_NE(first.find("not read: "), std::string::npos);
  EXPECT_NE(first.find(" intensity"), std::string::npos) << "intensity is among those not read";
  EXPECT_GT(sameFraction(viewer.settledScreenshot(shots, showing(rgb)), rgb), 0.98);

  // Picking reads the node whole: the point's intensity is reported though not drawn.
  viewer.ctrlClick(240, 180);
  EXPECT_TRUE(viewer.logged("parallax view: picked ")) << viewer.log();
  const std::string line = pickedLine(viewer.log());
  EXPECT_NE(line.find(" intensity="), std::string::npos) << line;
  EXPECT_NE(line.find(" gps_time="), std::string::npos) << line;

  viewer.key("c");  // elevation: positions only, nothing to read again
  viewer.key("c");  // intensity
  EXPECT_TRUE(viewer.logged("parallax view: colour intensity")) << viewer.log();
  EXPECT_GT(sameFraction(viewer.settledScreenshot(shots, showing(intensity)), intensity), 0.98)
      << viewer.log();
  std::vector<std::string> lines = readLines(viewer.log());
  ASSERT_EQ(lines.size(), 2u) << viewer.log();
  EXPECT_EQ(lines[1].substr(0, lines[1].find(';')), "x y z intensity");

  viewer.key("c");  // normal: the file has none, nothing to read
  viewer.key("c");  // classification
  EXPECT_TRUE(viewer.logged("parallax view: colour classification")) << viewer.log();
  EXPECT_GT(sameFraction(viewer.settledScreenshot(shots, showing(classification)), classification),
            0.98)
      << viewer.log();
  lines = readLines(viewer.log());
  ASSERT_EQ(lines.size(), 3u) << viewer.log();
  EXPECT_EQ(lines[2].substr(0, lines[2].find(';')), "x y z classification");
  EXPECT_EQ(viewer.quit(), 0) << viewer.log();
}

// The value the "read with A; read when asked for: B" line gives for `part` (0: A, 1: B).
std::string wholeFileRead(const std::string& log, int part) {
  const std::string prefix = "e7.laz read with ";
  const std::size_t at = log.find(prefix);
  if (at == std::string::npos) return "";
  const std::string line = log.substr(at + prefix.size(), log.find('\n', at) - at - prefix.size());
  const std::size_t split = line.find("; read when asked for: ");
  if (split == std::string::npos) return part == 0 ? line : "";
  return part == 0 ? line.substr(0, split) : line.substr(split + 23);
}

TEST(ViewerAttributes, AWholeLayeredLazReadsItsOtherLayersWhenAskedFor) {
  if (!onPath("Xvfb") || !onPath("xdotool")) {
    GTEST_SKIP() << "needs Xvfb and xdotool (Debian packages xvfb, xdotool)";
  }
  TempDir dir;
  // The same points as ellipsoid.copc.laz, as a plain layered LAZ (format 7, one chunk).
  const std::filesystem::path laz = dir / "e7.laz";
  const std::string convert = std::string(PARALLAX_EXECUTABLE) + " convert " +
                              testDataFile("laz/ellipsoid.laz").string() + " -o " + laz.string() +
                              " --point-format 7 --quiet";
  ASSERT_EQ(run(convert), 0) << convert;
  const RgbaImage rgb = renderWith(dir, laz, "rgb");
  const RgbaImage intensity = renderWith(dir, laz, "intensity");
  ASSERT_GT(cloudPixels(rgb), 15000u) << "the camera does not see the cloud";
  EXPECT_LT(sameFraction(rgb, intensity), 0.8);

  const auto shots = dir.path() / "shots";
  Display display(dir);
  ASSERT_FALSE(display.name().empty()) << "Xvfb did not start: " << readFile(dir / "xvfb.log");
  ViewerProcess viewer(dir, display.name(), viewerArgs(laz, shots), "viewer.log");
  ASSERT_TRUE(viewer.hasWindow()) << "no viewer window: " << viewer.log();
  EXPECT_TRUE(viewer.logged("parallax view: first picture after")) << viewer.log();
  viewer.key("g");  // hide the panel

  // The first read: positions, colour and classes; intensity and GPS time are left for later.
  EXPECT_EQ(wholeFileRead(viewer.log(), 0), "x y z red green blue classification") << viewer.log();
  const std::string unread = wholeFileRead(viewer.log(), 1);
  EXPECT_NE((" " + unread + " ").find(" intensity "), std::string::npos) << viewer.log();
  EXPECT_NE((" " + unread + " ").find(" gps_time "), std::string::npos) << viewer.log();
  EXPECT_GT(sameFraction(viewer.settledScreenshot(shots, showing(rgb)), rgb), 0.98);

  viewer.key("c");  // elevation: nothing to read
  viewer.key("c");  // intensity: its layer is read now, and drawn as `render` draws it
  EXPECT_TRUE(viewer.logged("parallax view: read later from e7.laz: intensity\n")) << viewer.log();
  EXPECT_GT(sameFraction(viewer.settledScreenshot(shots, showing(intensity)), intensity), 0.98)
      << viewer.log();

  // A pick reports every attribute: the rest is read then.
  viewer.ctrlClick(240, 180);
  EXPECT_TRUE(viewer.logged("parallax view: picked ")) << viewer.log();
  const std::string log = viewer.log();
  const std::size_t later = log.rfind("parallax view: read later from e7.laz: ");
  ASSERT_NE(later, std::string::npos) << log;
  EXPECT_NE(log.substr(later, log.find('\n', later) - later).find(" gps_time"), std::string::npos);
  const std::string line = pickedLine(log);
  EXPECT_NE(line.find(" gps_time="), std::string::npos) << line;
  EXPECT_NE(line.find(" intensity="), std::string::npos) << line;
  EXPECT_EQ(viewer.quit(), 0) << viewer.log();
}

}  // namespace
}  // namespace parallax::test
