// `parallax render` end to end: options to picture, with the exact-pixel rule checked through
// the command line (--eye --target --up --fov in the file's own coordinates), a camera path,
// and a clear error for a file that cannot be read. Level of detail: a Potree directory drawn
// through the node selection (equal to the plain render when the budget holds every point, at
// most the budget otherwise), a file over the budget converted once into the cache, --preview,
// and a hostile directory.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "render/camera.h"
#include "render/image_file.h"
#include "render/view_extent.h"
#include "support/run_parallax.h"
#include "support/temp_dir.h"

namespace parallax::test {
namespace {

using test::readText;
using test::runWithoutLeakCheck;

std::string quoted(const std::filesystem::path& path) {
  // Appended, not `"'" + path.string()`: GCC 12 warns (-Wrestrict, bug 105329) on that insert.
  std::string text = "'";
  text += path.string();
  text += '\'';
  return text;
}

// A camera path from `a` at time 0 to `b` at time 1 (render/camera_path.h).
std::string twoKeyframePath(const Camera& a, const Camera& b) {
  const nlohmann::json path = {
      {"keyframes",
       {{{"time", 0}, {"camera", cameraToJson(a)}}, {{"time", 1}, {"camera", cameraToJson(b)}}}}};
  return path.dump();
}

// Points at UTM-like coordinates with millimetre values, as a user's file would hold them.
constexpr double kEast = 432100.0, kNorth = 5123400.0, kUp = 250.0;

std::string pointsPly(const std::vector<std::array<double, 3>>& points) {
  std::ostringstream ply;
  ply.precision(12);
  ply << "ply\nformat ascii 1.0\nelement vertex " << points.size()
      << "\nproperty double x\nproperty double y\nproperty double z\nend_header\n";
  for (const auto& p : points) ply << p[0] << ' ' << p[1] << ' ' << p[2] << '\n';
  return ply.str();
}

TEST(RenderCommand, EyeTargetUpAndFovGiveExactlyTheProjectedPixels) {
  TempDir dir;
  std::vector<std::array<double, 3>> points;
  for (int i = 0; i < 7; ++i) {
    for (int j = 0; j < 5; ++j) {
      points.push_back({kEast + 0.137 * i - 0.4, kNorth + 0.093 * j - 0.2, kUp + 0.011 * i * j});
    }
  }
  const auto ply = dir.write("points.ply", pointsPly(points));
  const auto png = dir / "out.png";
  const std::string command = std::string(PARALLAX_EXECUTABLE) + " render " + quoted(ply) + " -o " +
                              quoted(png) +
                              " --width 96 --height 64 --point-size 1 --color uniform"
                              " --eye 432100.3,5123397.7,251.6 --target 432100,5123400,250"
                              " --up 0,0,1 --fov 40 2>" +
                              quoted(dir / "log");
  ASSERT_EQ(runWithoutLeakCheck(command), 0) << readText(dir / "log");
  const RgbaImage image = readPng(png);
  ASSERT_EQ(image.width, 96);
  ASSERT_EQ(image.height, 64);

  // The same camera on the CPU, in double.
  Camera camera;
  camera.lookAt({432100.3, 5123397.7, 251.6}, {kEast, kNorth, kUp}, {0, 0, 1});
  camera.fov_y_deg = 40;
  Bounds3 bounds;
  for (const auto& p : points) bounds.extend(p[0], p[1], p[2]);
  const glm::dmat4 projection = camera.projectionMatrix(96.0 / 64.0, camera.clipRange(bounds));
  // Points within 2% of a pixel edge may land on either side (the GPU snaps to 1/256 pixel):
  // their pixels are allowed, not required.
  std::set<std::pair<int, int>> expected, allowed;
  for (const auto& p : points) {
    const glm::dvec3 eye =
        glm::dmat3(camera.viewMatrix()) * (glm::dvec3(p[0], p[1], p[2]) - camera.position);
    const glm::dvec4 clip = projection * glm::dvec4(eye, 1.0);
    const double x = (clip.x / clip.w + 1) * 48, y = (clip.y / clip.w + 1) * 32;
    const double fx = x - std::floor(x), fy = y - std::floor(y);
    const bool edge = fx < 0.02 || fx > 0.98 || fy < 0.02 || fy > 0.98;
    if (!edge) {
      expected.insert({int(std::floor(x)), 63 - int(std::floor(y))});  // PNG rows: top first
      continue;
    }
    for (double ox : {-0.05, 0.05}) {
      for (double oy : {-0.05, 0.05}) {
        allowed.insert({int(std::floor(x + ox)), 63 - int(std::floor(y + oy))});
      }
    }
  }
  ASSERT_GT(expected.size(), 25u);
  std::set<std::pair<int, int>> lit;
  for (int row = 0; row < 64; ++row) {
    for (int column = 0; column < 96; ++column) {
      if (image.pixels[(std::size_t(row) * 96 + column) * 4] != 0) lit.insert({column, row});
    }
  }
  for (const auto& pixel : expected) {
    EXPECT_TRUE(lit.count(pixel)) << "not lit: " << pixel.first << ", " << pixel.second;
  }
  for (const auto& pixel : lit) {
    EXPECT_TRUE(expected.count(pixel) || allowed.count(pixel))
        << "lit but no point there: " << pixel.first << ", " << pixel.second;
  }
}

TEST(RenderCommand, CameraPathWritesEveryFrame) {
  TempDir dir;
  const auto ply = dir.write("points.ply", pointsPly({{0, 0, 0}, {1, 1, 1}, {1, 0, 0.5}}));
  Camera a, b;
  a.lookAt({5, -5, 3}, {0.5, 0.5, 0.5}, {0, 0, 1});
  b.lookAt({-5, -5, 3}, {0.5, 0.5, 0.5}, {0, 0, 1});
  dir.write("path.json", twoKeyframePath(a, b));
  const std::string command = std::string(PARALLAX_EXECUTABLE) + " render " + quoted(ply) +
                              " --path " + quoted(dir / "path.json") + " --frames 4 -o " +
                              quoted(dir / "frames" / "frame_%04d.png") +
                              " --width 32 --height 24 2>" + quoted(dir / "log");
  ASSERT_EQ(runWithoutLeakCheck(command), 0) << readText(dir / "log");
  for (int f = 0; f < 4; ++f) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%04d.png", f);
    EXPECT_TRUE(std::filesystem::exists(dir / "frames" / name)) << name;
  }
}

// A small grid in front of the default camera, for the stereo options.
std::string gridPly() {
  std::vector<std::array<double, 3>> points;
  for (int i = 0; i < 20; ++i) {
    for (int j = 0; j < 20; ++j) points.push_back({0.05 * i, 0.05 * j, 0.01 * ((i * j) % 7)});
  }
  return pointsPly(points);
}

// Without a camera the view frames the points as they project: centred, filling one axis up to
// the margin, nothing cut off. Checked on the picture, and against a CPU projection of the points
// with the default camera.
TEST(RenderCommand, DefaultViewFillsThePictureWithTheCloud) {
  TempDir dir;
  // A scan-like cloud: a wide, shallow ground disc with a mast on it, off-centre in its own
  // box (whose corners hold nothing), at UTM-like coordinates.
  std::vector<std::array<double, 3>> points;
  for (int ring = 1; ring <= 30; ++ring) {
    for (int k = 0; k < 12 * ring; ++k) {
      const double angle = 2 * 3.14159265358979 * k / (12 * ring), r = 2.0 * ring;
      points.push_back({512000 + r * std::cos(angle), 5400000 + 0.7 * r * std::sin(angle),
                        300 + 0.02 * r * std::sin(3 * angle)});
    }
  }
  for (int i = 0; i < 200; ++i) points.push_back({512030, 5400010, 300 + 0.2 * i});
  const auto ply = dir.write("scan.ply", pointsPly(points));
  const int width = 160, height = 120;
  ASSERT_EQ(runWithoutLeakCheck(std::string(PARALLAX_EXECUTABLE) + " render " + quoted(ply) +
                                " --width 160 " + "--height 120 -o " + quoted(dir / "out.png") +
                                " 2>" + quoted(dir / "log")),
            0)
      << readText(dir / "log");
  const RgbaImage image = readPng(dir / "out.png");
  ASSERT_EQ(image.width, width);
  int x0 = width, x1 = -1, y0 = height, y1 = -1;
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const std::uint8_t* p = &image.pixels[(std::size_t(y) * width + x) * 4];
      if (p[0] | p[1] | p[2])
        x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
    }
  }
  ASSERT_GE(x1, 0) << "nothing drawn";
  // Nothing touches the border; centred to a pixel; one axis spans the view less the margin
  // (Camera::kFitMargin of the half-size on each side: 97 % of the width or height).
  EXPECT_GT(x0, 0);
  EXPECT_GT(y0, 0);
  EXPECT_LT(x1, width - 1);
  EXPECT_LT(y1, height - 1);
  EXPECT_LE(std::abs(x0 - (width - 1 - x1)), 2) << x0 << ".." << x1;
  EXPECT_LE(std::abs(y0 - (height - 1 - y1)), 2) << y0 << ".." << y1;
  const double fill = std::max(double(x1 - x0 + 1) / width, double(y1 - y0 + 1) / height);
  EXPECT_GE(fill, 1.0 - Camera::kFitMargin - 2.0 / height)
      << x0 << ".." << x1 << ", " << y0 << ".." << y1;

  // The same extent from the points projected on the CPU with the default camera.
  PointCloud cloud;
  cloud.count = points.size();
  cloud.quantization.scale = {1e-4, 1e-4, 1e-4};
  cloud.quantization.offset = {512000, 5400000, 300};
  cloud.positions = Column<Int3>(points.size());
  std::vector<glm::dvec3> world;
  for (std::size_t i = 0; i < points.size(); ++i) {
    cloud.positions[i] = {cloud.quantization.toQuantized(0, points[i][0]),
                          cloud.quantization.toQuantized(1, points[i][1]),
                          cloud.quantization.toQuantized(2, points[i][2])};
    world.emplace_back(points[i][0], points[i][1], points[i][2]);
  }
  cloud.computeBounds();
  const double aspect = double(width) / height;
  const Camera camera = defaultCameraFor(viewExtentOf(cloud), aspect);
  const glm::dmat4 to_clip =
      camera.projectionMatrix(aspect, camera.clipRange(cloud.bounds)) * camera.viewMatrix();
  double px0 = INFINITY, px1 = -INFINITY, py0 = INFINITY, py1 = -INFINITY;
  for (const glm::dvec3& p : world) {
    const glm::dvec4 clip = to_clip * glm::dvec4(p, 1.0);
    const double px = (clip.x / clip.w + 1) * 0.5 * width,
                 py = (1 - clip.y / clip.w) * 0.5 * height;
    px0 = std::min(px0, px), px1 = std::max(px1, px), py0 = std::min(py0, py),
    py1 = std::max(py1, py);
  }
  EXPECT_NEAR(x0, px0, 1.0);
  EXPECT_NEAR(x1 + 1, px1, 1.0);
  EXPECT_NEAR(y0, py0, 1.0);
  EXPECT_NEAR(y1 + 1, py1, 1.0);
}

