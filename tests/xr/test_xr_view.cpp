// `parallax view --xr` end to end: the real Khronos loader loads the project's test runtime
// (XR_RUNTIME_JSON, tests/xr/runtime) under the core validation layer; the runtime reports the
// configured eyes and writes every submitted view as a PNG, which is checked against an
// independent CPU projection of the points (the stage mapping of issue 24, the eyes' XrFovf and
// XrPosef), headless on llvmpipe.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "../render/viewer_window_support.h"
#include "render/image_file.h"
#include "support/run_parallax.h"
#include "support/temp_dir.h"

namespace parallax {
namespace {

using test::quoted;
using test::runParallax;
using test::TempDir;

struct TestPoint {
  glm::dvec3 file;  // file coordinates (z up)
  std::uint8_t r, g, b;
};

struct Eye {
  double left, right, up, down;  // XrFovf angles
  glm::dvec3 position;           // stage
  glm::dquat orientation;        // stage, (w, x, y, z)
};

// UTM-size coordinates: float could not hold them to the centimetre.
const glm::dvec3 kOrigin{512345.25, 5412345.75, 312.5};

// A grid of points in front of the eyes (stage -z is file +y), each with its own colour.
std::vector<TestPoint> gridPoints() {
  std::vector<TestPoint> points;
  int n = 0;
  for (int iy = 0; iy < 3; ++iy) {
    for (int iz = 0; iz < 5; ++iz) {
      for (int ix = 0; ix < 6; ++ix, ++n) {
        const glm::dvec3 p = kOrigin + glm::dvec3(-2.5 + ix * 1.0 + 0.13 * iz, 3.0 + iy * 2.5,
                                                  0.2 + iz * 0.75 + 0.07 * ix);
        points.push_back({p, std::uint8_t(40 + n * 2), std::uint8_t(250 - n * 2),
                          std::uint8_t(60 + (n * 37) % 190)});
      }
    }
  }
  return points;
}

void writePly(const std::filesystem::path& path, const std::vector<TestPoint>& points) {
  std::ofstream out(path);
  out << "ply\nformat ascii 1.0\nelement vertex " << points.size()
      << "\nproperty double x\nproperty double y\nproperty double z\n"
         "property uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n";
  out.precision(17);
  for (const auto& p : points) {
    out << p.file.x << ' ' << p.file.y << ' ' << p.file.z << ' ' << int(p.r) << ' ' << int(p.g)
        << ' ' << int(p.b) << '\n';
  }
}

void writeConfig(const std::filesystem::path& path, const Eye (&eyes)[2], int width, int height,
                 int frames, const std::filesystem::path& output,
                 const nlohmann::json& controllers = nullptr) {
  nlohmann::json views = nlohmann::json::array();
  for (const Eye& e : eyes) {
    views.push_back(
        {{"fov", {{"left", e.left}, {"right", e.right}, {"up", e.up}, {"down", e.down}}},
         {"pose",
          {{"position", {e.position.x, e.position.y, e.position.z}},
           {"orientation",
            {e.orientation.x, e.orientation.y, e.orientation.z, e.orientation.w}}}}});
  }
  nlohmann::json config{{"views", views},
                        {"width", width},
                        {"height", height},
                        {"frames", frames},
                        {"output", output.string()}};
  if (!controllers.is_null()) config["controllers"] = controllers;
  std::ofstream(path) << config.dump();
}

// Where the point lands in the eye's picture, x right and y down from the top-left corner
// (pixels, continuous), written from the issue's definitions alone: stage = ((X-Ox)S, (Z-Oz)S,
// -(Y-Oy)S), eye space = the inverse of the eye's pose, the picture spans tan(left)..tan(right)
// and tan(down)..tan(up) at unit depth. False when the point is behind the eye.
// `moved` is what the controllers did to the world: stage position before -> after.
using StageMove = std::function<glm::dvec3(const glm::dvec3&)>;
bool project(const TestPoint& p, const Eye& eye, double scale, int width, int height,
             glm::dvec2& pixel, const StageMove& moved) {
  const glm::dvec3 d = p.file - kOrigin;
  const glm::dvec3 stage = moved(glm::dvec3(d.x * scale, d.z * scale, -d.y * scale));
  const glm::dvec3 local = glm::conjugate(eye.orientation) * (stage - eye.position);
  if (local.z >= 0) return false;
  const double tx = local.x / -local.z, ty = local.y / -local.z;
  const double tl = std::tan(eye.left), tr = std::tan(eye.right);
  const double tu = std::tan(eye.up), td = std::tan(eye.down);
  pixel.x = (tx - tl) / (tr - tl) * width;
  pixel.y = (tu - ty) / (tu - td) * height;
  return true;
}

struct Lit {
  int x, y;
  std::uint8_t r, g, b;
};
std::vector<Lit> litPixels(const RgbaImage& image) {
  std::vector<Lit> lit;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      const std::uint8_t* px = &image.pixels[(std::size_t(y) * image.width + x) * 4];
      if (px[0] || px[1] || px[2]) lit.push_back({x, y, px[0], px[1], px[2]});
    }
  }
  return lit;
}

class XrViewTest : public ::testing::Test {
 protected:
  void SetUp() override {
    setenv("XR_RUNTIME_JSON", PARALLAX_XR_TEST_RUNTIME, 1);
    // Headless (EGL) unless a test opens a display: with DISPLAY, view --xr opens the mirror.
    unsetenv("DISPLAY");
    unsetenv("XR_ENABLE_API_LAYERS");
    // The headless tests are not under the core validation layer: Debian's build of it (1.0.20)
    // rejects XrGraphicsBindingEGLMNDX in XrSessionCreateInfo's next chain ("Invalid
    // structure(s) in next chain", VUID-XrSessionCreateInfo-next-next) although
    // XR_MNDX_egl_enable is enabled: it was built without XR_USE_PLATFORM_EGL. The tests under
    // Xvfb below use the GLX binding (the mirror window's context) and run under the layer.
    setenv("PARALLAX_XR_TEST", (dir_ / "headset.json").c_str(), 1);
    points_ = gridPoints();
    writePly(dir_ / "grid.ply", points_);
  }

  // Runs view --xr.
  test::RunResult run(const Eye (&eyes)[2], int width, int height, int frames,
                      const std::string& extra = "", const nlohmann::json& controllers = nullptr) {
    writeConfig(dir_ / "headset.json", eyes, width, height, frames, dir_ / "out", controllers);
    const auto result = runParallax(
        dir_, "view " + quoted((dir_ / "grid.ply").string()) + " --xr --point-size 1 --xr-origin " +
                  std::to_string(kOrigin.x) + "," + std::to_string(kOrigin.y) + "," +
                  std::to_string(kOrigin.z) + " " + extra);
    return result;
  }

  // Every point in the picture is drawn in its colour within a pixel of where the CPU puts it,
  // and every lit pixel is such a point.
  void expectProjection(
      const Eye& eye, const RgbaImage& image, double scale, int* inside_count,
      const StageMove& moved = [](const glm::dvec3& s) { return s; }) {
    const auto lit = litPixels(image);
    struct Projected {
      const TestPoint* point;
      glm::dvec2 px;
      double depth;
    };
    std::vector<Projected> projected;
    for (const auto& p : points_) {
      glm::dvec2 px;
      if (project(p, eye, scale, image.width, image.height, px, moved)) {
        projected.push_back({&p, px, glm::length(p.file - kOrigin)});
      }
    }
    const auto near = [](const Lit& l, const glm::dvec2& px) {
      return std::abs(l.x + 0.5 - px.x) <= 1.0 && std::abs(l.y + 0.5 - px.y) <= 1.0;
    };
    int inside = 0;
    for (const auto& q : projected) {
      const TestPoint& p = *q.point;
      const glm::dvec2 px = q.px;
      if (px.x < 1 || px.y < 1 || px.x > image.width - 1 || px.y > image.height - 1) continue;
      ++inside;
      bool found = false, covered = false;
      for (const Lit& l : lit) found |= near(l, px) && l.r == p.r && l.g == p.g && l.b == p.b;
      // Another point drawn over it: two points within a pixel and a half of each other.
      for (const auto& other : projected) {
        covered |= other.point != q.point && glm::length(other.px - px) < 1.5;
      }
      EXPECT_TRUE(found || covered) << "point of colour " << int(p.r) << "," << int(p.g) << ","
                                    << int(p.b) << " expected near pixel " << px.x << "," << px.y;
    }
    for (const Lit& l : lit) {
      bool explained = false;
      for (const auto& q : projected) {
        explained |= near(l, q.px) && l.r == q.point->r && l.g == q.point->g && l.b == q.point->b;
      }
      EXPECT_TRUE(explained) << "lit pixel " << l.x << "," << l.y << " where no point projects";
    }
    *inside_count = inside;
  }

  TempDir dir_;
  std::vector<TestPoint> points_;
};

Eye straightEye(double x) {
  return {-0.7, 0.7, 0.6, -0.6, {x, 1.6, 0.0}, glm::dquat(1, 0, 0, 0)};
}

TEST_F(XrViewTest, EyesEqualACpuProjectionWithAsymmetricFovsAndARotatedHead) {
  // Asymmetric fields of view (each eye wider on its outer side, as headsets' are) and a head
  // turned 12 degrees left and rolled 5 degrees.
  const glm::dquat head = glm::angleAxis(glm::radians(12.0), glm::dvec3(0, 1, 0)) *
                          glm::angleAxis(glm::radians(5.0), glm::dvec3(0, 0, 1));
  const glm::dvec3 centre(0.1, 1.7, 0.4);
  const Eye eyes[2] = {{-0.85, 0.62, 0.55, -0.72, centre + head * glm::dvec3(-0.032, 0, 0), head},
                       {-0.62, 0.85, 0.55, -0.72, centre + head * glm::dvec3(0.032, 0, 0), head}};
  const int width = 160, height = 120;
  const auto result = run(eyes, width, height, 2);
  ASSERT_EQ(result.exit_code, 0) << result.err;
  for (int frame = 0; frame < 2; ++frame) {
    for (int v = 0; v < 2; ++v) {
      const auto png =
          dir_ / "out" / ("frame_" + std::to_string(frame) + "_view_" + std::to_string(v) + ".png");
      ASSERT_TRUE(std::filesystem::exists(png)) << png;
      const RgbaImage image = readPng(png);
      ASSERT_EQ(image.width, width);
      ASSERT_EQ(image.height, height);
      int inside = 0;
      expectProjection(eyes[v], image, 1.0, &inside);
      EXPECT_GT(inside, 40) << "the scene should fill most of the view";
    }
  }
}

