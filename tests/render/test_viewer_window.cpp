// The viewer in a real window under Xvfb, driven with xdotool: it opens a file, draws the panel,
// turns the view on a mouse drag, writes screenshots on P (the picture, without the panel; Shift
// + P the window) and quits on Escape; in stereo, it falls back from quad-buffer (Xvfb has no
// stereo visual) to side by side with a message and no raw GLFW error, the panel collapsed, and
// the 3 key cycles the stereo modes. Level of detail: a Potree directory is shown and the , key
// lowers the point budget live; a file over the budget shows a sample, then switches to its
// octree once built in the background, and a second visit opens the cached octree at once. The
// first picture and the F key frame the cloud as it projects, beside the panel. Progressive
// refinement completes an octree's picture in parts; R cycles the rasterizers. The keys go to
// the 3D view from the start (Tab, W, 3); Esc closes the help before it quits; a failed open is
// shown in the middle of the window.
//
// Needs the Debian packages xvfb and xdotool; skipped (with the reason) where they are missing.
// Xvfb picks a free display itself (-displayfd), so parallel runs do not collide.
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <functional>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "render/camera.h"
#include "render/class_colors.h"
#include "render/image_file.h"
#include "render/view_extent.h"
#include "support/temp_dir.h"
#include "viewer_window_support.h"