TEST(RenderCommand, StereoQuadBufferFallsBackToSideBySideHeadlessWithAMessage) {
  TempDir dir;
  const auto ply = dir.write("grid.ply", gridPly());
  const std::string base = std::string(PARALLAX_EXECUTABLE) + " render " + quoted(ply) +
                           " --width 96 --height 48 --eye-separation 0.05 --convergence 2";
  ASSERT_EQ(runWithoutLeakCheck(base + " --stereo quad-buffer -o " + quoted(dir / "quad.png") +
                                " 2>" + quoted(dir / "quad.log")),
            0)
      << readText(dir / "quad.log");
  ASSERT_EQ(runWithoutLeakCheck(base + " --stereo sbs -o " + quoted(dir / "sbs.png") + " 2>" +
                                quoted(dir / "sbs.log")),
            0)
      << readText(dir / "sbs.log");
  const std::string log = readText(dir / "quad.log");
  EXPECT_NE(log.find("quad-buffer stereo needs a window with a stereo (GL_STEREO) visual"),
            std::string::npos)
      << log;
  EXPECT_NE(log.find("falling back to sbs"), std::string::npos) << log;
  EXPECT_NE(log.find("stereo sbs, eye separation 0.05, convergence 2"), std::string::npos) << log;
  const RgbaImage quad = readPng(dir / "quad.png"), sbs = readPng(dir / "sbs.png");
  EXPECT_EQ(quad.width, 96);
  EXPECT_EQ(quad.pixels, sbs.pixels);
  // Both halves show the grid.
  std::size_t left = 0, right = 0;
  for (int y = 0; y < sbs.height; ++y) {
    for (int x = 0; x < sbs.width; ++x) {
      const std::uint8_t* p = &sbs.pixels[(std::size_t(y) * sbs.width + x) * 4];
      if (p[0] | p[1] | p[2]) ++(x < 48 ? left : right);
    }
  }
  EXPECT_GT(left, 50u);
  EXPECT_GT(right, 50u);
}