TEST_F(XrViewTest, ScaleMapsFileUnitsToStageMetres) {
  // At --xr-scale 0.5 the grid (3..8 m away in the file) stands 1.5..4 m away; drawn by GL_POINTS
  // here, by the compute rasterizer (the default on llvmpipe) elsewhere.
  const Eye eyes[2] = {straightEye(-0.03), straightEye(0.03)};
  const auto result = run(eyes, 128, 96, 1, "--xr-scale 0.5 --rasterizer points");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  for (int v = 0; v < 2; ++v) {
    int inside = 0;
    expectProjection(eyes[v],
                     readPng(dir_ / "out" / ("frame_0_view_" + std::to_string(v) + ".png")), 0.5,
                     &inside);
    EXPECT_GT(inside, 20);
  }
}

TEST_F(XrViewTest, ANearPointIsFurtherLeftInTheRightEye) {
  // Read off the pictures alone: the right eye sees every point at a finite distance shifted to
  // the left of where the left eye sees it (crossed the other way, the user sees depth inverted).
  const Eye eyes[2] = {straightEye(-0.032), straightEye(0.032)};
  const auto result = run(eyes, 200, 150, 1);
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const auto left = litPixels(readPng(dir_ / "out" / "frame_0_view_0.png"));
  const auto right = litPixels(readPng(dir_ / "out" / "frame_0_view_1.png"));
  int pairs = 0, shifted = 0;
  for (const Lit& l : left) {
    for (const Lit& r : right) {
      if (l.r == r.r && l.g == r.g && l.b == r.b) {
        ++pairs;
        // The farthest points (8 m) shift by less than a pixel here: never to the right.
        EXPECT_LE(r.x, l.x) << "colour " << int(l.r) << "," << int(l.g) << "," << int(l.b);
        shifted += r.x < l.x;
        EXPECT_LE(std::abs(r.y - l.y), 1) << "no vertical disparity";
      }
    }
  }
  EXPECT_GT(pairs, 30);
  EXPECT_GT(shifted, 20);
}

TEST_F(XrViewTest, TheSessionRunsTheConfiguredFramesThenEnds) {
  const Eye eyes[2] = {straightEye(-0.032), straightEye(0.032)};
  const auto result = run(eyes, 32, 24, 3);
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(result.err.find("3 frames of 2 x 32x24 drawn"), std::string::npos) << result.err;
  for (int f = 0; f < 3; ++f) {
    const auto json_path = dir_ / "out" / ("frame_" + std::to_string(f) + ".json");
    ASSERT_TRUE(std::filesystem::exists(json_path)) << json_path;
    const auto doc = nlohmann::json::parse(test::readText(json_path));
    ASSERT_EQ(doc["layers"].size(), 1u);
    const auto& views = doc["layers"][0]["views"];
    ASSERT_EQ(views.size(), 2u);
    for (int v = 0; v < 2; ++v) {
      // What the application submitted is what it was given: the located fov and pose.
      EXPECT_FLOAT_EQ(views[v]["fov"]["left"].get<float>(), -0.7f);
      EXPECT_FLOAT_EQ(views[v]["fov"]["up"].get<float>(), 0.6f);
      EXPECT_FLOAT_EQ(views[v]["pose"]["position"][0].get<float>(), v == 0 ? -0.032f : 0.032f);
      EXPECT_EQ(views[v]["image_rect"]["width"], 32);
      EXPECT_EQ(views[v]["image_rect"]["x"], v * 32);
    }
  }
  EXPECT_FALSE(std::filesystem::exists(dir_ / "out" / "frame_3.json"));
}

TEST_F(XrViewTest, TakesViewsLookDefaultsAdaptiveRoundPoints) {
  // Without --point-size, --size-mode or --shape, view (the window and --xr alike) sizes round
  // points to the local spacing: the grid's points (1 m apart, 3 to 8 m away) cover many pixels
  // each, where --point-size 1 (render's look) lights about one.
  const Eye eyes[2] = {straightEye(-0.032), straightEye(0.032)};
  writeConfig(dir_ / "headset.json", eyes, 160, 120, 1, dir_ / "out");
  const std::string origin = " --xr-origin " + std::to_string(kOrigin.x) + "," +
                             std::to_string(kOrigin.y) + "," + std::to_string(kOrigin.z);
  const std::string input = "view " + quoted((dir_ / "grid.ply").string()) + " --xr" + origin;
  auto result = runParallax(dir_, input + " --point-size 1");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const auto one_pixel = litPixels(readPng(dir_ / "out" / "frame_0_view_0.png")).size();
  result = runParallax(dir_, input);
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const auto adaptive = litPixels(readPng(dir_ / "out" / "frame_0_view_0.png")).size();
  EXPECT_GT(one_pixel, 40u);
  EXPECT_GT(adaptive, 4 * one_pixel) << one_pixel << " pixels at 1 px, " << adaptive << " adaptive";
}

// --- controllers (the test runtime's scripted "controllers", xr/locomotion.h's rules) ----------

nlohmann::json poseJson(const glm::dvec3& p, const glm::dquat& q) {
  return {{"position", {p.x, p.y, p.z}}, {"orientation", {q.x, q.y, q.z, q.w}}};
}

// Hands held behind the head and pointing backwards: their lasers stay out of the eyes' view, so
// every lit pixel is still a point.
const glm::dquat kBackwards = glm::angleAxis(glm::radians(180.0), glm::dvec3(0, 1, 0));
nlohmann::json handJson(const glm::dvec3& grip, const nlohmann::json& inputs,
                        const glm::dquat& aim = kBackwards) {
  return {{"grip", poseJson(grip, aim)}, {"inputs", inputs}};
}

// Ry(a) v: a turn about the stage's vertical, counter-clockwise seen from above.
glm::dvec3 turnY(const glm::dvec3& v, double a) {
  return {std::cos(a) * v.x + std::sin(a) * v.z, v.y, -std::sin(a) * v.x + std::cos(a) * v.z};
}

struct Placement {
  glm::dvec3 origin{0.0};
  double scale = 0, yaw = 0;
};
// The placement `view --xr` reports at the end ("origin X,Y,Z, scale S, yaw A").
Placement reportedPlacement(const std::string& err) {
  Placement p;
  const auto at = err.find("origin ");
  EXPECT_NE(at, std::string::npos) << err;
  if (at == std::string::npos) return p;
  EXPECT_EQ(std::sscanf(err.c_str() + at, "origin %lf,%lf,%lf, scale %lf, yaw %lf", &p.origin.x,
                        &p.origin.y, &p.origin.z, &p.scale, &p.yaw),
            5)
      << err;
  return p;
}
// A file point's stage position under a reported placement: the issue's mapping, then the yaw.
glm::dvec3 stageOf(const Placement& p, const glm::dvec3& file) {
  const glm::dvec3 d = file - p.origin;
  return turnY({d.x * p.scale, d.z * p.scale, -d.y * p.scale}, p.yaw);
}

constexpr double kFramePeriod = 0.011111111;  // the test runtime's 90 Hz, in seconds

TEST_F(XrViewTest, GrabbingWithOneHandMovesTheWorldWithTheHand) {
  const Eye eyes[2] = {straightEye(-0.032), straightEye(0.032)};
  const glm::dvec3 g0(0.2, 1.1, 0.3), d(0.5, -0.25, -1.0);
  const nlohmann::json controllers{
      {"profile", "/interaction_profiles/oculus/touch_controller"},
      {"frames",
       {{{"frame", 0}, {"right", handJson(g0, {{"squeeze/value", 1.0}})}},
        {{"frame", 1}, {"right", handJson(g0 + d, {{"squeeze/value", 0.9}})}},
        {{"frame", 2}, {"right", handJson(g0 + d, {{"squeeze/value", 0.0}})}}}}};
  const auto result = run(eyes, 128, 96, 3, "", controllers);
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const auto moved = [&](const glm::dvec3& s) { return s + d; };
  for (int v = 0; v < 2; ++v) {
    int inside = 0;
    expectProjection(eyes[v],
                     readPng(dir_ / "out" / ("frame_2_view_" + std::to_string(v) + ".png")), 1.0,
                     &inside, moved);
    EXPECT_GT(inside, 20);
  }
  const Placement p = reportedPlacement(result.err);
  EXPECT_NEAR(p.scale, 1.0, 1e-12);
  EXPECT_EQ(p.yaw, 0.0);
  for (const auto& point : points_) {
    const glm::dvec3 expected = stageOf({kOrigin, 1.0, 0.0}, point.file) + d;
    EXPECT_NEAR(glm::length(stageOf(p, point.file) - expected), 0.0, 1e-6);
  }
}

TEST_F(XrViewTest, TwoHandsScaleAndTurnTheWorldAboutTheirMidpoint) {
  const Eye eyes[2] = {straightEye(-0.032), straightEye(0.032)};
  const glm::dvec3 m0(0.0, 1.2, 0.4), m(0.1, 1.25, 0.2);
  const double angle = glm::radians(15.0);
  const glm::dvec3 half = turnY({0.3, 0.0, 0.0}, angle);  // 1.5 times the first span
  const nlohmann::json squeeze{{"squeeze/value", 1.0}};
  const nlohmann::json controllers{{"profile", "/interaction_profiles/valve/index_controller"},
                                   {"frames",
                                    {{{"frame", 0},
                                      {"left", handJson(m0 - glm::dvec3(0.2, 0, 0), squeeze)},
                                      {"right", handJson(m0 + glm::dvec3(0.2, 0, 0), squeeze)}},
                                     {{"frame", 1},
                                      {"left", handJson(m - half, squeeze)},
                                      {"right", handJson(m + half, squeeze)}}}}};
  const auto result = run(eyes, 128, 96, 2, "", controllers);
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const auto moved = [&](const glm::dvec3& s) { return turnY(s - m0, angle) * 1.5 + m; };
  for (int v = 0; v < 2; ++v) {
    int inside = 0;
    expectProjection(eyes[v],
                     readPng(dir_ / "out" / ("frame_1_view_" + std::to_string(v) + ".png")), 1.0,
                     &inside, moved);
    EXPECT_GT(inside, 15);
  }
  const Placement p = reportedPlacement(result.err);
  EXPECT_NEAR(p.scale, 1.5, 1e-6);
  EXPECT_NEAR(p.yaw, angle, 1e-6);
  for (const auto& point : points_) {
    const glm::dvec3 expected = moved(stageOf({kOrigin, 1.0, 0.0}, point.file));
    EXPECT_NEAR(glm::length(stageOf(p, point.file) - expected), 0.0, 1e-5);
  }
}