namespace parallax::test {
namespace {

using namespace std::chrono_literals;

TEST(ViewerWindow, OpensDrawsThePanelTurnsOnDragAndTakesScreenshots) {
  if (!onPath("Xvfb") || !onPath("xdotool")) {
    GTEST_SKIP() << "needs Xvfb and xdotool (Debian packages xvfb, xdotool)";
  }
  TempDir dir;
  const auto cloud = dir.write("grid.ply", gridPly());
  const auto shots = dir.path() / "shots";
  std::filesystem::create_directories(shots);

  // Xvfb writes the display number it chose to the file given to -displayfd once it is ready.
  const auto display_file = dir / "display";
  const std::string xvfb_command =
      "exec Xvfb -displayfd 3 -screen 0 1024x768x24 -nolisten tcp 3>" + display_file.string();
  Child xvfb({"sh", "-c", xvfb_command}, {}, (dir / "xvfb.log").string());
  ASSERT_TRUE(xvfb.started());
  ASSERT_TRUE(waitFor([&] { return !readFile(display_file).empty(); }, 20s))
      << "Xvfb did not start: " << readFile(dir / "xvfb.log");
  const std::string display = ":" + std::to_string(std::stoi(readFile(display_file)));
  const std::string env = "DISPLAY=" + display + " ";

  Child viewer({PARALLAX_EXECUTABLE, "view", cloud.string(), "--width", "800", "--height", "480",
                "--screenshot-dir", shots.string(), "--background", "255,255,255", "--point-size",
                "4", "--no-vsync"},
               {"DISPLAY=" + display, "ASAN_OPTIONS=detect_leaks=0"},
               (dir / "viewer.log").string());
  ASSERT_TRUE(viewer.started());
  ASSERT_EQ(
      run(env + "timeout 60 xdotool search --sync --name Parallax > " + (dir / "window").string()),
      0)
      << "no viewer window: " << readFile(dir / "viewer.log");
  const std::string window = std::to_string(std::stol(readFile(dir / "window")));
  auto xdo = [&](const std::string& args) {
    return run(env + "xdotool " + args + " > /dev/null 2>&1");
  };
  int shot_count = 0;
  auto screenshot = [&](const std::string& key = "p") {
    const auto path = shots / ("parallax-screenshot-" + std::to_string(++shot_count) + ".png");
    EXPECT_EQ(xdo("key --window " + window + " " + key), 0);
    EXPECT_TRUE(waitFor([&] { return std::filesystem::exists(path); }, 30s))
        << "no screenshot " << path << ": " << readFile(dir / "viewer.log");
    return readPng(path);
  };
  // Screenshots until one equals the one before (the last input drawn, the panel at its size),
  // for at most 30 s: a wait on the picture itself, not a fixed time.
  auto settledScreenshot = [&] {
    const auto end = std::chrono::steady_clock::now() + 30s;
    RgbaImage last = screenshot();
    for (;;) {
      RgbaImage next = screenshot();
      if (next.pixels == last.pixels || std::chrono::steady_clock::now() >= end) return next;
      last = std::move(next);
    }
  };
  // The first picture first (on a loaded machine it can take seconds), then frames until the
  // picture settles (the panel has its size).
  EXPECT_TRUE(waitFor(
      [&] {
        return readFile(dir / "viewer.log").find("parallax view: first picture after") !=
               std::string::npos;
      },
      30s))
      << readFile(dir / "viewer.log");
  const RgbaImage before = settledScreenshot();

  // Drag to the right across the part of the window that the panel does not cover.
  // Each step in a frame of its own, waited on with a screenshot (P comes after the step's events
  // and its file is written by the frame that took them), never a fixed time.
  ASSERT_EQ(xdo("mousemove --window " + window + " 500 240 mousedown 1 mousemove --window " +
                window + " 560 260"),
            0);
  screenshot();
  ASSERT_EQ(xdo("mousemove --window " + window + " 640 280"), 0);
  screenshot();
  ASSERT_EQ(xdo("mouseup 1"), 0);
  const RgbaImage after = settledScreenshot();
  const RgbaImage window_shot = screenshot("shift+p");

  ASSERT_EQ(before.width, 800);
  ASSERT_EQ(before.height, 480);
  ASSERT_EQ(after.width, before.width);
  auto pixel = [](const RgbaImage& image, int x, int y) {
    const std::uint8_t* p = &image.pixels[(std::size_t(y) * image.width + x) * 4];
    return std::array<int, 3>{p[0], p[1], p[2]};
  };
  // P writes the picture alone: the panel (ImGui's dark window, at the top left over the white
  // background) is in Shift + P's picture of the window only. Each path is printed on stderr.
  EXPECT_EQ(pixel(before, 60, 60), (std::array<int, 3>{255, 255, 255})) << "a panel in the picture";
  const auto panel = pixel(window_shot, 60, 60);
  EXPECT_LT(panel[0] + panel[1] + panel[2], 3 * 80) << "no panel at the top left of the window";
  for (int n = 1; n <= shot_count; ++n) {
    const auto path = shots / ("parallax-screenshot-" + std::to_string(n) + ".png");
    EXPECT_NE(readFile(dir / "viewer.log").find("parallax view: screenshot: " + path.string()),
              std::string::npos)
        << readFile(dir / "viewer.log");
  }
  // The cloud is drawn, and the drag turned it: the part right of the panel changed.
  std::size_t cloud_pixels = 0, changed = 0;
  for (int y = 0; y < before.height; ++y) {
    for (int x = 400; x < before.width; ++x) {
      const auto a = pixel(before, x, y), b = pixel(after, x, y);
      if (a != std::array<int, 3>{255, 255, 255}) ++cloud_pixels;
      if (a != b) ++changed;
    }
  }
  EXPECT_GT(cloud_pixels, 500u) << "the cloud is not drawn";
  EXPECT_GT(changed, 500u) << "the view did not change on a mouse drag";

  // Not checked: xdotool fails on the key release when the viewer has already closed its window.
  xdo("key --window " + window + " Escape");
  EXPECT_EQ(viewer.wait(20s), 0) << "the viewer did not quit on Escape: "
                                 << readFile(dir / "viewer.log");
  // The drag's frames, summarised on the way out as the orbit benchmark does.
  EXPECT_NE(readFile(dir / "viewer.log").find("parallax view: frames while moving: median "),
            std::string::npos)
      << readFile(dir / "viewer.log");
}

// Where the cloud's pixels (not the background's colour) are: count, and the middle of their
// box (the default view centres the cloud's extent; its centroid depends on the perspective).
struct Coverage {
  std::size_t count = 0;
  double x = 0, y = 0;
};

Coverage coverage(const RgbaImage& image, int x0, int y0, int x1, int y1) {
  Coverage c;
  int low_x = x1, high_x = x0, low_y = y1, high_y = y0;
  for (int y = y0; y < y1; ++y) {
    for (int x = x0; x < x1; ++x) {
      const std::uint8_t* p = &image.pixels[(std::size_t(y) * image.width + x) * 4];
      if (!(p[0] | p[1] | p[2])) continue;
      ++c.count;
      low_x = std::min(low_x, x), high_x = std::max(high_x, x);
      low_y = std::min(low_y, y), high_y = std::max(high_y, y);
    }
  }
  if (c.count) c.x = 0.5 * (low_x + high_x + 1), c.y = 0.5 * (low_y + high_y + 1);
  return c;
}

TEST(ViewerWindow, QuadBufferFallsBackToSideBySideAndTheThreeKeyCyclesStereoModes) {
  if (!onPath("Xvfb") || !onPath("xdotool")) {
    GTEST_SKIP() << "needs Xvfb and xdotool (Debian packages xvfb, xdotool)";
  }
  TempDir dir;
  const auto cloud = dir.write("grid.ply", gridPly());
  const auto shots = dir.path() / "shots";
  std::filesystem::create_directories(shots);
  const auto display_file = dir / "display";
  Child xvfb(
      {"sh", "-c",
       "exec Xvfb -displayfd 3 -screen 0 1024x768x24 -nolisten tcp 3>" + display_file.string()},
      {}, (dir / "xvfb.log").string());
  ASSERT_TRUE(xvfb.started());
  ASSERT_TRUE(waitFor([&] { return !readFile(display_file).empty(); }, 20s))
      << "Xvfb did not start: " << readFile(dir / "xvfb.log");
  const std::string display = ":" + std::to_string(std::stoi(readFile(display_file)));
  const std::string env = "DISPLAY=" + display + " ";

  const auto log = dir / "viewer.log";
  Child viewer({PARALLAX_EXECUTABLE, "view", cloud.string(), "--width", "800", "--height", "400",
                "--screenshot-dir", shots.string(), "--point-size", "3", "--no-vsync", "--stereo",
                "quad-buffer"},
               {"DISPLAY=" + display, "ASAN_OPTIONS=detect_leaks=0"}, log.string());
  ASSERT_TRUE(viewer.started());
  ASSERT_EQ(
      run(env + "timeout 60 xdotool search --sync --name Parallax > " + (dir / "window").string()),
      0)
      << "no viewer window: " << readFile(log);
  const std::string window = std::to_string(std::stol(readFile(dir / "window")));
  auto xdo = [&](const std::string& args) {
    return run(env + "xdotool " + args + " > /dev/null 2>&1");
  };
  // Keys are taken in order: what follows a key waits on what it changes (a line of the log, a
  // screenshot), never a fixed time.
  auto key = [&](const std::string& name) {
    EXPECT_EQ(xdo("key --window " + window + " " + name), 0);
  };
  int shot_count = 0;
  auto screenshot = [&](const std::string& name = "p") {
    const auto path = shots / ("parallax-screenshot-" + std::to_string(++shot_count) + ".png");
    key(name);
    EXPECT_TRUE(waitFor([&] { return std::filesystem::exists(path); }, 30s))
        << "no screenshot " << path << ": " << readFile(log);
    return readPng(path);
  };
  auto settledScreenshot = [&] {
    const auto end = std::chrono::steady_clock::now() + 30s;
    RgbaImage last = screenshot();
    for (;;) {
      RgbaImage next = screenshot();
      if (next.pixels == last.pixels || std::chrono::steady_clock::now() >= end) return next;
      last = std::move(next);
    }
  };
  auto logged = [&](const std::string& text) {
    return waitFor([&] { return readFile(log).find(text) != std::string::npos; }, 10s);
  };

  // Xvfb offers no stereo visual: the viewer says so and shows side by side.
  EXPECT_TRUE(
      logged("quad-buffer stereo: this display offers no stereo (GL_STEREO) visual; "
             "showing sbs (side by side) instead"))
      << readFile(log);
  // The fallback is said in words; GLFW's own "format unavailable" is not printed first.
  EXPECT_EQ(readFile(log).find("GLFW error"), std::string::npos) << readFile(log);
  // In sbs the panel starts collapsed to its title bar: below it, the window is the picture.
  const RgbaImage picture = settledScreenshot();
  const RgbaImage window_shot = screenshot("shift+p");
  ASSERT_EQ(picture.pixels.size(), window_shot.pixels.size());
  std::size_t covered = 0;
  for (int y = 40; y < 400; ++y) {
    for (int x = 0; x < 400; ++x) {
      const std::size_t i = (std::size_t(y) * 800 + x) * 4;
      covered += std::memcmp(&picture.pixels[i], &window_shot.pixels[i], 3) != 0;
    }
  }
  EXPECT_EQ(covered, 0u) << "the panel covers the left eye";
  key("g");  // hide the panel
  const RgbaImage sbs = screenshot();
  ASSERT_EQ(sbs.width, 800);
  const Coverage left = coverage(sbs, 0, 0, 400, 400), right = coverage(sbs, 400, 0, 800, 400);
  EXPECT_GT(left.count, 500u) << "no left eye";
  EXPECT_GT(right.count, 500u) << "no right eye";
  EXPECT_NEAR(left.x, 200, 60);
  EXPECT_NEAR(right.x, 600, 60);

  key("3");
  EXPECT_TRUE(logged("stereo sbs-squeezed")) << readFile(log);
  key("3");
  EXPECT_TRUE(logged("stereo tb")) << readFile(log);
  const RgbaImage tb = screenshot();
  const Coverage top = coverage(tb, 0, 0, 800, 200), bottom = coverage(tb, 0, 200, 800, 400);
  EXPECT_GT(top.count, 500u) << "no left eye on top";
  EXPECT_GT(bottom.count, 500u) << "no right eye below";
  EXPECT_NEAR(top.y, 100, 40);
  EXPECT_NEAR(bottom.y, 300, 40);
  EXPECT_NEAR(top.x, 400, 60);

  key("3");
  EXPECT_TRUE(logged("stereo anaglyph")) << readFile(log);
  const RgbaImage anaglyph = screenshot();
  const Coverage whole = coverage(anaglyph, 0, 0, 800, 400);
  EXPECT_NEAR(whole.x, 400, 60) << "an anaglyph is one picture across the window";
  EXPECT_GT(whole.count, left.count);
  key("bracketright");
  EXPECT_TRUE(logged("stereo eye separation")) << readFile(log);
  // Through anaglyph-dubois and interlaced, past quad-buffer (not offered here), back to mono.
  key("3");
  key("3");
  key("3");
  EXPECT_TRUE(logged("stereo mono")) << readFile(log);
  EXPECT_EQ(readFile(log).find("stereo quad-buffer"), std::string::npos) << readFile(log);

  // Not checked: xdotool fails on the key release when the viewer has already closed its window.
  xdo("key --window " + window + " Escape");
  EXPECT_EQ(viewer.wait(20s), 0) << "the viewer did not quit on Escape: " << readFile(log);
}

// An Xvfb display for one test, started on a free display number.
// Pixels that are not the white background.
std::size_t cloudPixels(const RgbaImage& image) {
  std::size_t count = 0;
  for (std::size_t i = 0; i < image.pixels.size(); i += 4) {
    if (image.pixels[i] != 255 || image.pixels[i + 1] != 255 || image.pixels[i + 2] != 255) ++count;
  }
  return count;
}

// A 60 000-point generated scan converted to a Potree directory at `octree`; false on failure.
bool writeScanOctree(const TempDir& dir, const std::filesystem::path& octree) {
  const auto ply = dir / "scan.ply";
  return run(std::string(PARALLAX_EXECUTABLE) + " generate --points 60000 -o " + ply.string() +
             " > /dev/null 2>&1") == 0 &&
         run(std::string(PARALLAX_EXECUTABLE) + " convert -q " + ply.string() + " -o " +
             octree.string()) == 0;
}

TEST(ViewerWindow, ShowsAPotreeDirectoryAndTheCommaKeyLowersTheBudget) {
  if (!onPath("Xvfb") || !onPath("xdotool")) {
    GTEST_SKIP() << "needs Xvfb and xdotool (Debian packages xvfb, xdotool)";
  }
  TempDir dir;
  const auto octree = dir / "scan_octree";
  ASSERT_TRUE(writeScanOctree(dir, octree));
  const auto shots = dir.path() / "shots";
  std::filesystem::create_directories(shots);
  Display display(dir);
  ASSERT_FALSE(display.name().empty()) << "Xvfb did not start: " << readFile(dir / "xvfb.log");
  ViewerProcess viewer(
      dir, display.name(),
      {octree.string(), "--width", "480", "--height", "360", "--screenshot-dir", shots.string(),
       "--background", "255,255,255", "--point-size", "3", "--no-vsync", "--budget", "100000"},
      "viewer.log");
  ASSERT_TRUE(viewer.hasWindow()) << "no viewer window: " << viewer.log();
  EXPECT_TRUE(viewer.logged("opened the octree " + octree.string() + " (60000 points)"))
      << viewer.log();
  EXPECT_TRUE(viewer.logged("parallax view: first picture after")) << viewer.log();
  viewer.key("g");  // hide the panel
  const std::size_t full = cloudPixels(viewer.settledScreenshot(shots));
  EXPECT_GT(full, 3000u) << "the octree is not drawn";

  viewer.key("comma");
  viewer.key("comma");
  viewer.key("comma");
  EXPECT_TRUE(viewer.logged("point budget 12500")) << viewer.log();
  const std::size_t reduced = cloudPixels(viewer.settledScreenshot(shots));
  EXPECT_GT(reduced, 1000u) << "the cloud is gone at a budget of 12500";
  EXPECT_LT(reduced, full) << "a budget of 12500 draws as much as one of 100000";
  viewer.key("period");
  EXPECT_TRUE(viewer.logged("point budget 25000")) << viewer.log();
  EXPECT_EQ(viewer.quit(), 0) << "the viewer did not quit on Escape: " << viewer.log();
}

TEST(ViewerWindow, FileOverTheBudgetShowsASampleThenItsOctreeAndIsCachedForTheNextVisit) {
  if (!onPath("Xvfb") || !onPath("xdotool")) {
    GTEST_SKIP() << "needs Xvfb and xdotool (Debian packages xvfb, xdotool)";
  }
  TempDir dir;
  const auto cloud = dir.write("grid.ply", gridPly());  // 3600 points: large for a budget of 1000
  const auto shots = dir.path() / "shots", cache = dir.path() / "cache";
  std::filesystem::create_directories(shots);
  Display display(dir);
  ASSERT_FALSE(display.name().empty()) << "Xvfb did not start: " << readFile(dir / "xvfb.log");
  const std::vector<std::string> args = {
      cloud.string(), "--width",      "480",         "--height",     "360", "--screenshot-dir",
      shots.string(), "--background", "255,255,255", "--point-size", "4",   "--no-vsync",
      "--budget",     "1000",         "--cache-dir", cache.string()};
  {
    ViewerProcess viewer(dir, display.name(), args, "first.log");
    ASSERT_TRUE(viewer.hasWindow()) << "no viewer window: " << viewer.log();
    EXPECT_TRUE(viewer.logged("has 3600 points, over the budget of 1000: showing a sample of"))
        << viewer.log();
    EXPECT_TRUE(viewer.logged("switched to the level-of-detail octree in " + cache.string()))
        << viewer.log();
    viewer.key("g");
    EXPECT_GT(cloudPixels(viewer.settledScreenshot(shots)), 1000u) << "no cloud after the switch";
    EXPECT_EQ(viewer.quit(), 0) << viewer.log();
  }
  ViewerProcess again(dir, display.name(), args, "second.log");
  ASSERT_TRUE(again.hasWindow()) << "no viewer window: " << again.log();
  EXPECT_TRUE(again.logged("(3600 points) from its octree in " + cache.string())) << again.log();
  EXPECT_EQ(again.log().find("showing a sample"), std::string::npos) << again.log();
  EXPECT_EQ(again.quit(), 0) << again.log();
}

// The box around the pixels that are not the white background; x1 < 0 when there are none.
struct PixelBox {
  int x0 = 1 << 30, y0 = 1 << 30, x1 = -1, y1 = -1;
};

PixelBox cloudBox(const RgbaImage& image) {
  PixelBox box;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      const std::uint8_t* p = &image.pixels[(std::size_t(y) * image.width + x) * 4];
      if (p[0] == 255 && p[1] == 255 && p[2] == 255) continue;
      box.x0 = std::min(box.x0, x), box.x1 = std::max(box.x1, x);
      box.y0 = std::min(box.y0, y), box.y1 = std::max(box.y1, y);
    }
  }
  return box;
}