TEST(RenderCommand, UnknownStereoModeIsAClearError) {
  TempDir dir;
  const auto ply = dir.write("grid.ply", gridPly());
  const std::string command = std::string(PARALLAX_EXECUTABLE) + " render " + quoted(ply) +
                              " --stereo 3d -o " + quoted(dir / "out.png") + " 2>" +
                              quoted(dir / "log");
  EXPECT_EQ(runWithoutLeakCheck(command), 1);  // an option error (bad input is 2), not a crash
  const std::string log = readText(dir / "log");
  EXPECT_NE(log.find("--stereo: unknown mode '3d' (use mono|sbs|sbs-squeezed|tb|anaglyph|"
                     "anaglyph-dubois|interlaced|quad-buffer)"),
            std::string::npos)
      << log;
  EXPECT_FALSE(std::filesystem::exists(dir / "out.png"));
}

TEST(RenderCommand, UnreadableFileIsAClearErrorNotACrash) {
  TempDir dir;
  const auto bad = dir.write("broken.ply", "ply\nformat ascii 1.0\nelement vertex 2\nend_header\n");
  const std::string command = std::string(PARALLAX_EXECUTABLE) + " render " + quoted(bad) + " -o " +
                              quoted(dir / "out.png") + " 2>" + quoted(dir / "log");
  EXPECT_EQ(runWithoutLeakCheck(command), 2);
  EXPECT_NE(readText(dir / "log").find("broken.ply"), std::string::npos) << readText(dir / "log");
  EXPECT_FALSE(std::filesystem::exists(dir / "out.png"));
}