TEST_F(XrViewTest, SnapTurnAboutTheHeadThenFlyForward) {
  // Wide eyes, so that the grid stays in view after the turn.
  Eye eyes[2] = {straightEye(-0.032), straightEye(0.032)};
  for (Eye& e : eyes) e.left = -1.2, e.right = 1.2;
  const glm::dvec3 head(0.0, 1.6, 0.0);
  const glm::dvec3 right_hand(0.2, 1.0, 0.3), left_hand(-0.2, 1.0, 0.3);
  const nlohmann::json controllers{
      {"profile", "/interaction_profiles/oculus/touch_controller"},
      {"frames",
       {{{"frame", 0}, {"right", handJson(right_hand, nlohmann::json::object())}},
        {{"frame", 1}, {"right", handJson(right_hand, {{"thumbstick", {1.0, 0.0}}})}},
        // Held past the first frame: one snap per push.
        {{"frame", 2},
         {"right", handJson(right_hand, {{"thumbstick", {0.95, 0.0}}})},
         // The left hand aims backwards: pulling its stick back flies towards -z.
         {"left", handJson(left_hand, {{"thumbstick", {0.0, -1.0}}})}}}}};
  const auto result = run(eyes, 160, 96, 4, "", controllers);
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const double snap = glm::radians(30.0);
  // Frames 2 and 3 fly at 2 m/s for one display period each.
  const glm::dvec3 flown(0.0, 0.0, 2.0 * 2.0 * kFramePeriod);
  const auto moved = [&](const glm::dvec3& s) { return turnY(s - head, snap) + head + flown; };
  for (int v = 0; v < 2; ++v) {
    int inside = 0;
    expectProjection(eyes[v],
                     readPng(dir_ / "out" / ("frame_3_view_" + std::to_string(v) + ".png")), 1.0,
                     &inside, moved);
    EXPECT_GT(inside, 15);
  }
  const Placement p = reportedPlacement(result.err);
  EXPECT_NEAR(p.yaw, snap, 1e-12);
  for (const auto& point : points_) {
    const glm::dvec3 expected = moved(stageOf({kOrigin, 1.0, 0.0}, point.file));
    EXPECT_NEAR(glm::length(stageOf(p, point.file) - expected), 0.0, 1e-5);
  }
}

TEST_F(XrViewTest, TheVignetteHidesTheEdgesOnlyWhileFlying) {
  Eye eyes[2] = {straightEye(-0.032), straightEye(0.032)};
  for (Eye& e : eyes) e.left = -1.0, e.right = 1.0, e.up = 0.9, e.down = -0.9;
  const glm::dvec3 left_hand(-0.2, 1.0, 0.3);
  const nlohmann::json controllers{
      {"profile", "/interaction_profiles/oculus/touch_controller"},
      {"frames",
       {{{"frame", 0}, {"left", handJson(left_hand, nlohmann::json::object())}},
        {{"frame", 1}, {"left", handJson(left_hand, {{"thumbstick", {0.0, -1.0}}})}}}}};
  const int width = 160, height = 120;
  const auto result = run(eyes, width, height, 2, "--xr-vignette", controllers);
  ASSERT_EQ(result.exit_code, 0) << result.err;
  // Lit pixels by their tangent's distance from the eye's forward direction.
  const auto count = [&](int frame, double from, double to) {
    int n = 0;
    const Eye& e = eyes[0];
    for (const Lit& l :
         litPixels(readPng(dir_ / "out" / ("frame_" + std::to_string(frame) + "_view_0.png")))) {
      const double tx =
          std::tan(e.left) + (l.x + 0.5) / width * (std::tan(e.right) - std::tan(e.left));
      const double ty = std::tan(e.up) - (l.y + 0.5) / height * (std::tan(e.up) - std::tan(e.down));
      const double r = std::hypot(tx, ty);
      n += r >= from && r < to;
    }
    return n;
  };
  EXPECT_GT(count(0, 0.85, 100.0), 5) << "standing still: the edges are shown";
  EXPECT_EQ(count(1, 0.85, 100.0), 0) << "flying: the edges are black";
  EXPECT_GT(count(1, 0.0, 0.45), 5) << "flying: the centre is still shown";
}

// The orientation that turns -z (an aim's pointing direction) towards `direction`.
glm::dquat aimingAt(const glm::dvec3& direction) {
  const glm::dvec3 from(0, 0, -1), to = glm::normalize(direction);
  const glm::dvec3 axis = glm::cross(from, to);
  return glm::angleAxis(std::acos(glm::dot(from, to)), glm::normalize(axis));
}

// The hand that points the laser: below the eyes' view, so that its laser rises into it.
const glm::dvec3 kLaserHand(0.15, 1.3, -0.2);

// A controller at kLaserHand aiming at `p` (its file coordinates through the default stage
// mapping, stage = (x, z, -y) from kOrigin), with `inputs`.
nlohmann::json handAimingAt(const glm::dvec3& file, const nlohmann::json& inputs) {
  const glm::dvec3 d = file - kOrigin;
  const glm::dvec3 stage(d.x, d.z, -d.y);
  nlohmann::json hand{{"grip", poseJson(kLaserHand, glm::dquat(1, 0, 0, 0))},
                      {"aim", poseJson(kLaserHand, aimingAt(stage - kLaserHand))}};
  if (!inputs.is_null()) hand["inputs"] = inputs;
  return hand;
}

// One frame of a controller script: `side` ("left" or "right") aiming at `p` with `inputs`.
nlohmann::json frameAimingAt(int frame, const char* side, const TestPoint& p,
                             const nlohmann::json& inputs) {
  return {{"frame", frame}, {side, handAimingAt(p.file, inputs)}};
}

// One hand's script: at(frame, p, inputs) is a frame of `side` aiming at `p` with `inputs`.
auto handScript(const char* side) {
  return [side](int frame, const TestPoint& p, const nlohmann::json& inputs) {
    return frameAimingAt(frame, side, p, inputs);
  };
}

TEST_F(XrViewTest, TheLaserPicksThePointItAimsAtAndMeasuresADistance) {
  const Eye eyes[2] = {straightEye(-0.032), straightEye(0.032)};
  const TestPoint& a = points_[7];
  const TestPoint& b = points_[52];
  const auto aim = [](const TestPoint& p, bool click) {
    return handAimingAt(p.file, {{"select/click", click}});
  };
  const nlohmann::json controllers{{"profile", "/interaction_profiles/khr/simple_controller"},
                                   {"frames",
                                    {{{"frame", 0}, {"right", aim(a, false)}},
                                     {{"frame", 1}, {"right", aim(a, true)}},
                                     {{"frame", 2}, {"right", aim(b, false)}},
                                     {{"frame", 3}, {"right", aim(b, true)}}}}};
  const auto result = run(eyes, 128, 96, 4, "", controllers);
  ASSERT_EQ(result.exit_code, 0) << result.err;
  std::vector<glm::dvec3> picks;
  for (std::size_t at = result.err.find("laser pick "); at != std::string::npos;
       at = result.err.find("laser pick ", at + 1)) {
    glm::dvec3 p;
    ASSERT_EQ(std::sscanf(result.err.c_str() + at, "laser pick %lf,%lf,%lf", &p.x, &p.y, &p.z), 3);
    picks.push_back(p);
  }
  ASSERT_EQ(picks.size(), 2u) << result.err;
  // The file's values as the cloud stores them (quantized to its scale: well under a millimetre).
  EXPECT_LT(glm::length(picks[0] - a.file), 1e-3) << result.err;
  EXPECT_LT(glm::length(picks[1] - b.file), 1e-3) << result.err;
  const auto at = result.err.find("distance ");
  ASSERT_NE(at, std::string::npos) << result.err;
  double distance = 0;
  ASSERT_EQ(std::sscanf(result.err.c_str() + at, "distance %lf", &distance), 1);
  EXPECT_NEAR(distance, glm::length(a.file - b.file), 2e-3);
}

// The text pixels of the overlay's labels in a picture (x right, y down): white glyphs over
// their dark box, grey where a glyph's edge is blended with the box. No point of the grid is grey.
struct TextBox {
  int count = 0;
  int x0 = 1 << 30, y0 = 1 << 30, x1 = -1, y1 = -1;
};
TextBox textPixels(const RgbaImage& image) {
  TextBox box;
  for (const Lit& l : litPixels(image)) {
    if (l.r != l.g || l.g != l.b || l.r < 96) continue;
    ++box.count;
    box.x0 = std::min(box.x0, l.x);
    box.y0 = std::min(box.y0, l.y);
    box.x1 = std::max(box.x1, l.x);
    box.y1 = std::max(box.y1, l.y);
  }
  return box;
}