// What a fitted view looks like in the part [x_begin, width) of the window: nothing at its
// border, centred in it, one axis filled up to the margin (Camera::kFitMargin of the half-size
// each side), give or take the 2-pixel points.
void expectFramed(const PixelBox& box, int x_begin, int width, int height,
                  const std::string& what) {
  SCOPED_TRACE(what);
  ASSERT_GE(box.x1, 0) << "nothing drawn";
  EXPECT_GT(box.x0, x_begin);
  EXPECT_GT(box.y0, 0);
  EXPECT_LT(box.x1, width - 1);
  EXPECT_LT(box.y1, height - 1);
  EXPECT_LE(std::abs((box.x0 - x_begin) - (width - 1 - box.x1)), 3) << box.x0 << ".." << box.x1;
  EXPECT_LE(std::abs(box.y0 - (height - 1 - box.y1)), 3) << box.y0 << ".." << box.y1;
  const double fill = std::max(double(box.x1 - box.x0 + 1) / (width - x_begin),
                               double(box.y1 - box.y0 + 1) / height);
  EXPECT_GE(fill, 1.0 - Camera::kFitMargin - 3.0 / height);
  EXPECT_LE(fill, 1.0 - Camera::kFitMargin + 3.0 / height);
}

// The grid's box as the default camera fitted into [x_begin, width) draws it (CPU projection).
PixelBox projectedGrid(int x_begin, int width, int height) {
  ViewExtent extent;
  for (int j = 0; j < 60; ++j) {
    for (int i = 0; i < 60; ++i) {
      const double x = i / 59.0 - 0.5, y = j / 59.0 - 0.5;
      extent.points.emplace_back(x, y, 0.3 * (0.5 - x * x - y * y));
      extent.bounds.extend(x, y, 0.3 * (0.5 - x * x - y * y));
    }
  }
  const double aspect = double(width) / height;
  const Camera camera = defaultCameraFor(extent, aspect, 2.0 * x_begin / width - 1.0, 1.0);
  const glm::dmat4 to_clip =
      camera.projectionMatrix(aspect, camera.clipRange(extent.bounds)) * camera.viewMatrix();
  double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
  for (const glm::dvec3& p : extent.points) {
    const glm::dvec4 clip = to_clip * glm::dvec4(p, 1.0);
    const double px = (clip.x / clip.w + 1) * 0.5 * width;
    const double py = (1 - clip.y / clip.w) * 0.5 * height;
    x0 = std::min(x0, px), x1 = std::max(x1, px), y0 = std::min(y0, py), y1 = std::max(y1, py);
  }
  return {int(std::lround(x0)), int(std::lround(y0)), int(std::lround(x1)), int(std::lround(y1))};
}