TEST(RenderCommand, NoOpenGl45IsAClearError) {
  TempDir dir;
  const auto ply = dir.write("points.ply", pointsPly({{0, 0, 0}, {1, 1, 1}}));
  const std::string render = std::string(PARALLAX_EXECUTABLE) + " render " + quoted(ply) + " -o " +
                             quoted(dir / "out.png");
  // Only Mesa honours MESA_GL_VERSION_OVERRIDE. Whether the driver is Mesa is read off a run
  // without the override (its GL version string names Mesa), never off the run under test: a
  // render that succeeds under the override is exactly the failure this test is for.
  ASSERT_EQ(runWithoutLeakCheck(render + " 2>" + quoted(dir / "plain.log")), 0)
      << readText(dir / "plain.log");
  const std::string plain = readText(dir / "plain.log");
  const auto gl = plain.find("(OpenGL ");
  ASSERT_NE(gl, std::string::npos) << plain;
  // "(OpenGL 4.5 (Core Profile) Mesa 22.3.6, EGL ...)": the version runs to the comma.
  const std::string version = plain.substr(gl + 1, plain.find(", ", gl) - gl - 1);
  if (version.find("Mesa") == std::string::npos) {
    GTEST_SKIP() << "the driver is not Mesa (" << version
                 << "), so MESA_GL_VERSION_OVERRIDE cannot stand for an old driver";
  }
  // Mesa's override caps the version it offers: what a user with an old driver would see.
  const int status =
      runWithoutLeakCheck("MESA_GL_VERSION_OVERRIDE=3.3 " + render + " 2>" + quoted(dir / "log"));
  EXPECT_EQ(status, 1);
  const std::string log = readText(dir / "log");
  EXPECT_NE(log.find("needs OpenGL 4.5 core"), std::string::npos) << log;
  EXPECT_NE(log.find("offers OpenGL 3.3"), std::string::npos) << log;
}