// The tool button (B) cycles distance -> height -> area and closes an area; the trigger's picks
// make a height and an area whose printed values are the test's own arithmetic on the picked
// points, and the height's label is drawn where its anchor projects in each eye.
TEST_F(XrViewTest, TheToolButtonChoosesHeightAndAreaWhosePicksAreMeasured) {
  const Eye eyes[2] = {straightEye(-0.032), straightEye(0.032)};
  const TestPoint& a = points_[7];
  const TestPoint& b = points_[52];
  const TestPoint& c = points_[26];
  // The area's other points: not a and b, the height's vertices (a press on one grabs it).
  const TestPoint& d = points_[8];
  const TestPoint& e = points_[53];
  const auto at = handScript("right");
  const nlohmann::json none = nlohmann::json::object();
  const nlohmann::json pull{{"trigger/value", 1.0}}, button{{"b/click", true}};
  const nlohmann::json controllers{
      {"profile", "/interaction_profiles/oculus/touch_controller"},
      {"frames",
       {at(0, a, none), at(1, a, pull),  // a distance's first point...
        at(2, a, button),                // ...dropped: the height tool
        at(3, a, none), at(4, a, pull), at(5, b, none), at(6, b, pull),  // a height
        at(7, b, button),                                                // the area tool
        at(8, d, none), at(9, d, pull), at(10, e, none), at(11, e, pull), at(12, c, none),
        at(13, c, pull), at(14, c, button),  // an area, closed by the button
        at(15, c, none)}}};
  const auto result = run(eyes, 320, 240, 16, "", controllers);
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const std::string& err = result.err;
  const auto tool_height = err.find("tool height"), tool_area = err.find("tool area");
  ASSERT_NE(tool_height, std::string::npos) << err;
  ASSERT_NE(tool_area, std::string::npos) << err;
  EXPECT_LT(tool_height, tool_area);
  EXPECT_EQ(err.find("--xr: distance "), std::string::npos) << "the dropped distance was finished";

  std::vector<glm::dvec3> picks;
  for (auto p = err.find("laser pick "); p != std::string::npos;
       p = err.find("laser pick ", p + 1)) {
    glm::dvec3 q;
    ASSERT_EQ(std::sscanf(err.c_str() + p, "laser pick %lf,%lf,%lf", &q.x, &q.y, &q.z), 3);
    picks.push_back(q);
  }
  ASSERT_EQ(picks.size(), 6u) << err;
  const TestPoint* aimed[6] = {&a, &a, &b, &d, &e, &c};
  for (int i = 0; i < 6; ++i) EXPECT_LT(glm::length(picks[i] - aimed[i]->file), 1e-3) << i;

  // The height: z1 - z0, the horizontal and the 3D distance of the picks (six decimals printed).
  double dz = 0, horizontal = 0, distance = 0;
  const auto height_at = err.find("height difference ");
  ASSERT_NE(height_at, std::string::npos) << err;
  ASSERT_EQ(std::sscanf(err.c_str() + height_at,
                        "height difference %lf m, horizontal %lf m, distance %lf m", &dz,
                        &horizontal, &distance),
            3)
      << err;
  const glm::dvec3 h0 = picks[1], h1 = picks[2];
  EXPECT_NEAR(dz, h1.z - h0.z, 1e-6);
  EXPECT_NEAR(horizontal, std::hypot(h1.x - h0.x, h1.y - h0.y), 1e-6);
  EXPECT_NEAR(distance, glm::length(h1 - h0), 1e-6);
  EXPECT_NEAR(dz, b.file.z - a.file.z, 2e-3);

  // The area of the triangle of the last three picks: half the cross product's length, and on
  // the ground half the cross product's z.
  double area_3d = 0, area_ground = 0, perimeter = 0;
  const auto area_at = err.find("area 3D ");
  ASSERT_NE(area_at, std::string::npos) << err;
  ASSERT_EQ(std::sscanf(err.c_str() + area_at, "area 3D %lf m², projected %lf m², perimeter %lf m",
                        &area_3d, &area_ground, &perimeter),
            3)
      << err;
  const glm::dvec3 t0 = picks[3], t1 = picks[4], t2 = picks[5];
  const glm::dvec3 cross = glm::cross(t1 - t0, t2 - t0);
  EXPECT_NEAR(area_3d, 0.5 * glm::length(cross), 1e-6);
  EXPECT_NEAR(area_ground, 0.5 * std::abs(cross.z), 1e-6);
  EXPECT_NEAR(perimeter, glm::length(t1 - t0) + glm::length(t2 - t1) + glm::length(t0 - t2), 1e-6);
  EXPECT_GT(area_3d, 0.5);  // a real triangle, not three picks of one point

  // Frame 7 shows the finished height alone, its label "dz ..." at the midpoint of its ends:
  // the label's text starts a few pixels right of and above where that point projects in each
  // eye, so its disparity is the point's.
  const TestPoint mid{0.5 * (h0 + h1), 0, 0, 0};
  double left_x[2] = {0, 0};
  for (int v = 0; v < 2; ++v) {
    const RgbaImage image = readPng(dir_ / "out" / ("frame_7_view_" + std::to_string(v) + ".png"));
    glm::dvec2 anchor;
    ASSERT_TRUE(project(mid, eyes[v], 1.0, image.width, image.height, anchor,
                        [](const glm::dvec3& s) { return s; }));
    const TextBox text = textPixels(image);
    ASSERT_GT(text.count, 10) << "view " << v << ": no label drawn";
    EXPECT_GE(text.x0, anchor.x) << "view " << v;
    EXPECT_LE(text.x0, anchor.x + 12) << "view " << v;
    EXPECT_LE(text.y1, anchor.y) << "view " << v;
    EXPECT_GE(text.y0, anchor.y - 30) << "view " << v;
    EXPECT_GT(text.x1 - text.x0, 30) << "view " << v << ": \"dz 1.23 m\" is wider";
    left_x[v] = text.x0;
  }
  glm::dvec2 p0, p1;
  ASSERT_TRUE(project(mid, eyes[0], 1.0, 320, 240, p0, [](const glm::dvec3& s) { return s; }));
  ASSERT_TRUE(project(mid, eyes[1], 1.0, 320, 240, p1, [](const glm::dvec3& s) { return s; }));
  EXPECT_NEAR(left_x[0] - left_x[1], p0.x - p1.x, 1.5) << "the label's disparity";
  EXPECT_GT(p0.x - p1.x, 1.0) << "a near label sits further left in the right eye";
}

// The grey text pixels inside [x0, x1] x [y0, y1].
TextBox textPixelsIn(const RgbaImage& image, double x0, double y0, double x1, double y1) {
  TextBox box;
  for (const Lit& l : litPixels(image)) {
    if (l.r != l.g || l.g != l.b || l.r < 96 || l.x < x0 || l.x > x1 || l.y < y0 || l.y > y1) {
      continue;
    }
    ++box.count;
    box.x0 = std::min(box.x0, l.x);
    box.y0 = std::min(box.y0, l.y);
    box.x1 = std::max(box.x1, l.x);
    box.y1 = std::max(box.y1, l.y);
  }
  return box;
}

// The "laser pick X,Y,Z" lines, in order.
std::vector<glm::dvec3> laserPicks(const std::string& err) {
  std::vector<glm::dvec3> picks;
  for (auto p = err.find("laser pick "); p != std::string::npos;
       p = err.find("laser pick ", p + 1)) {
    glm::dvec3 q;
    if (std::sscanf(err.c_str() + p, "laser pick %lf,%lf,%lf", &q.x, &q.y, &q.z) == 3) {
      picks.push_back(q);
    }
  }
  return picks;
}

// The measurement file's "measurements", read as plain JSON: kind, points, width (0 if none).
struct SavedMeasurement {
  std::string kind;
  std::vector<glm::dvec3> points;
  double width = 0;
};
std::vector<SavedMeasurement> savedMeasurements(const std::filesystem::path& file) {
  const nlohmann::json doc = nlohmann::json::parse(test::readFile(file));
  EXPECT_EQ(doc.at("format"), "parallax-measurements");
  std::vector<SavedMeasurement> out;
  for (const nlohmann::json& m : doc.at("measurements")) {
    SavedMeasurement saved;
    saved.kind = m.at("kind").get<std::string>();
    for (const nlohmann::json& p : m.at("points")) {
      saved.points.push_back({p.at(0).get<double>(), p.at(1).get<double>(), p.at(2).get<double>()});
    }
    if (m.contains("width")) saved.width = m.at("width").get<double>();
    out.push_back(std::move(saved));
  }
  return out;
}