// The panel's right edge in a picture of the window (Shift + P): on a row through its title bar
// (the cloud, framed right of the panel, leaves the top rows white), the rightmost pixel that
// is not the white background, plus one.
int panelRight(const RgbaImage& window) {
  const int y = 14;
  for (int x = window.width - 1; x >= 0; --x) {
    const std::uint8_t* p = &window.pixels[(std::size_t(y) * window.width + x) * 4];
    if (p[0] != 255 || p[1] != 255 || p[2] != 255) return x + 1;
  }
  return 0;
}

// The first picture and F frame the cloud in the part of the window the panel leaves free (the
// panel starts open at the top left); with the panel hidden, F frames it in the whole window.
TEST(ViewerWindow, FirstPictureAndTheFKeyFrameTheCloud) {
  if (!onPath("Xvfb") || !onPath("xdotool")) {
    GTEST_SKIP() << "needs Xvfb and xdotool (Debian packages xvfb, xdotool)";
  }
  TempDir dir;
  const auto cloud = dir.write("grid.ply", gridPly());
  const auto shots = dir.path() / "shots";
  std::filesystem::create_directories(shots);
  Display display(dir);
  ASSERT_FALSE(display.name().empty()) << "Xvfb did not start: " << readFile(dir / "xvfb.log");
  const int width = 800, height = 480;
  ViewerProcess viewer(dir, display.name(),
                       {cloud.string(), "--width", std::to_string(width), "--height",
                        std::to_string(height), "--screenshot-dir", shots.string(), "--background",
                        "255,255,255", "--point-size", "2", "--no-vsync"},
                       "viewer.log");
  ASSERT_TRUE(viewer.hasWindow()) << "no viewer window: " << viewer.log();
  EXPECT_TRUE(viewer.logged("parallax view: first picture after")) << viewer.log();
  const RgbaImage first = viewer.settledScreenshot(shots);  // the picture, without the panel
  ASSERT_EQ(first.width, width);
  const int panel = panelRight(viewer.windowShot(shots));
  ASSERT_GT(panel, 100) << "no panel";
  ASSERT_LT(panel, width / 2 + 20) << "the panel (or the cloud) reaches the top right";
  const PixelBox box = cloudBox(first);
  expectFramed(box, panel, width, height, "first picture, beside the panel");
  // The same box from the grid's points projected on the CPU with the default camera fitted
  // into the part right of the panel.
  const PixelBox expected = projectedGrid(panel, width, height);
  EXPECT_NEAR(box.x0, expected.x0, 2.0);
  EXPECT_NEAR(box.x1 + 1, expected.x1, 2.0);
  EXPECT_NEAR(box.y0, expected.y0, 2.0);
  EXPECT_NEAR(box.y1 + 1, expected.y1, 2.0);

  // Turned and zoomed in, then F: framed again from the new direction, beside the panel.
  viewer.drag(600, 240, 700, 300);
  viewer.scroll(3);
  const PixelBox turned = cloudBox(viewer.screenshot(shots));
  EXPECT_FALSE(turned.x0 > panel && turned.x1 < width - 1 && turned.y0 > 0 &&
               turned.y1 < height - 1)
      << "zoomed in, the cloud should reach past the free part";
  viewer.key("f");
  expectFramed(cloudBox(viewer.settledScreenshot(shots)), panel, width, height, "after F");

  // The panel hidden, F frames the cloud in the whole window.
  viewer.key("g");
  viewer.key("f");
  expectFramed(cloudBox(viewer.settledScreenshot(shots)), 0, width, height, "after G and F");
  EXPECT_EQ(viewer.quit(), 0) << "the viewer did not quit on Escape: " << viewer.log();
}