// Level of detail on a generated 60 000-point scan (several octree nodes: a node splits above
// 20 000 points), converted once per test.
struct LodFiles {
  std::filesystem::path ply, octree;
};

LodFiles generatedCloud(const TempDir& dir) {
  LodFiles files{dir / "scan.ply", dir / "scan_octree"};
  const std::string exe = PARALLAX_EXECUTABLE;
  EXPECT_EQ(runWithoutLeakCheck(exe + " generate --points 60000 -o " + quoted(files.ply) +
                                " > /dev/null 2>&1"),
            0);
  EXPECT_EQ(
      runWithoutLeakCheck(exe + " convert -q " + quoted(files.ply) + " -o " + quoted(files.octree)),
      0);
  return files;
}

// The number after `label` in `text`. A missing label fails the test (the -1 returned then
// would pass a `<=` check on its own).
long long numberAfter(const std::string& text, const std::string& label) {
  const auto at = text.find(label);
  if (at == std::string::npos) {
    ADD_FAILURE() << "no '" << label << "' in:\n" << text;
    return -1;
  }
  return std::atoll(text.c_str() + at + label.size());
}

std::size_t litPixels(const RgbaImage& image) {
  std::size_t lit = 0;
  for (std::size_t i = 0; i < image.pixels.size(); i += 4) {
    if (image.pixels[i] | image.pixels[i + 1] | image.pixels[i + 2]) ++lit;
  }
  return lit;
}

TEST(RenderCommandLod, DirectoryWithABudgetAboveTheCloudEqualsThePlainRender) {
  TempDir dir;
  const LodFiles files = generatedCloud(dir);
  // One camera for both (the default view frames a sample of the points, which differs); the
  // options after the input, which --target's list would otherwise take in.
  const std::string render = std::string(PARALLAX_EXECUTABLE) + " render ";
  const std::string options = " --width 160 --height 120 --eye=-130,-130,80 --target=0,10,0";
  ASSERT_EQ(runWithoutLeakCheck(render + quoted(files.ply) + options + " -o " +
                                quoted(dir / "plain.png") + " 2>" + quoted(dir / "plain.log")),
            0)
      << readText(dir / "plain.log");
  ASSERT_EQ(runWithoutLeakCheck(render + quoted(files.octree) + options + " --min-node-size 0 -o " +
                                quoted(dir / "lod.png") + " 2>" + quoted(dir / "lod.log")),
            0)
      << readText(dir / "lod.log");
  const std::string log = readText(dir / "lod.log");
  EXPECT_EQ(numberAfter(log, "drawn ("), 60000) << log;
  const RgbaImage plain = readPng(dir / "plain.png"), lod = readPng(dir / "lod.png");
  ASSERT_EQ(lod.width, 160);
  EXPECT_GT(litPixels(plain), 1000u);
  EXPECT_TRUE(plain.pixels == lod.pixels) << "the LOD render differs from the plain render";
}

TEST(RenderCommandLod, SmallBudgetDrawsAtMostTheBudgetInMonoAndStereo) {
  TempDir dir;
  const LodFiles files = generatedCloud(dir);
  for (const std::string stereo : {"mono", "sbs"}) {
    const auto log = dir / (stereo + ".log");
    ASSERT_EQ(
        runWithoutLeakCheck(std::string(PARALLAX_EXECUTABLE) + " render " + quoted(files.octree) +
                            " --budget 20000 --stereo " + stereo + " --width 128 --height 96 -o " +
                            quoted(dir / (stereo + ".png")) + " 2>" + quoted(log)),
        0)
        << readText(log);
    const std::string text = readText(log);
    const long long drawn = numberAfter(text, "drawn (");
    EXPECT_GT(drawn, 0) << text;
    EXPECT_LE(drawn, 20000) << text;
    EXPECT_EQ(numberAfter(text, "selected ("), drawn) << text;
    EXPECT_GT(litPixels(readPng(dir / (stereo + ".png"))), 300u) << stereo;
  }
}