// The tool button goes on past the area to the angle, the profile and the point tools (the
// window's order); their printed values are the test's own arithmetic on the picks: the angle at
// the middle pick, the section line's length and the points of the grid in its corridor, the
// point's coordinates. The angle's label and the profile's summary label are drawn where their
// anchors project in each eye, and --measurements FILE (not there before) holds the three
// measurements when the session ends.
TEST_F(XrViewTest, AngleProfileAndPointToolsMeasureThePicksAndAreSaved) {
  const Eye eyes[2] = {straightEye(-0.032), straightEye(0.032)};
  const TestPoint& a = points_[7];
  const TestPoint& b = points_[52];
  const TestPoint& c = points_[26];
  const auto at = handScript("right");
  // The profile's and the point's: not the angle's vertices (a press on one grabs it).
  const TestPoint& d = points_[8];
  const TestPoint& e = points_[53];
  const TestPoint& f = points_[27];
  const nlohmann::json none = nlohmann::json::object();
  const nlohmann::json pull{{"trigger/value", 1.0}}, button{{"b/click", true}};
  // A short press acts at its release: height at frame 2, area at 4, angle at 6.
  const nlohmann::json controllers{
      {"profile", "/interaction_profiles/oculus/touch_controller"},
      {"frames", {at(0, a, none),    at(1, a, button), at(2, a, none),  at(3, a, button),
                  at(4, a, none),    at(5, a, button), at(6, a, none),  at(7, a, pull),
                  at(8, b, none),    at(9, b, pull),   at(10, c, none), at(11, c, pull),  // angle
                  at(12, c, button), at(13, d, none),                    // the profile tool
                  at(14, d, pull),   at(15, e, none),  at(16, e, pull),  // a profile d -> e
                  at(17, c, button), at(18, f, none),                    // the point tool
                  at(19, f, pull),   at(20, f, none)}}};
  const std::filesystem::path file = dir_ / "headset-measurements.json";
  ASSERT_FALSE(std::filesystem::exists(file));
  const auto result =
      run(eyes, 320, 240, 21, "--profile-width 1.5 --measurements " + quoted(file.string()),
          controllers);
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const std::string& err = result.err;
  const auto tool_angle = err.find("tool angle"), tool_profile = err.find("tool profile"),
             tool_point = err.find("tool point");
  ASSERT_NE(tool_angle, std::string::npos) << err;
  ASSERT_NE(tool_profile, std::string::npos) << err;
  ASSERT_NE(tool_point, std::string::npos) << err;
  EXPECT_LT(tool_angle, tool_profile);
  EXPECT_LT(tool_profile, tool_point);

  const std::vector<glm::dvec3> picks = laserPicks(err);
  ASSERT_EQ(picks.size(), 6u) << err;
  const TestPoint* aimed[6] = {&a, &b, &c, &d, &e, &f};
  for (int i = 0; i < 6; ++i) EXPECT_LT(glm::length(picks[i] - aimed[i]->file), 1e-3) << i;

  // The angle at the second pick: atan2(|u x v|, u . v) in degrees, six decimals printed.
  double angle = 0;
  const auto angle_at = err.find("--xr: angle ");
  ASSERT_NE(angle_at, std::string::npos) << err;
  ASSERT_EQ(std::sscanf(err.c_str() + angle_at, "--xr: angle %lf degrees (3 points)", &angle), 1);
  const glm::dvec3 ray0 = picks[0] - picks[1], ray1 = picks[2] - picks[1];
  EXPECT_NEAR(angle,
              glm::degrees(std::atan2(glm::length(glm::cross(ray0, ray1)), glm::dot(ray0, ray1))),
              1e-6);
  EXPECT_GT(angle, 5.0);

  // The profile: the section line's 3D length, the corridor's width, and the points of the grid
  // whose horizontal distance to the line is at most 0.75 with their foot on it.
  double length = 0, width = 0;
  const auto profile_at = err.find("--xr: profile ");
  ASSERT_NE(profile_at, std::string::npos) << err;
  ASSERT_EQ(std::sscanf(err.c_str() + profile_at, "--xr: profile %lf m long, %lf m wide (2 points)",
                        &length, &width),
            2)
      << err;
  EXPECT_NEAR(length, glm::length(picks[4] - picks[3]), 1e-6);
  EXPECT_EQ(width, 1.5);
  const glm::dvec2 p0(picks[3]), p1(picks[4]);
  const glm::dvec2 along = p1 - p0;
  std::size_t inside = 0;
  for (const TestPoint& p : points_) {
    // The line's ends are points of the cloud as it holds them (the picks: within a float's
    // rounding of the file's values); every other point is 0.016 or more off the corridor's edges.
    glm::dvec3 held = p.file;
    for (const glm::dvec3& end : {picks[3], picks[4]}) {
      if (glm::length(p.file - end) < 1e-3) held = end;
    }
    const glm::dvec2 q = glm::dvec2(held) - p0;
    const double t = glm::dot(q, along) / glm::dot(along, along);
    const double off = std::abs(q.x * along.y - q.y * along.x) / glm::length(along);
    if (t >= 0 && t <= 1 && off <= 0.75) ++inside;
  }
  EXPECT_GE(inside, 10u);  // (8 in a corridor of 1, 28 in one of 3: the width counts)
  std::size_t listed = 0;
  const auto summary_at = err.find("profile of measurement 2: ");
  ASSERT_NE(summary_at, std::string::npos) << err;
  ASSERT_EQ(std::sscanf(err.c_str() + summary_at, "profile of measurement 2: %zu points", &listed),
            1);
  EXPECT_EQ(listed, inside);

  // The point: its coordinates, six decimals.
  glm::dvec3 point;
  const auto point_at = err.find("--xr: point ");
  ASSERT_NE(point_at, std::string::npos) << err;
  ASSERT_EQ(
      std::sscanf(err.c_str() + point_at, "--xr: point %lf %lf %lf", &point.x, &point.y, &point.z),
      3);
  EXPECT_LT(glm::length(point - picks[5]), 1e-6);

  // Frame 12 shows the angle alone, its label at the vertex; frame 17 the profile's summary
  // ("14 points, heights ...") at the section line's start, where no other label is.
  const auto expectLabelAt = [&](int frame, const glm::dvec3& anchor_file, int least_width) {
    for (int v = 0; v < 2; ++v) {
      const RgbaImage image =
          readPng(dir_ / "out" /
                  ("frame_" + std::to_string(frame) + "_view_" + std::to_string(v) + ".png"));
      glm::dvec2 anchor;
      ASSERT_TRUE(project({anchor_file, 0, 0, 0}, eyes[v], 1.0, image.width, image.height, anchor,
                          [](const glm::dvec3& s) { return s; }));
      const TextBox text =
          textPixelsIn(image, anchor.x - 20, anchor.y - 40, anchor.x + 200, anchor.y + 20);
      ASSERT_GT(text.count, 10) << "frame " << frame << " view " << v << ": no label drawn";
      EXPECT_GE(text.x0, anchor.x) << "frame " << frame << " view " << v;
      EXPECT_LE(text.x0, anchor.x + 12) << "frame " << frame << " view " << v;
      EXPECT_LE(text.y1, anchor.y) << "frame " << frame << " view " << v;
      EXPECT_GE(text.y0, anchor.y - 30) << "frame " << frame << " view " << v;
      EXPECT_GT(text.x1 - text.x0, least_width) << "frame " << frame << " view " << v;
    }
  };
  expectLabelAt(12, picks[1], 15);  // "12.3°"
  expectLabelAt(17, picks[3], 60);  // "14 points, heights 0.27 to 3.48 m"

  // The file, read back as JSON: the three measurements, the same doubles.
  ASSERT_TRUE(std::filesystem::exists(file)) << err;
  const std::vector<SavedMeasurement> saved = savedMeasurements(file);
  ASSERT_EQ(saved.size(), 3u);
  EXPECT_EQ(saved[0].kind, "angle");
  EXPECT_EQ(saved[0].points, (std::vector<glm::dvec3>{picks[0], picks[1], picks[2]}));
  EXPECT_EQ(saved[1].kind, "profile");
  EXPECT_EQ(saved[1].points, (std::vector<glm::dvec3>{picks[3], picks[4]}));
  EXPECT_EQ(saved[1].width, 1.5);
  EXPECT_EQ(saved[2].kind, "point");
  EXPECT_EQ(saved[2].points, std::vector<glm::dvec3>{picks[5]});
  EXPECT_NE(err.find("3 measurements saved to "), std::string::npos) << err;
}

// The profile's plot on a panel (xr/profile_panel.h), written out here from its rule: above the
// middle of the section line, its bottom 0.05 D above the line's highest end, 0.5 D wide, as high
// as the picture's 640 x 400 make it, facing the head's horizontal direction (D: from the head to
// the line's middle). The picture's layout (measure/profile_plot_image.h): data area columns
// 150..619, rows 48..335; each point of the corridor a 5 x 5 orange dot at its distance along the
// line (0 .. the line's horizontal length) and height (lowest .. highest); a dark background
// (20, 20, 24). Corners: bottom-left, bottom-right, top-right, top-left (file coordinates).
std::array<glm::dvec3, 4> expectedPanel(const glm::dvec3& start, const glm::dvec3& end,
                                        const glm::dvec3& head) {
  const glm::dvec3 middle = 0.5 * (start + end);
  const double distance = glm::length(head - middle);
  const glm::dvec2 facing = glm::normalize(glm::dvec2(head) - glm::dvec2(middle));
  const glm::dvec3 right(-facing.y, facing.x, 0);  // right of someone looking along -facing
  const double width = 0.5 * distance, height = width * 400.0 / 640.0;
  const glm::dvec3 bottom(middle.x, middle.y, std::max(start.z, end.z) + 0.05 * distance);
  const glm::dvec3 up(0, 0, height);
  return {bottom - 0.5 * width * right, bottom + 0.5 * width * right,
          bottom + 0.5 * width * right + up, bottom - 0.5 * width * right + up};
}

// The file position of the picture's pixel centre (column, row; the top row first) on the panel.
glm::dvec3 onPanel(const std::array<glm::dvec3, 4>& c, double column, double row) {
  const double u = (column + 0.5) / 640.0, v = (row + 0.5) / 400.0;
  return c[0] + u * (c[1] - c[0]) + (1.0 - v) * (c[3] - c[0]);
}

// Eyes 6.4 cm apart at 1.6 m, looking 25 degrees up at where the profile's panel stands (its
// corners at tangents -0.19..0.31 across, -0.14..0.14 up): at 480 x 256 pixels, the panel's 640
// columns cover about 365 of theirs.
constexpr double kPanelPitch = 0.436;
Eye panelEye(double x) {
  return {-0.26, 0.36,          0.17,
          -0.17, {x, 1.6, 0.0}, glm::angleAxis(kPanelPitch, glm::dvec3(1, 0, 0))};
}

// The profile tool chosen, a profile from points_[7] to points_[52] (picked at frames 9 and 11),
// frame 12 showing it; then, if `hold`, the tool button held from frame 13 for 45 periods: the
// profile deleted at frame 58, frame 59 showing what is left.
nlohmann::json profileScript(const std::vector<TestPoint>& points, bool hold) {
  const TestPoint& a = points[7];
  const TestPoint& b = points[52];
  const auto at = handScript("right");
  const nlohmann::json none = nlohmann::json::object();
  const nlohmann::json pull{{"trigger/value", 1.0}}, button{{"b/click", true}};
  // Short presses act at their release: height at frame 2, area 4, angle 6, profile 8.
  nlohmann::json frames{at(0, a, none), at(1, a, button), at(2, a, none),  at(3, a, button),
                        at(4, a, none), at(5, a, button), at(6, a, none),  at(7, a, button),
                        at(8, a, none), at(9, a, pull),   at(10, b, none), at(11, b, pull),
                        at(12, b, none)};
  if (hold) {
    frames.push_back(at(13, b, button));
    frames.push_back(at(59, b, none));
  }
  return {{"profile", "/interaction_profiles/oculus/touch_controller"}, {"frames", frames}};
}

bool panelBackground(const std::uint8_t* p) {
  return std::abs(p[0] - 20) <= 6 && std::abs(p[1] - 20) <= 6 && std::abs(p[2] - 24) <= 6;
}