// The command line's filter reaches the viewer, whose panel takes over the first cloud's clip
// box rather than resetting it: a box around the whole cloud drawn inside keeps the picture,
// outside hides every point; a class the grid lacks (it has no classification: class 0) too.
TEST(ViewerWindow, CommandLineFiltersReachTheViewer) {
  if (!onPath("Xvfb") || !onPath("xdotool")) {
    GTEST_SKIP() << "needs Xvfb and xdotool (Debian packages xvfb, xdotool)";
  }
  TempDir dir;
  const auto cloud = dir.write("grid.ply", gridPly());
  Display display(dir);
  ASSERT_FALSE(display.name().empty()) << "Xvfb did not start: " << readFile(dir / "xvfb.log");
  const std::vector<std::string> box = {"--clip-box", "-1,-1,-1,1,1,1"};
  struct Case {
    std::vector<std::string> options;
    bool drawn;
  };
  // A square around the whole grid; the grid has no returns (1 of 1), no GPS time (0) and z
  // from 0 to 0.15.
  const std::string polygon = dir.write("square.txt", "-1 -1\n1 -1\n1 1\n-1 1\n").string();
  const std::vector<Case> cases = {{box, true},
                                   {{box[0], box[1], "--clip-mode", "outside"}, false},
                                   {{"--classes", "5"}, false},
                                   {{"--classes", "0-4"}, true},
                                   {{"--returns", "single", "--clip-polygon", polygon}, true},
                                   {{"--clip-polygon", polygon, "--clip-mode", "outside"}, false},
                                   {{"--elevation", "0.2,1"}, false},
                                   {{"--gps-time", "1,2"}, false},
                                   // A strip right of the grid; turned a quarter about its
                                   // centre (0.9, 0), it crosses the grid's middle.
                                   {{"--clip-box", "0.8,-1.2,-1,1,1.2,1"}, false},
                                   {{"--clip-box", "0.8,-1.2,-1,1,1.2,1,90"}, true}};
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const auto shots = dir.path() / ("shots" + std::to_string(i));
    std::filesystem::create_directories(shots);
    std::vector<std::string> args = {
        cloud.string(), "--width",      "480",         "--height",     "360", "--screenshot-dir",
        shots.string(), "--background", "255,255,255", "--point-size", "3",   "--no-vsync"};
    args.insert(args.end(), cases[i].options.begin(), cases[i].options.end());
    const std::string log = "viewer" + std::to_string(i) + ".log";
    ViewerProcess viewer(dir, display.name(), args, log);
    ASSERT_TRUE(viewer.hasWindow()) << "no viewer window: " << viewer.log();
    EXPECT_TRUE(viewer.logged("parallax view: first picture after")) << viewer.log();
    viewer.key("g");  // hide the panel
    const std::size_t pixels = cloudPixels(viewer.settledScreenshot(shots));
    if (cases[i].drawn) {
      EXPECT_GT(pixels, 1000u) << "case " << i;
    } else {
      EXPECT_EQ(pixels, 0u) << "case " << i;
    }
    EXPECT_EQ(viewer.quit(), 0) << viewer.log();
  }
}