TEST(RenderCommandLod, CameraPathOverADirectoryWritesEveryFrame) {
  TempDir dir;
  const LodFiles files = generatedCloud(dir);
  Camera a, b;
  a.lookAt({0, -300, 150}, {0, 0, 0}, {0, 0, 1});
  b.lookAt({300, 0, 150}, {0, 0, 0}, {0, 0, 1});
  dir.write("path.json", twoKeyframePath(a, b));
  ASSERT_EQ(
      runWithoutLeakCheck(std::string(PARALLAX_EXECUTABLE) + " render " + quoted(files.octree) +
                          " --budget 30000 --path " + quoted(dir / "path.json") +
                          " --frames 3 -o " + quoted(dir / "frames" / "f%d.png") +
                          " --width 48 --height 32 2>" + quoted(dir / "log")),
      0)
      << readText(dir / "log");
  for (int f = 0; f < 3; ++f) {
    std::string name = "f";  // appended: `"f" + std::to_string(f)` trips GCC 12's -Wrestrict
    name += std::to_string(f) + ".png";
    EXPECT_TRUE(std::filesystem::exists(dir / "frames" / name)) << f;
  }
  EXPECT_LE(numberAfter(readText(dir / "log"), "drawn ("), 30000) << readText(dir / "log");
}

TEST(RenderCommandLod, FileOverTheBudgetIsConvertedOnceIntoTheCache) {
  TempDir dir;
  const LodFiles files = generatedCloud(dir);
  // XDG_CACHE_HOME decides the cache folder; the second run finds the octree there.
  const std::string command = "XDG_CACHE_HOME=" + quoted(dir / "xdg") + " " + PARALLAX_EXECUTABLE +
                              " render " + quoted(files.ply) +
                              " --budget 30000 --width 128 --height 96 -o ";
  ASSERT_EQ(
      runWithoutLeakCheck(command + quoted(dir / "first.png") + " 2>" + quoted(dir / "first.log")),
      0)
      << readText(dir / "first.log");
  ASSERT_EQ(runWithoutLeakCheck(command + quoted(dir / "second.png") + " 2>" +
                                quoted(dir / "second.log")),
            0)
      << readText(dir / "second.log");
  const std::string first = readText(dir / "first.log"), second = readText(dir / "second.log");
  const std::string cache = (dir / "xdg" / "parallax" / "octrees").string();
  EXPECT_NE(
      first.find("60000 points, over the budget of 30000: converting to an octree in " + cache),
      std::string::npos)
      << first;
  EXPECT_NE(second.find("over the budget of 30000: using the octree in " + cache),
            std::string::npos)
      << second;
  EXPECT_EQ(second.find("converting"), std::string::npos) << second;
  EXPECT_LE(numberAfter(second, "drawn ("), 30000) << second;
  EXPECT_TRUE(readPng(dir / "first.png").pixels == readPng(dir / "second.png").pixels);

  // --cache-dir overrides it; --no-cache leaves nothing behind.
  ASSERT_EQ(runWithoutLeakCheck(std::string(PARALLAX_EXECUTABLE) + " render " + quoted(files.ply) +
                                " --budget 30000 --width 64 --height 48 --cache-dir " +
                                quoted(dir / "mine") + " -o " + quoted(dir / "mine.png") + " 2>" +
                                quoted(dir / "mine.log")),
            0)
      << readText(dir / "mine.log");
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir / "mine"), {}), 1);
  std::filesystem::create_directories(dir / "tmp");
  ASSERT_EQ(runWithoutLeakCheck("TMPDIR=" + quoted(dir / "tmp") + " " + PARALLAX_EXECUTABLE +
                                " render " + quoted(files.ply) +
                                " --budget 30000 --width 64 --height 48 --no-cache -o " +
                                quoted(dir / "none.png") + " 2>" + quoted(dir / "none.log")),
            0)
      << readText(dir / "none.log");
  EXPECT_TRUE(std::filesystem::exists(dir / "none.png"));
  EXPECT_NE(readText(dir / "none.log").find("converting to an octree in " + (dir / "tmp").string()),
            std::string::npos)
      << readText(dir / "none.log");
  EXPECT_TRUE(std::filesystem::is_empty(dir / "tmp")) << "--no-cache left its octree behind";
}