// After the profile tool's two picks, the panel stands where its rule puts it in both eyes (its
// left edge where the test projects it, so with the eyes' disparity), the corridor's points are
// orange dots on it where the plot's layout and the test's projection put them, its background
// between them.
TEST_F(XrViewTest, AProfilesPlotStandsOnAPanelAboveItsLineInBothEyes) {
  const Eye eyes[2] = {panelEye(-0.032), panelEye(0.032)};
  constexpr int kW = 480, kH = 256;
  const auto result = run(eyes, kW, kH, 13, "--profile-width 1.5", profileScript(points_, false));
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const std::string& err = result.err;
  const std::vector<glm::dvec3> picks = laserPicks(err);
  ASSERT_EQ(picks.size(), 2u) << err;

  // The corridor's points as the plot places them: distance along the line, height.
  const glm::dvec2 p0(picks[0]), along = glm::dvec2(picks[1]) - p0;
  const double length = glm::length(along);
  std::vector<glm::dvec2> samples;  // (station, height)
  for (const TestPoint& p : points_) {
    glm::dvec3 held = p.file;
    for (const glm::dvec3& end : picks) {
      if (glm::length(p.file - end) < 1e-3) held = end;
    }
    const glm::dvec2 q = glm::dvec2(held) - p0;
    const double t = glm::dot(q, along) / glm::dot(along, along);
    const double off = std::abs(q.x * along.y - q.y * along.x) / length;
    if (t >= 0 && t <= 1 && off <= 0.75) samples.push_back({t * length, held.z});
  }
  ASSERT_GE(samples.size(), 10u);
  double low = samples[0].y, high = samples[0].y;
  for (const glm::dvec2& s : samples) low = std::min(low, s.y), high = std::max(high, s.y);

  const glm::dvec3 head = kOrigin + glm::dvec3(0, 0, 1.6);  // the eyes' middle, in the file
  const std::array<glm::dvec3, 4> corners = expectedPanel(picks[0], picks[1], head);
  const auto eyePixel = [&](int v, const glm::dvec3& file) {
    glm::dvec2 px(-1e9);
    EXPECT_TRUE(
        project({file, 0, 0, 0}, eyes[v], 1.0, kW, kH, px, [](const glm::dvec3& s) { return s; }));
    return px;
  };
  const auto pixelOf = [&](const RgbaImage& image, const glm::dvec2& px) {
    const int x = int(std::floor(px.x)), y = int(std::floor(px.y));
    EXPECT_TRUE(x >= 0 && y >= 0 && x < image.width && y < image.height) << px.x << "," << px.y;
    const std::uint8_t* p =
        &image.pixels[(std::size_t(std::clamp(y, 0, image.height - 1)) * image.width +
                       std::size_t(std::clamp(x, 0, image.width - 1))) *
                      4];
    return glm::ivec3(p[0], p[1], p[2]);
  };
  // A grid point drawn in front of the panel could cover a pixel checked: none is near one.
  const auto nearAPoint = [&](int v, const glm::dvec2& px) {
    for (const TestPoint& p : points_) {
      glm::dvec2 q;
      if (project(p, eyes[v], 1.0, kW, kH, q, [](const glm::dvec3& s) { return s; }) &&
          glm::length(q - px) < 2.5) {
        return true;
      }
    }
    return false;
  };
  const auto orange = [](const glm::ivec3& c) {
    return c.r > 110 && c.r > c.g + 25 && c.g > c.b + 15;
  };
  const auto background = [](const glm::ivec3& c) {
    const std::uint8_t p[3] = {std::uint8_t(c.r), std::uint8_t(c.g), std::uint8_t(c.b)};
    return panelBackground(p);
  };

  double left_edge[2] = {0, 0};
  for (int v = 0; v < 2; ++v) {
    const RgbaImage image = readPng(dir_ / "out" / ("frame_12_view_" + std::to_string(v) + ".png"));
    ASSERT_EQ(image.width, kW);
    // The corners are in the picture: the whole panel is seen.
    for (const glm::dvec3& c : corners) {
      const glm::dvec2 px = eyePixel(v, c);
      EXPECT_TRUE(px.x > 2 && px.y > 2 && px.x < kW - 2 && px.y < kH - 2) << "view " << v;
    }
    // Each point of the corridor: an orange dot at its place in the plot.
    int dots = 0;
    for (const glm::dvec2& s : samples) {
      const double column = 150 + std::round(s.x / length * 469.0);
      const double row = 335 - std::round((s.y - low) / (high - low) * 287.0);
      const glm::dvec2 px = eyePixel(v, onPanel(corners, column, row));
      if (nearAPoint(v, px)) continue;
      const glm::ivec3 c = pixelOf(image, px);
      EXPECT_TRUE(orange(c)) << "view " << v << ": the point at " << s.x << " m, height " << s.y
                             << " expected at " << px.x << "," << px.y << ", found " << c.r << ","
                             << c.g << "," << c.b;
      ++dots;
    }
    EXPECT_GE(dots, 6) << "view " << v;
    // The background in the data area, away from the dots; black just outside the panel's
    // corners.
    int backgrounds = 0;
    for (double column = 170; column < 610; column += 40) {
      for (double row = 70; row < 330; row += 40) {
        bool clear = true;
        for (const glm::dvec2& s : samples) {
          const double dc = 150 + s.x / length * 469.0 - column;
          const double dr = 335 - (s.y - low) / (high - low) * 287.0 - row;
          clear &= std::hypot(dc, dr) > 12;
        }
        const glm::dvec2 px = eyePixel(v, onPanel(corners, column, row));
        if (!clear || nearAPoint(v, px)) continue;
        const glm::ivec3 c = pixelOf(image, px);
        EXPECT_TRUE(background(c)) << "view " << v << " at " << px.x << "," << px.y << ": " << c.r
                                   << "," << c.g << "," << c.b;
        ++backgrounds;
      }
    }
    EXPECT_GE(backgrounds, 20) << "view " << v;
    for (const auto& [column, row] : {std::pair{-12.0, 420.0}, {652.0, 420.0}, {-12.0, -20.0}}) {
      const glm::dvec2 px = eyePixel(v, onPanel(corners, column, row));
      if (nearAPoint(v, px)) continue;
      EXPECT_FALSE(background(pixelOf(image, px))) << "view " << v << " outside the panel";
    }
    // The panel's left edge on the row through its middle (the picture's left margin is
    // background there): the first background pixel from the left, where the edge projects.
    const glm::dvec2 mid = eyePixel(v, onPanel(corners, -0.5, 199.5));
    const int y = int(std::floor(mid.y));
    int first = -1;
    for (int x = 0; x < kW && first < 0; ++x) {
      if (background(pixelOf(image, {x + 0.5, y + 0.5}))) first = x;
    }
    EXPECT_NEAR(first + 0.5, mid.x, 1.0) << "view " << v;
    left_edge[v] = first;
  }
  // The disparity: the panel, nearer than infinity, sits further left in the right eye.
  const glm::dvec2 edge0 = eyePixel(0, onPanel(corners, -0.5, 199.5));
  const glm::dvec2 edge1 = eyePixel(1, onPanel(corners, -0.5, 199.5));
  EXPECT_GT(edge0.x - edge1.x, 3.0);
  EXPECT_NEAR(left_edge[0] - left_edge[1], edge0.x - edge1.x, 1.5);
}

// The tool button held deletes the profile (the last measurement), and its panel goes with it:
// frame 12 shows the panel's background, frame 59 none (small pictures: the panel alone counts).
TEST_F(XrViewTest, TheToolButtonHeldTakesTheProfilesPanelAway) {
  const Eye eyes[2] = {panelEye(-0.032), panelEye(0.032)};
  const auto result = run(eyes, 64, 34, 60, "--profile-width 1.5", profileScript(points_, true));
  ASSERT_EQ(result.exit_code, 0) << result.err;
  ASSERT_NE(result.err.find("--xr: deleted profile "), std::string::npos) << result.err;
  for (int v = 0; v < 2; ++v) {
    const auto count = [&](int frame) {
      const RgbaImage image =
          readPng(dir_ / "out" /
                  ("frame_" + std::to_string(frame) + "_view_" + std::to_string(v) + ".png"));
      int n = 0;
      for (std::size_t i = 0; i < image.pixels.size(); i += 4)
        n += panelBackground(&image.pixels[i]);
      return n;
    };
    // The panel covers about 24 x 14 of these pixels, some of them its dots and labels.
    EXPECT_GT(count(12), 150) << "view " << v;
    EXPECT_EQ(count(59), 0) << "view " << v;
  }
}

// The left controller's script of the delete tests: a distance a -> b, then d -> c (trigger
// pulls), then the tool button (Y) held from frame 8 with the laser on `held_on`, let go at 54.
nlohmann::json twoDistancesThenToolHeld(const TestPoint& a, const TestPoint& b, const TestPoint& d,
                                        const TestPoint& c, const TestPoint& held_on) {
  const auto at = handScript("left");
  const nlohmann::json none = nlohmann::json::object();
  const nlohmann::json pull{{"trigger/value", 1.0}}, hold{{"y/click", true}};
  return {{"profile", "/interaction_profiles/oculus/touch_controller"},
          {"frames",
           {at(0, a, none), at(1, a, pull), at(2, b, none), at(3, b, pull), at(4, d, none),
            at(5, d, pull), at(6, c, none), at(7, c, pull), at(8, held_on, hold),
            at(54, held_on, none)}}};
}

// The length on the one "deleted distance" line of `err` (NaN, and a failure, without one).
double deletedDistance(const std::string& err) {
  const auto deleted = err.find("--xr: deleted distance ");
  EXPECT_NE(deleted, std::string::npos) << err;
  if (deleted == std::string::npos) return std::nan("");
  EXPECT_EQ(err.find("--xr: deleted ", deleted + 1), std::string::npos) << "deleted once";
  double length = std::nan("");
  EXPECT_EQ(std::sscanf(err.c_str() + deleted, "--xr: deleted distance %lf m", &length), 1);
  return length;
}

// --measurements FILE that exists: its measurements and annotations are kept, the headset's are
// added, and the tool button held half a second (45 frames at the runtime's 90 Hz) with the laser
// on no measurement deletes the last one, which the file then lacks.
TEST_F(XrViewTest, TheToolButtonHeldDeletesTheLastMeasurementAndTheFileKeepsTheRest) {
  const Eye eyes[2] = {straightEye(-0.032), straightEye(0.032)};
  const TestPoint& a = points_[7];
  const TestPoint& b = points_[52];
  const TestPoint& c = points_[26];
  const TestPoint& d = points_[8];     // not b: a press on the first distance's vertex grabs it
  const TestPoint& away = points_[0];  // the laser on no measurement: tens of degrees off them
  // Held from frame 8: 45 periods later, frame 53, deletes d -> c.
  const nlohmann::json controllers = twoDistancesThenToolHeld(a, b, d, c, away);
  const std::filesystem::path file = dir_ / "kept.json";
  std::ofstream(file) << R"({"format": "parallax-measurements", "version": 1,
    "measurements": [{"kind": "height", "name": "mast", "points": [[1, 2, 3], [1, 2, 7.5]]}],
    "annotations": [{"label": "gate", "position": [4, 5, 6]}]})";
  const auto result = run(eyes, 64, 48, 55, "--measurements " + quoted(file.string()), controllers);
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const std::string& err = result.err;
  const std::vector<glm::dvec3> picks = laserPicks(err);
  ASSERT_EQ(picks.size(), 4u) << err;
  EXPECT_EQ(err.find("tool "), std::string::npos) << "a long press is no short one: " << err;
  EXPECT_NEAR(deletedDistance(err), glm::length(picks[3] - picks[2]), 1e-6);

  const std::vector<SavedMeasurement> saved = savedMeasurements(file);
  ASSERT_EQ(saved.size(), 2u);
  EXPECT_EQ(saved[0].kind, "height");
  EXPECT_EQ(saved[0].points, (std::vector<glm::dvec3>{glm::dvec3(1, 2, 3), glm::dvec3(1, 2, 7.5)}));
  EXPECT_EQ(saved[1].kind, "distance");
  EXPECT_EQ(saved[1].points, (std::vector<glm::dvec3>{picks[0], picks[1]}));
  const nlohmann::json doc = nlohmann::json::parse(test::readFile(file));
  EXPECT_EQ(doc.at("measurements").at(0).at("name"), "mast");
  ASSERT_EQ(doc.at("annotations").size(), 1u);
  EXPECT_EQ(doc.at("annotations").at(0).at("label"), "gate");
}