// `view --color distance`: a scalar attribute through a ramp reaches the viewer's first
// picture; every pixel drawn is one of the ramp's colours for the grid's values, computed here
// (grey: round(255 t)).
TEST(ViewerWindow, ScalarAttributeThroughAGreyRamp) {
  if (!onPath("Xvfb") || !onPath("xdotool")) {
    GTEST_SKIP() << "needs Xvfb and xdotool (Debian packages xvfb, xdotool)";
  }
  TempDir dir;
  std::ostringstream ply;
  ply << "ply\nformat ascii 1.0\nelement vertex 900\nproperty float x\nproperty float y\n"
         "property float z\nproperty float distance\nend_header\n";
  for (int j = 0; j < 30; ++j) {
    for (int i = 0; i < 30; ++i)
      ply << i / 29.0 - 0.5 << ' ' << j / 29.0 - 0.5 << " 0 " << i << '\n';
  }
  const auto cloud = dir.write("distance.ply", ply.str());
  std::set<std::array<int, 3>> ramp;
  for (int i = 0; i < 30; ++i) {
    const int v = int(std::lround(255.0 * i / 29.0));
    ramp.insert({v, v, v});
  }
  const auto shots = dir.path() / "shots";
  std::filesystem::create_directories(shots);
  Display display(dir);
  ASSERT_FALSE(display.name().empty()) << "Xvfb did not start: " << readFile(dir / "xvfb.log");
  ViewerProcess viewer(
      dir, display.name(),
      {cloud.string(), "--width", "480", "--height", "360", "--screenshot-dir", shots.string(),
       "--background", "255,0,255", "--point-size", "3", "--no-vsync", "--color", "distance",
       "--color-ramp", "grey", "--color-range", "0,29"},
      "viewer.log");
  ASSERT_TRUE(viewer.hasWindow()) << "no viewer window: " << viewer.log();
  EXPECT_TRUE(viewer.logged("parallax view: first picture after")) << viewer.log();
  viewer.key("g");  // hide the panel
  const RgbaImage image = viewer.settledScreenshot(shots);
  std::set<std::array<int, 3>> seen;
  std::size_t off_ramp = 0;
  for (std::size_t i = 0; i < image.pixels.size(); i += 4) {
    const std::array<int, 3> c{image.pixels[i], image.pixels[i + 1], image.pixels[i + 2]};
    if (c == std::array<int, 3>{255, 0, 255}) continue;
    seen.insert(c);
    off_ramp += ramp.count(c) == 0;
  }
  EXPECT_EQ(off_ramp, 0u) << "pixels of colours the ramp does not make";
  EXPECT_GE(seen.size(), 25u) << "too few of the grid's 30 values seen";
  EXPECT_EQ(viewer.quit(), 0) << viewer.log();
}

// The panel's right edge (10 + its 400 pixels) and a little more.
constexpr int kRightOfPanel = 415;

// Pixels of the points right of the panel: all but the white background.
std::size_t pointPixelsRightOfPanel(const RgbaImage& image) {
  std::size_t count = 0;
  for (int y = 0; y < image.height; ++y) {
    for (int x = kRightOfPanel; x < image.width; ++x) {
      const std::uint8_t* p = &image.pixels[(std::size_t(y) * image.width + x) * 4];
      count += p[0] != 255 || p[1] != 255 || p[2] != 255;
    }
  }
  return count;
}

// The centre of the panel's legend swatch of `classification` (the square of its colour left
// of its checkbox, left of the panel's edge), or {-1, -1}.
std::array<int, 2> legendSwatch(const RgbaImage& image, int classification) {
  const std::array<float, 3> rgb = classColor(classification);
  std::array<int, 3> want{};
  for (std::size_t k = 0; k < 3; ++k) want[k] = int(rgb[k] * 255.0f + 0.5f);  // as ImGui rounds
  int x0 = image.width, x1 = -1, y0 = image.height, y1 = -1;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < std::min(kRightOfPanel, image.width); ++x) {
      const std::uint8_t* p = &image.pixels[(std::size_t(y) * image.width + x) * 4];
      if (p[0] == want[0] && p[1] == want[1] && p[2] == want[2]) {
        x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
      }
    }
  }
  // A swatch is a square of the frame's height (about 19 pixels).
  if (x1 < 0 || x1 - x0 < 8 || x1 - x0 > 40 || y1 - y0 < 8 || y1 - y0 > 40) return {-1, -1};
  return {(x0 + x1) / 2, (y0 + y1) / 2};
}

// Toggling a class in the panel: a click on the "6 building" checkbox hides the building half
// of the grid in the next pictures, a second click brings it back (the same picture).
TEST(ViewerWindow, ClickingAClassCheckboxInThePanelChangesThePicture) {
  if (!onPath("Xvfb") || !onPath("xdotool")) {
    GTEST_SKIP() << "needs Xvfb and xdotool (Debian packages xvfb, xdotool)";
  }
  TempDir dir;
  const auto cloud = dir.write("classified.ply", gridPly(true));
  const auto shots = dir.path() / "shots";
  std::filesystem::create_directories(shots);
  Display display(dir);
  ASSERT_FALSE(display.name().empty()) << "Xvfb did not start: " << readFile(dir / "xvfb.log");
  ViewerProcess viewer(
      dir, display.name(),
      {cloud.string(), "--width", "900", "--height", "700", "--screenshot-dir", shots.string(),
       "--background", "255,255,255", "--point-size", "3", "--no-vsync"},
      "viewer.log");
  ASSERT_TRUE(viewer.hasWindow()) << "no viewer window: " << viewer.log();
  EXPECT_TRUE(viewer.logged("parallax view: first picture after")) << viewer.log();
  // The filters are near the panel's end: scrolled to it (the panel is taller than the window).
  viewer.scrollDownAt(150, 300, 15);
  const RgbaImage before = viewer.windowShot(shots);  // the panel included
  const std::size_t all = pointPixelsRightOfPanel(before);
  ASSERT_GT(all, 2000u) << "the grid is not drawn";
  const std::array<int, 2> swatch = legendSwatch(before, 6);
  ASSERT_GE(swatch[0], 0) << "no legend swatch of class 6 in the panel";
  ASSERT_NE(legendSwatch(before, 2)[0], -1) << "no legend swatch of class 2 in the panel";
  // The checkbox is the next item on the line: the swatch's half width (about 10 pixels),
  // ImGui's item spacing (8) and the checkbox's half width (about 10) to its right.
  const int checkbox_x = swatch[0] + 10 + 8 + 10;
  viewer.click(checkbox_x, swatch[1]);
  const std::size_t without = pointPixelsRightOfPanel(viewer.settledScreenshot(
      shots, [&](const RgbaImage& image) { return pointPixelsRightOfPanel(image) < all; }));
  EXPECT_LT(without, all * 3 / 4) << "the building half is still drawn";
  EXPECT_GT(without, all / 10) << "more than the building half went";
  viewer.click(checkbox_x, swatch[1]);
  const RgbaImage again = viewer.settledScreenshot(
      shots, [&](const RgbaImage& image) { return pointPixelsRightOfPanel(image) == all; });
  EXPECT_EQ(pointPixelsRightOfPanel(again), all) << "the building half did not come back";
  EXPECT_EQ(viewer.quit(), 0) << viewer.log();
}