TEST(RenderCommandLod, TextFileOverTheBudgetGoesThroughTheOctree) {
  TempDir dir;
  const LodFiles files = generatedCloud(dir);
  const auto xyz = dir / "scan.xyz";
  ASSERT_EQ(runWithoutLeakCheck(std::string(PARALLAX_EXECUTABLE) + " convert -q " +
                                quoted(files.ply) + " -o " + quoted(xyz)),
            0);
  ASSERT_EQ(runWithoutLeakCheck(std::string(PARALLAX_EXECUTABLE) + " render " + quoted(xyz) +
                                " --budget 30000 --width 64 --height 48 --cache-dir " +
                                quoted(dir / "cache") + " -o " + quoted(dir / "text.png") + " 2>" +
                                quoted(dir / "text.log")),
            0)
      << readText(dir / "text.log");
  const std::string log = readText(dir / "text.log");
  EXPECT_NE(log.find("60000 points, over the budget of 30000: converting to an octree in " +
                     (dir / "cache").string()),
            std::string::npos)
      << log;
  EXPECT_LE(numberAfter(log, "drawn ("), 30000) << log;
  ASSERT_EQ(std::distance(std::filesystem::directory_iterator(dir / "cache"), {}), 1);
  const auto octree = std::filesystem::directory_iterator(dir / "cache")->path();
  EXPECT_EQ(nlohmann::json::parse(readText(octree / "metadata.json"))["points"], 60000);
}

TEST(RenderCommandLod, PreviewDrawsASampleOfTheBudget) {
  TempDir dir;
  const auto ply = dir / "scan.ply";
  ASSERT_EQ(runWithoutLeakCheck(std::string(PARALLAX_EXECUTABLE) + " generate --points 60000 -o " +
                                quoted(ply) + " > /dev/null 2>&1"),
            0);
  ASSERT_EQ(runWithoutLeakCheck(std::string(PARALLAX_EXECUTABLE) + " render " + quoted(ply) +
                                " --preview --budget 6000 --cache-dir " + quoted(dir / "cache") +
                                " --width 128 --height 96 -o " + quoted(dir / "preview.png") +
                                " 2>" + quoted(dir / "log")),
            0)
      << readText(dir / "log");
  const std::string log = readText(dir / "log");
  const long long sample = numberAfter(log, "preview, a sample of ");
  EXPECT_GE(sample, 5000) << log;
  EXPECT_LE(sample, 7000) << log;
  EXPECT_NE(log.find("of the file's 60000 points"), std::string::npos) << log;
  EXPECT_GT(litPixels(readPng(dir / "preview.png")), 300u);
  EXPECT_FALSE(std::filesystem::exists(dir / "cache")) << "--preview converted the file";
}

TEST(RenderCommandLod, HierarchyPointingPastOctreeBinIsAClearError) {
  TempDir dir;
  const LodFiles files = generatedCloud(dir);
  // The second hierarchy entry (node r0): its byte offset (bytes 6-13 of the 22) far past the end.
  std::fstream hierarchy(files.octree / "hierarchy.bin",
                         std::ios::in | std::ios::out | std::ios::binary);
  hierarchy.seekp(22 + 6);
  const std::uint64_t offset = 1'000'000'000;
  hierarchy.write(reinterpret_cast<const char*>(&offset), sizeof offset);
  hierarchy.close();
  const std::string command = std::string(PARALLAX_EXECUTABLE) + " render " + quoted(files.octree) +
                              " --min-node-size 0 -o " + quoted(dir / "out.png") + " 2>" +
                              quoted(dir / "log");
  EXPECT_EQ(runWithoutLeakCheck(command), 2);
  const std::string log = readText(dir / "log");
  EXPECT_NE(log.find("hierarchy.bin: byte offset 22, element 'node r0': expected a byte range "
                     "inside"),
            std::string::npos)
      << log;
  EXPECT_NE(log.find("found bytes 1000000000 to"), std::string::npos) << log;
  EXPECT_FALSE(std::filesystem::exists(dir / "out.png"));
}

}  // namespace
}  // namespace parallax::test