// The trigger pressed with the laser on a distance's second vertex grabs it (no pick); held, the
// vertex follows the laser's pick to another point of the grid, the segment's label drawn at the
// new midpoint while it is held; let go, the distance is printed and saved with that vertex: its
// length the test's own arithmetic on the points.
TEST_F(XrViewTest, TheTriggerOnAVertexGrabsItAndItFollowsTheLaserUntilLetGo) {
  const Eye eyes[2] = {straightEye(-0.032), straightEye(0.032)};
  const TestPoint& a = points_[7];
  const TestPoint& b = points_[52];
  const TestPoint& c = points_[26];
  const auto at = handScript("right");
  const nlohmann::json none = nlohmann::json::object();
  const nlohmann::json pull{{"trigger/value", 1.0}};
  const nlohmann::json controllers{
      {"profile", "/interaction_profiles/oculus/touch_controller"},
      {"frames",
       {at(0, a, none), at(1, a, pull), at(2, b, none), at(3, b, pull),  // a distance a -> b
        at(4, b, none), at(5, b, pull),                                  // b grabbed
        at(6, c, pull),                                                  // dragged to c
        at(7, c, none)}}};                                               // and let go there
  const std::filesystem::path file = dir_ / "moved.json";
  const auto result =
      run(eyes, 320, 240, 8, "--measurements " + quoted(file.string()), controllers);
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const std::string& err = result.err;
  const std::vector<glm::dvec3> picks = laserPicks(err);
  ASSERT_EQ(picks.size(), 2u) << "the grab and the drag are no picks: " << err;
  EXPECT_LT(glm::length(picks[0] - a.file), 1e-3) << err;
  EXPECT_LT(glm::length(picks[1] - b.file), 1e-3) << err;
  EXPECT_NE(err.find("--xr: grabbed vertex 2 of measurement 1\n"), std::string::npos) << err;
  const auto moved_at = err.find("--xr: moved vertex 2 of measurement 1 to ");
  ASSERT_NE(moved_at, std::string::npos) << err;
  EXPECT_EQ(err.find("--xr: moved ", moved_at + 1), std::string::npos) << "one release: " << err;
  glm::dvec3 moved;
  double length = 0;
  ASSERT_EQ(std::sscanf(err.c_str() + moved_at,
                        "--xr: moved vertex 2 of measurement 1 to %lf,%lf,%lf: distance %lf m",
                        &moved.x, &moved.y, &moved.z, &length),
            4)
      << err;
  EXPECT_LT(glm::length(moved - c.file), 1e-3) << "the laser's pick of c";
  EXPECT_NEAR(length, glm::length(moved - picks[0]), 1e-6);
  EXPECT_NEAR(length, glm::length(c.file - a.file), 2e-3);
  EXPECT_GT(std::abs(length - glm::length(picks[1] - picks[0])), 1.0) << "it did move";

  // While held (frame 6) the segment's label is at the midpoint of a and the laser's point, not
  // where it was (frame 4, the midpoint of a and b).
  const auto labelAt = [&](int frame, int v, const glm::dvec3& anchor_file) {
    const RgbaImage image = readPng(
        dir_ / "out" / ("frame_" + std::to_string(frame) + "_view_" + std::to_string(v) + ".png"));
    glm::dvec2 anchor;
    EXPECT_TRUE(project({anchor_file, 0, 0, 0}, eyes[v], 1.0, image.width, image.height, anchor,
                        [](const glm::dvec3& s) { return s; }));
    const TextBox text =
        textPixelsIn(image, anchor.x - 20, anchor.y - 40, anchor.x + 200, anchor.y + 20);
    return text.count > 10 && text.x0 >= anchor.x && text.x0 <= anchor.x + 12 &&
           text.y1 <= anchor.y && text.y0 >= anchor.y - 30;
  };
  const glm::dvec3 before = 0.5 * (picks[0] + picks[1]), after = 0.5 * (picks[0] + moved);
  for (int v = 0; v < 2; ++v) {
    EXPECT_TRUE(labelAt(4, v, before)) << "view " << v;
    EXPECT_FALSE(labelAt(4, v, after)) << "view " << v;
    EXPECT_TRUE(labelAt(6, v, after)) << "view " << v;
    EXPECT_FALSE(labelAt(6, v, before)) << "view " << v;
  }

  const std::vector<SavedMeasurement> saved = savedMeasurements(file);
  ASSERT_EQ(saved.size(), 1u);
  EXPECT_EQ(saved[0].kind, "distance");
  ASSERT_EQ(saved[0].points.size(), 2u);
  EXPECT_EQ(saved[0].points[0], picks[0]);
  EXPECT_LT(glm::length(saved[0].points[1] - moved), 1e-6) << "as printed, six decimals";
}

// The tool button held with the laser on the first of two distances (the middle of its line, no
// vertex near) deletes that one; the file keeps the second.
TEST_F(XrViewTest, TheToolButtonHeldOnAMeasurementDeletesThatOne) {
  const Eye eyes[2] = {straightEye(-0.032), straightEye(0.032)};
  const TestPoint& a = points_[7];
  const TestPoint& b = points_[52];
  const TestPoint& c = points_[26];
  const TestPoint& d = points_[8];
  const TestPoint middle{0.5 * (a.file + b.file), 0, 0, 0};
  // Held from frame 8 on a -> b's line: frame 53 deletes a -> b.
  const nlohmann::json controllers = twoDistancesThenToolHeld(a, b, d, c, middle);
  const std::filesystem::path file = dir_ / "second.json";
  const auto result = run(eyes, 64, 48, 55, "--measurements " + quoted(file.string()), controllers);
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const std::string& err = result.err;
  const std::vector<glm::dvec3> picks = laserPicks(err);
  ASSERT_EQ(picks.size(), 4u) << err;
  EXPECT_NEAR(deletedDistance(err), glm::length(picks[1] - picks[0]), 1e-6);
  const std::vector<SavedMeasurement> saved = savedMeasurements(file);
  ASSERT_EQ(saved.size(), 1u);
  EXPECT_EQ(saved[0].kind, "distance");
  EXPECT_EQ(saved[0].points, (std::vector<glm::dvec3>{picks[2], picks[3]}));
  EXPECT_NE(err.find("1 measurements saved to "), std::string::npos) << err;
}

// --- adding and removing a vertex of a finished area ------------------------------------------

// A measurement file holding one area whose vertices are `corners` (their file coordinates,
// exactly: the JSON keeps every digit of a double).
void writeAreaFile(const std::filesystem::path& file,
                   const std::vector<const TestPoint*>& corners) {
  nlohmann::json points = nlohmann::json::array();
  for (const TestPoint* corner : corners) {
    points.push_back({corner->file.x, corner->file.y, corner->file.z});
  }
  const nlohmann::json doc{{"format", "parallax-measurements"},
                           {"version", 1},
                           {"measurements", {{{"kind", "area"}, {"points", points}}}}};
  std::ofstream(file) << doc.dump();
}

// The three values of an area's printed line at `from` ("area 3D A m², projected P m²,
// perimeter L m"), NaN and a failure where there is none.
glm::dvec3 printedArea(const std::string& err, std::size_t from) {
  glm::dvec3 values(std::nan(""));
  const auto at = err.find("area 3D ", from);
  EXPECT_NE(at, std::string::npos) << err.substr(from);
  if (at == std::string::npos) return values;
  EXPECT_EQ(std::sscanf(err.c_str() + at, "area 3D %lf m², projected %lf m², perimeter %lf m",
                        &values.x, &values.y, &values.z),
            3)
      << err.substr(at);
  return values;
}

// The test's own arithmetic on a closed polygon: half the length of the sum of the triangles'
// cross products from its first vertex (3D), half the absolute sum of their z (projected), and
// the boundary's length.
glm::dvec3 polygonValues(const std::vector<glm::dvec3>& p) {
  glm::dvec3 cross(0.0);
  double perimeter = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const glm::dvec3& q = p[(i + 1) % p.size()];
    cross += glm::cross(p[i] - p[0], q - p[0]);
    perimeter += glm::length(q - p[i]);
  }
  return {0.5 * glm::length(cross), 0.5 * std::abs(cross.z), perimeter};
}

// The vertex and its measurement's values on the line "--xr: added vertex V of measurement 1 at
// X,Y,Z: area ..." (NaN and a failure where there is none); `from` moves past it.
glm::dvec3 addedVertex(const std::string& err, int vertex, std::size_t& from, glm::dvec3& values) {
  const std::string line = "--xr: added vertex " + std::to_string(vertex) + " of measurement 1 at ";
  glm::dvec3 p(std::nan(""));
  from = err.find(line, from);
  EXPECT_NE(from, std::string::npos) << line << " in " << err;
  if (from == std::string::npos) return p;
  EXPECT_EQ(std::sscanf(err.c_str() + from + line.size(), "%lf,%lf,%lf", &p.x, &p.y, &p.z), 3);
  values = printedArea(err, from);
  ++from;
  return p;
}

// The trigger pressed with the laser on a finished area's line (the middle of it: no vertex
// near, nothing of the grid within 2 degrees) adds a vertex on that line and holds it: let go at
// once, it stays on the line, where the laser crosses it; on another line, held and turned to a
// grid point, it follows the laser there. Each release prints the area of the new polygon, the
// test's own arithmetic on the vertices, and the file saves the five in order. (The area is
// the file's, from --measurements: the headset's own areas are tested above.)
TEST_F(XrViewTest, TheTriggerOnAnAreasLineAddsAVertexThereThatFollowsTheLaser) {
  const Eye eyes[2] = {straightEye(-0.032), straightEye(0.032)};
  const TestPoint& a = points_[7];
  const TestPoint& b = points_[52];
  const TestPoint& c = points_[26];
  const TestPoint& to = points_[8];  // where the second new vertex is taken
  const TestPoint ab{0.5 * (a.file + b.file), 0, 0, 0}, bc{0.5 * (b.file + c.file), 0, 0, 0};
  const std::filesystem::path file = dir_ / "added.json";
  writeAreaFile(file, {&a, &b, &c});
  const auto at = handScript("right");
  const nlohmann::json none = nlohmann::json::object(), pull{{"trigger/value", 1.0}};
  const nlohmann::json controllers{
      {"profile", "/interaction_profiles/oculus/touch_controller"},
      {"frames",
       {at(0, ab, pull), at(1, ab, none),                      // added on a -> b, let go there
        at(2, bc, pull), at(3, to, pull), at(4, to, none)}}};  // added on b -> c, taken to `to`
  const auto result = run(eyes, 64, 48, 5, "--measurements " + quoted(file.string()), controllers);
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const std::string& err = result.err;
  EXPECT_TRUE(laserPicks(err).empty()) << "the presses on the lines are no picks: " << err;
  EXPECT_NE(err.find("--xr: inserted vertex 2 in measurement 1 (on its line)\n"), std::string::npos)
      << err;
  EXPECT_NE(err.find("--xr: inserted vertex 4 in measurement 1 (on its line)\n"), std::string::npos)
      << err;

  // Let go where it was added: the line's point nearest the laser, which was aimed at its middle.
  std::size_t from = 0;
  glm::dvec3 values(0.0);
  const glm::dvec3 first = addedVertex(err, 2, from, values);
  EXPECT_LT(glm::length(first - ab.file), 1e-6) << err;
  glm::dvec3 expected = polygonValues({a.file, first, b.file, c.file});
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(values[i], expected[i], 2e-6) << i;
  EXPECT_NEAR(values.x, polygonValues({a.file, b.file, c.file}).x, 2e-6)
      << "a vertex on a line leaves the area as it was";

  // Taken to `to`: the laser's pick of it, vertex 4 of five.
  const glm::dvec3 second = addedVertex(err, 4, from, values);
  EXPECT_LT(glm::length(second - to.file), 1e-3) << err;
  expected = polygonValues({a.file, first, b.file, second, c.file});
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(values[i], expected[i], 2e-6) << i;
  EXPECT_GT(std::abs(values.x - polygonValues({a.file, b.file, c.file}).x), 0.1)
      << "the area changed with the moved vertex";

  const std::vector<SavedMeasurement> saved = savedMeasurements(file);
  ASSERT_EQ(saved.size(), 1u);
  EXPECT_EQ(saved[0].kind, "area");
  ASSERT_EQ(saved[0].points.size(), 5u);
  EXPECT_EQ(saved[0].points[0], a.file);
  EXPECT_LT(glm::length(saved[0].points[1] - first), 1e-6);
  EXPECT_EQ(saved[0].points[2], b.file);
  EXPECT_LT(glm::length(saved[0].points[3] - second), 1e-6);
  EXPECT_EQ(saved[0].points[4], c.file);
}