// Progressive refinement: with a frame budget far below what the octree takes to draw, the
// picture is drawn in several parts, and once complete it is the picture drawn in one frame.
// R cycles the rasterizers and says who draws.
TEST(ViewerWindow, ProgressiveRefinementCompletesThePictureAndTheRKeyCyclesRasterizers) {
  if (!onPath("Xvfb") || !onPath("xdotool")) {
    GTEST_SKIP() << "needs Xvfb and xdotool (Debian packages xvfb, xdotool)";
  }
  TempDir dir;
  const auto octree = dir / "scan_octree";
  ASSERT_TRUE(writeScanOctree(dir, octree));
  Display display(dir);
  ASSERT_FALSE(display.name().empty()) << "Xvfb did not start: " << readFile(dir / "xvfb.log");
  auto picture = [&](const std::string& budget_ms, const std::string& name) {
    const auto shots = dir.path() / name;
    std::filesystem::create_directories(shots);
    ViewerProcess viewer(dir, display.name(),
                         {octree.string(), "--width", "480", "--height", "360", "--screenshot-dir",
                          shots.string(), "--background", "255,255,255", "--point-size", "2",
                          "--no-vsync", "--rasterizer", "points", "--frame-budget", budget_ms},
                         name + ".log");
    EXPECT_TRUE(viewer.hasWindow()) << "no viewer window: " << viewer.log();
    if (!viewer.hasWindow()) return std::pair<RgbaImage, std::string>{};
    EXPECT_TRUE(viewer.logged("parallax view: first picture after")) << viewer.log();
    viewer.key("g");  // hide the panel
    // The refined picture is complete once the viewer says so; then it no longer changes.
    if (name == "refined") {
      EXPECT_TRUE(viewer.logged("first picture refined to completion")) << viewer.log();
    }
    RgbaImage image = viewer.settledScreenshot(shots);
    if (name == "refined") {
      viewer.key("r");
      EXPECT_TRUE(viewer.logged("rasterizer auto: the compute rasterizer draws")) << viewer.log();
      viewer.key("r");
      EXPECT_TRUE(viewer.logged("rasterizer compute: the compute rasterizer draws"))
          << viewer.log();
      viewer.key("r");
      EXPECT_TRUE(viewer.logged("rasterizer points: GL_POINTS draws")) << viewer.log();
    }
    EXPECT_EQ(viewer.quit(), 0) << "the viewer did not quit on Escape: " << viewer.log();
    return std::pair<RgbaImage, std::string>{std::move(image), viewer.log()};
  };
  const auto [whole, whole_log] = picture("0", "whole");
  const auto [refined, refined_log] = picture("0.2", "refined");
  EXPECT_EQ(whole_log.find("refined to completion"), std::string::npos) << whole_log;
  const std::string marker = "first picture refined to completion in ";
  const std::size_t at = refined_log.find(marker);
  ASSERT_NE(at, std::string::npos) << refined_log;
  EXPECT_GT(std::stoi(refined_log.substr(at + marker.size())), 2) << refined_log;
  // The picture's points are those of all its parts, more than its first part drew.
  const std::size_t points_at = refined_log.find(" parts (", at);
  ASSERT_NE(points_at, std::string::npos) << refined_log;
  const std::uint64_t picture_points = std::stoull(refined_log.substr(points_at + 8));
  const std::string first_marker = "first picture after ";
  const std::size_t first_at = refined_log.find(first_marker);
  ASSERT_NE(first_at, std::string::npos) << refined_log;
  const std::uint64_t first_part_points =
      std::stoull(refined_log.substr(refined_log.find(" s (", first_at) + 4));
  EXPECT_GT(picture_points, first_part_points) << refined_log;
  EXPECT_LE(picture_points, 60000u) << refined_log;
  ASSERT_EQ(whole.pixels.size(), refined.pixels.size());
  ASSERT_FALSE(whole.pixels.empty());
  EXPECT_GT(cloudPixels(whole), 3000u) << "the octree is not drawn";
  std::size_t differing = 0;
  for (std::size_t i = 0; i < whole.pixels.size(); i += 4) {
    differing += std::memcmp(&whole.pixels[i], &refined.pixels[i], 3) != 0;
  }
  // Points of one depth in two nodes may land in either order: a handful of pixels at most.
  EXPECT_LE(differing, whole.pixels.size() / 4 / 500)
      << differing << " pixels differ between the refined picture and the whole one";
}

// Ctrl + click picks the point under the cursor: the line on stderr names the same point, with
// the file's coordinates, that `parallax pick` gives for that pixel of the same picture.
TEST(ViewerWindow, CtrlClickPrintsThePickedPoint) {
  if (!onPath("Xvfb") || !onPath("xdotool")) {
    GTEST_SKIP() << "needs Xvfb and xdotool (Debian packages xvfb, xdotool)";
  }
  TempDir dir;
  const auto cloud = dir.write("grid.ply", gridPly());
  const std::vector<std::string> look = {"--width",      "640",   "--height", "400",
                                         "--point-size", "4",     "--eye",    "0.4,-1.6,1.2",
                                         "--target",     "0,0,0", "--fov",    "30"};
  // The pick the command line makes in the upper part of the picture (rows count from the top in
  // both), and where its point is drawn.
  std::string args = " pick " + cloud.string() + " --pixel 320,110 --json";
  for (const std::string& option : look) args += " " + option;
  ASSERT_EQ(run(std::string(PARALLAX_EXECUTABLE) + args + " > " + (dir / "pick.json").string()), 0);
  const nlohmann::json expected = nlohmann::json::parse(readFile(dir / "pick.json"));
  ASSERT_TRUE(expected.at("found").get<bool>()) << expected.dump();
  const int x = expected.at("point_pixel")[0], y = expected.at("point_pixel")[1];

  Display display(dir);
  ASSERT_FALSE(display.name().empty()) << "Xvfb did not start: " << readFile(dir / "xvfb.log");
  std::vector<std::string> view_args = {cloud.string(), "--no-vsync"};
  view_args.insert(view_args.end(), look.begin(), look.end());
  ViewerProcess viewer(dir, display.name(), view_args, "viewer.log");
  ASSERT_TRUE(viewer.hasWindow()) << "no viewer window: " << viewer.log();
  EXPECT_TRUE(viewer.logged("parallax view: first picture after")) << viewer.log();
  viewer.key("g");  // the panel off the picture
  viewer.ctrlClick(x, y);
  ASSERT_TRUE(viewer.logged("parallax view: picked ")) << viewer.log();
  const std::string log = viewer.log();
  std::istringstream line(log.substr(log.find("parallax view: picked ") + 22));
  double px = 0, py = 0, pz = 0;
  line >> px >> py >> pz;
  EXPECT_EQ(px, expected.at("point").at("x").get<double>()) << log;
  EXPECT_EQ(py, expected.at("point").at("y").get<double>()) << log;
  EXPECT_EQ(pz, expected.at("point").at("z").get<double>()) << log;
  const std::string red = "red=" + std::to_string(expected.at("point").at("red").get<int>()) + " ";
  EXPECT_NE(log.find(red), std::string::npos) << log;
  EXPECT_EQ(viewer.quit(), 0) << "the viewer did not quit on Escape: " << viewer.log();
}

// The keyboard belongs to the 3D view from the start: Tab enters fly mode (the panel's fields are
// no Tab stops), W held then flies, 3 cycles the stereo mode; Esc closes an open list of the
// panel and the help before it quits.
TEST(ViewerWindow, KeysGoToTheViewAndEscapeClosesAListAndTheHelpFirst) {
  if (!onPath("Xvfb") || !onPath("xdotool")) {
    GTEST_SKIP() << "needs Xvfb and xdotool (Debian packages xvfb, xdotool)";
  }
  TempDir dir;
  const auto cloud = dir.write("grid.ply", gridPly());
  const auto shots = dir.path() / "shots";
  std::filesystem::create_directories(shots);
  Display display(dir);
  ASSERT_FALSE(display.name().empty()) << "Xvfb did not start: " << readFile(dir / "xvfb.log");
  ViewerProcess viewer(
      dir, display.name(),
      {cloud.string(), "--width", "640", "--height", "400", "--screenshot-dir", shots.string(),
       "--background", "255,255,255", "--point-size", "3", "--no-vsync"},
      "viewer.log");
  ASSERT_TRUE(viewer.hasWindow()) << "no viewer window: " << viewer.log();
  EXPECT_TRUE(viewer.logged("parallax view: first picture after")) << viewer.log();
  const RgbaImage before = viewer.screenshot(shots);
  // A click on the rasterizer's combo (the panel's first, at the same place in every window)
  // opens its list; Esc closes the list, not the viewer. (Before the camera moves: the panel's
  // headline is then one line shorter.)
  viewer.click(120, 137);
  const RgbaImage list_open = viewer.windowShot(shots);
  viewer.key("Escape");
  const RgbaImage list_closed = viewer.windowShot(shots);
  ASSERT_EQ(list_closed.width, 640) << "the viewer quit on the Escape that closed the list";
  std::size_t list_pixels = 0;
  for (int y = 150; y < 210; ++y) {
    for (int x = 20; x < 240; ++x) {
      const std::size_t i = (std::size_t(y) * 640 + x) * 4;
      list_pixels += std::memcmp(&list_open.pixels[i], &list_closed.pixels[i], 3) != 0;
    }
  }
  EXPECT_GT(list_pixels, 200u) << "no list opened and closed below the combo";

  // The panel clicked, Tab still goes to the view.
  viewer.key("Tab");
  EXPECT_TRUE(viewer.logged("parallax view: fly mode on")) << viewer.log();
  viewer.hold("w", 1.5);
  const RgbaImage flown = viewer.screenshot(shots);
  ASSERT_EQ(flown.pixels.size(), before.pixels.size());
  // Flown: the picture moved (a field with the keyboard would have taken the W instead).
  std::size_t changed = 0;
  for (std::size_t i = 0; i < flown.pixels.size(); i += 4) {
    changed += std::memcmp(&flown.pixels[i], &before.pixels[i], 3) != 0;
  }
  EXPECT_GT(changed, cloudPixels(before) / 4) << "W did not fly";
  viewer.key("3");
  EXPECT_TRUE(viewer.logged("parallax view: stereo sbs")) << viewer.log();

  // H opens the help; Esc closes it and the viewer goes on (it still answers P), the next quits.
  viewer.key("h");
  viewer.key("Escape");
  const RgbaImage after_help = viewer.windowShot(shots);
  EXPECT_EQ(after_help.width, 640) << "the viewer quit on the Escape that closed the help";
  EXPECT_EQ(viewer.quit(), 0) << "the viewer did not quit on the second Escape: " << viewer.log();
}

// A file that cannot be opened is said where the eye is: in the middle of the empty window (in
// the error colour), not only at the bottom of the panel.
TEST(ViewerWindow, AFailedOpenIsShownInTheMiddleOfTheWindow) {
  if (!onPath("Xvfb") || !onPath("xdotool")) {
    GTEST_SKIP() << "needs Xvfb and xdotool (Debian packages xvfb, xdotool)";
  }
  TempDir dir;
  const auto shots = dir.path() / "shots";
  std::filesystem::create_directories(shots);
  Display display(dir);
  ASSERT_FALSE(display.name().empty()) << "Xvfb did not start: " << readFile(dir / "xvfb.log");
  const auto missing = dir / "no-such-cloud.ply";
  ViewerProcess viewer(dir, display.name(),
                       {missing.string(), "--width", "800", "--height", "480", "--screenshot-dir",
                        shots.string(), "--no-vsync"},
                       "viewer.log");
  ASSERT_TRUE(viewer.hasWindow()) << "no viewer window: " << viewer.log();
  EXPECT_TRUE(viewer.logged("parallax view: cannot open " + missing.string())) << viewer.log();
  viewer.key("g");  // the panel hidden: what is left in the middle is the message
  const RgbaImage window = viewer.windowShot(shots);
  ASSERT_EQ(window.width, 800);
  // Reddish text (the error colour, 255, 89, 89) in the middle third of the window.
  std::size_t red = 0;
  for (int y = window.height / 3; y < 2 * window.height / 3; ++y) {
    for (int x = window.width / 4; x < 3 * window.width / 4; ++x) {
      const std::uint8_t* p = &window.pixels[(std::size_t(y) * window.width + x) * 4];
      red += p[0] > 180 && p[1] < 130 && p[2] < 130;
    }
  }
  EXPECT_GT(red, 100u) << "no error text in the middle of the window";
  EXPECT_EQ(viewer.quit(), 0) << viewer.log();
}

}  // namespace
}  // namespace parallax::test