// The tool button pressed while the trigger holds an area's vertex removes it: the line printed
// is the area of the other three, the test's own arithmetic; at three vertices a second press
// removes nothing and says so. Neither press is a tool button's short press (no next tool), and
// the file saves the three.
TEST_F(XrViewTest, TheToolButtonOnAHeldVertexRemovesItDownToThreeForAnArea) {
  const Eye eyes[2] = {straightEye(-0.032), straightEye(0.032)};
  const TestPoint& a = points_[7];
  const TestPoint& b = points_[8];
  const TestPoint& c = points_[53];
  const TestPoint& d = points_[26];
  const std::filesystem::path file = dir_ / "removed.json";
  writeAreaFile(file, {&a, &b, &c, &d});
  const auto at = handScript("right");
  const nlohmann::json none = nlohmann::json::object(), pull{{"trigger/value", 1.0}};
  const nlohmann::json pull_button{{"trigger/value", 1.0}, {"b/click", true}};
  const nlohmann::json controllers{
      {"profile", "/interaction_profiles/oculus/touch_controller"},
      {"frames",
       {at(0, d, pull), at(1, d, pull_button), at(2, d, pull), at(3, d, none),     // d removed
        at(4, c, pull), at(5, c, pull_button), at(6, c, pull), at(7, c, none)}}};  // c stays
  const auto result = run(eyes, 64, 48, 8, "--measurements " + quoted(file.string()), controllers);
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const std::string& err = result.err;
  EXPECT_TRUE(laserPicks(err).empty()) << err;
  EXPECT_NE(err.find("--xr: grabbed vertex 4 of measurement 1\n"), std::string::npos) << err;
  const auto removed = err.find("--xr: removed vertex 4 of measurement 1: area 3D ");
  ASSERT_NE(removed, std::string::npos) << err;
  EXPECT_EQ(err.find("--xr: removed ", removed + 1), std::string::npos) << "removed once: " << err;
  const glm::dvec3 values = printedArea(err, removed);
  const glm::dvec3 expected = polygonValues({a.file, b.file, c.file});
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(values[i], expected[i], 2e-6) << i;
  EXPECT_NE(err.find("(3 points)", removed), std::string::npos) << err;
  EXPECT_NE(err.find("--xr: grabbed vertex 3 of measurement 1\n", removed), std::string::npos)
      << err;
  EXPECT_NE(err.find("--xr: vertex 3 of measurement 1 stays: the area keeps at least 3 points\n"),
            std::string::npos)
      << err;
  EXPECT_EQ(err.find("--xr: tool "), std::string::npos) << "no short press: " << err;
  EXPECT_EQ(err.find("--xr: deleted "), std::string::npos) << err;

  const std::vector<SavedMeasurement> saved = savedMeasurements(file);
  ASSERT_EQ(saved.size(), 1u);
  EXPECT_EQ(saved[0].kind, "area");
  ASSERT_EQ(saved[0].points.size(), 3u);
  EXPECT_EQ(saved[0].points[0], a.file);
  EXPECT_EQ(saved[0].points[1], b.file);
  EXPECT_LT(glm::length(saved[0].points[2] - c.file), 1e-3) << "held on c: the laser's c";
}

TEST_F(XrViewTest, TheAButtonTeleportsToTheLaserPointOnTheFloorUnderTheHead) {
  const Eye eyes[2] = {straightEye(-0.032), straightEye(0.032)};
  const TestPoint& target = points_[33];
  const nlohmann::json aim = handAimingAt(target.file, nullptr);
  nlohmann::json pressed = aim;
  pressed["inputs"] = {{"a/click", true}};
  const nlohmann::json controllers{
      {"profile", "/interaction_profiles/oculus/touch_controller"},
      {"frames", {{{"frame", 0}, {"right", aim}}, {{"frame", 1}, {"right", pressed}}}}};
  const auto result = run(eyes, 96, 72, 2, "", controllers);
  ASSERT_EQ(result.exit_code, 0) << result.err;
  // The head is at (0, 1.6, 0): the point comes to the stage's origin, on the floor.
  const Placement p = reportedPlacement(result.err);
  EXPECT_LT(glm::length(stageOf(p, target.file)), 1e-3) << result.err;
  EXPECT_EQ(p.yaw, 0.0);
}

// --- under Xvfb: the mirror window's GLX context, the Khronos core validation layer ----------

class XrViewValidatedTest : public XrViewTest {
 protected:
  void SetUp() override {
    XrViewTest::SetUp();
    display_ = std::make_unique<test::Display>(dir_);
    ASSERT_FALSE(display_->name().empty())
        << "Xvfb did not start: " << test::readFile(dir_ / "xvfb.log");
    setenv("DISPLAY", display_->name().c_str(), 1);
    setenv("XR_ENABLE_API_LAYERS", "XR_APILAYER_LUNARG_core_validation", 1);
  }
  void TearDown() override { unsetenv("DISPLAY"); }

  // The layer ran (it announces its output type on stderr) and reported nothing: every message
  // of it starts "[VALID_" (errors, warnings, performance warnings alike), on stdout.
  static void expectValidated(const test::RunResult& result) {
    EXPECT_NE(result.err.find("Core Validation output type"), std::string::npos)
        << "the core validation layer did not run: " << result.err;
    EXPECT_EQ(result.out.find("[VALID_"), std::string::npos) << result.out;
    EXPECT_EQ(result.err.find("[VALID_"), std::string::npos) << result.err;
    EXPECT_NE(result.err.find("through GLX (XR_KHR_opengl_enable)"), std::string::npos)
        << result.err;
  }

  std::unique_ptr<test::Display> display_;
};

TEST_F(XrViewValidatedTest, TheLifecycleRunsCleanUnderTheValidationLayer) {
  const Eye eyes[2] = {straightEye(-0.032), straightEye(0.032)};
  const auto result = run(eyes, 32, 24, 3, "--width 320 --height 200");
  ASSERT_EQ(result.exit_code, 0) << result.err << result.out;
  expectValidated(result);
  EXPECT_NE(result.err.find("3 frames of 2 x 32x24 drawn"), std::string::npos) << result.err;
  EXPECT_TRUE(std::filesystem::exists(dir_ / "out" / "frame_2.json"));
  EXPECT_FALSE(std::filesystem::exists(dir_ / "out" / "frame_3.json"));
}

TEST_F(XrViewValidatedTest, EyesEqualACpuProjectionUnderTheValidationLayer) {
  const glm::dquat head = glm::angleAxis(glm::radians(-8.0), glm::dvec3(0, 1, 0));
  const glm::dvec3 centre(-0.1, 1.5, 0.2);
  const Eye eyes[2] = {{-0.8, 0.6, 0.5, -0.7, centre + head * glm::dvec3(-0.032, 0, 0), head},
                       {-0.6, 0.8, 0.5, -0.7, centre + head * glm::dvec3(0.032, 0, 0), head}};
  const auto result = run(eyes, 140, 110, 1);
  ASSERT_EQ(result.exit_code, 0) << result.err << result.out;
  expectValidated(result);
  for (int v = 0; v < 2; ++v) {
    int inside = 0;
    expectProjection(eyes[v],
                     readPng(dir_ / "out" / ("frame_0_view_" + std::to_string(v) + ".png")), 1.0,
                     &inside);
    EXPECT_GT(inside, 30);
  }
}

TEST_F(XrViewValidatedTest, ControllersRunCleanUnderTheValidationLayer) {
  const Eye eyes[2] = {straightEye(-0.032), straightEye(0.032)};
  const glm::dvec3 g0(0.2, 1.1, 0.3), d(-0.3, 0.1, -0.5);
  const nlohmann::json controllers{
      {"profile", "/interaction_profiles/oculus/touch_controller"},
      {"frames",
       {{{"frame", 0}, {"right", handJson(g0, {{"squeeze/value", 1.0}})}},
        {{"frame", 1}, {"right", handJson(g0 + d, {{"squeeze/value", 1.0}})}}}}};
  const auto result = run(eyes, 128, 96, 2, "", controllers);
  ASSERT_EQ(result.exit_code, 0) << result.err << result.out;
  expectValidated(result);
  int inside = 0;
  expectProjection(eyes[0], readPng(dir_ / "out" / "frame_1_view_0.png"), 1.0, &inside,
                   [&](const glm::dvec3& s) { return s + d; });
  EXPECT_GT(inside, 20);
}

TEST_F(XrViewTest, WithoutARuntimeTheMessageNamesTheRuntimeLookedFor) {
  const auto missing = dir_ / "no-such-runtime.json";
  setenv("XR_RUNTIME_JSON", missing.c_str(), 1);
  const auto result = runParallax(dir_, "view " + quoted((dir_ / "grid.ply").string()) + " --xr");
  EXPECT_EQ(result.exit_code, 1) << result.err;
  EXPECT_NE(result.err.find("no OpenXR runtime"), std::string::npos) << result.err;
  EXPECT_NE(result.err.find(missing.string()), std::string::npos) << result.err;
}

}  // namespace
}  // namespace parallax
