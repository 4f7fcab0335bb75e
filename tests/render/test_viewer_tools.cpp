// The distance, height, area, angle and profile tools in a real window under Xvfb, driven with
// xdotool (as test_viewer_measure.cpp drives them against `parallax pick`), with oracles of their
// own: the clicks land on known points of a bowl the test writes (coordinates that are exact in
// float), at the pixels the test's own projection (support/reference_projection.h) gives them;
// the viewer must name exactly those points, print the length, height, area or angle the test
// computes from their coordinates, draw the overlay's markers and lines where that projection
// puts them, and export exactly the points a brute-force count puts within the profile's corridor.
//
// Needs the Debian packages xvfb and xdotool; skipped (with the reason) where they are missing.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "core/point_cloud.h"
#include "io/point_file.h"
#include "render/image_file.h"
#include "support/reference_projection.h"
#include "support/temp_dir.h"
#include "viewer_window_support.h"

namespace parallax::test {
namespace {

using namespace std::chrono_literals;

constexpr int kWidth = 640, kHeight = 400;
constexpr int kGrid = 41;  // points a side

// The bowl's point (i, j): x and y in steps of 1/16 around 0, z = (x² + y²) / 4, every value a
// multiple of 1/1024 and so exact in the PLY's floats and in double. Concave upwards: a chord
// between two of its points runs above it, so a measurement's lines are never hidden.
glm::dvec3 bowlPoint(int i, int j) {
  const double x = (i - kGrid / 2) / 16.0, y = (j - kGrid / 2) / 16.0;
  return {x, y, (x * x + y * y) / 4};
}

std::string bowlPly() {
  std::ostringstream ply;
  ply << "ply\nformat ascii 1.0\nelement vertex " << kGrid * kGrid
      << "\nproperty float x\nproperty float y\nproperty float z\nproperty uchar red\n"
         "property uchar green\nproperty uchar blue\nend_header\n";
  ply.precision(17);
  for (int j = 0; j < kGrid; ++j) {
    for (int i = 0; i < kGrid; ++i) {
      const glm::dvec3 p = bowlPoint(i, j);
      ply << p.x << ' ' << p.y << ' ' << p.z << " 90 90 90\n";
    }
  }
  return ply.str();
}

// The camera of every test, as the command line gives it and as the reference projection reads it.
const glm::dvec3 kEye{0.6, -3.0, 3.0}, kTarget{0.0, 0.0, 0.2};
constexpr double kFov = 40.0;

ReferenceView referenceView() {
  ReferenceView view;
  view.eye = kEye, view.target = kTarget, view.fov_y_deg = kFov;
  view.width = kWidth, view.height = kHeight;
  return view;
}

std::vector<std::string> lookOptions() {
  return {"--width",  "640",     "--height", "400", "--point-size", "5",    "--eye", "0.6,-3,3",
          "--target", "0,0,0.2", "--fov",    "40",  "--background", "0,0,0"};
}

// A pixel of the picture (top row 0), as xdotool clicks and screenshots count.
struct Pixel {
  int column = 0, row = 0;
};

Pixel pixelOf(const glm::dvec3& p) {
  const auto projected = referenceProject(referenceView(), p);
  EXPECT_TRUE(projected.has_value()) << p.x << " " << p.y << " " << p.z << " is out of view";
  if (!projected) return {};
  return {projected->column(), projected->row(kHeight)};
}

// The decimal numbers ("12.345678", "-0.5") on the first line of `log` that starts with
// `prefix` and holds `also`, after the prefix.
std::vector<double> numbersAfter(const std::string& log, const std::string& prefix,
                                 const std::string& also = "") {
  std::vector<double> numbers;
  std::istringstream lines(log);
  std::string line;
  while (std::getline(lines, line)) {
    if (line.starts_with(prefix) && line.find(also) != std::string::npos) break;
    line.clear();
  }
  if (line.empty()) return numbers;
  line = line.substr(prefix.size());
  // Every decimal number (-?digits.digits) left to right, as a regex search would find them;
  // by hand, since GCC 12 warns inside std::regex under the sanitizers (-Wmaybe-uninitialized).
  const auto digit = [&](std::size_t k) {
    return k < line.size() && std::isdigit(static_cast<unsigned char>(line[k]));
  };
  for (std::size_t i = 0; i < line.size();) {
    const std::size_t start = i;
    std::size_t k = line[i] == '-' ? i + 1 : i;
    const std::size_t whole = k;
    while (digit(k)) ++k;
    if (k > whole && k < line.size() && line[k] == '.' && digit(k + 1)) {
      ++k;
      while (digit(k)) ++k;
      numbers.push_back(std::stod(line.substr(start, k - start)));
      i = k;
    } else {
      i = std::max(k, start + 1);
    }
  }
  return numbers;
}

std::array<int, 3> colourAt(const RgbaImage& image, int column, int row) {
  const std::size_t i = (std::size_t(row) * std::size_t(image.width) + std::size_t(column)) * 4;
  return {image.pixels[i], image.pixels[i + 1], image.pixels[i + 2]};
}

void expectColour(const RgbaImage& image, int column, int row, const std::array<int, 3>& expected,
                  const std::string& what) {
  ASSERT_EQ(image.width, kWidth);
  ASSERT_EQ(image.height, kHeight);
  const auto got = colourAt(image, column, row);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(got[c], expected[c], 2) << what << " at " << column << "," << row << ": " << got[0]
                                        << " " << got[1] << " " << got[2];
  }
}

// The overlay of a finished (selected) measurement: an 11-pixel marker on each vertex and a
// 3-pixel line along each segment, in the kind's colour, where the reference projection puts
// them. Markers are looked at two pixels down-left of the vertex and lines a quarter of the way
// from their lower end: labels sit up and to the right of their anchors.
void expectOverlay(const RgbaImage& shot, const std::vector<glm::dvec3>& vertices, bool closed,
                   const std::array<int, 3>& colour) {
  std::vector<glm::dvec2> at;
  for (const glm::dvec3& v : vertices) {
    const auto projected = referenceProject(referenceView(), v);
    ASSERT_TRUE(projected.has_value());
    at.push_back({projected->window.x, kHeight - projected->window.y});  // y down, as rows
  }
  for (std::size_t i = 0; i < at.size(); ++i) {
    expectColour(shot, int(std::floor(at[i].x)) - 2, int(std::floor(at[i].y)) + 2, colour,
                 "marker " + std::to_string(i + 1));
  }
  const std::size_t segments = closed ? at.size() : at.size() - 1;
  for (std::size_t i = 0; i < segments; ++i) {
    glm::dvec2 from = at[i], to = at[(i + 1) % at.size()];
    const bool swap = std::abs(from.y - to.y) < 3 ? to.x < from.x : to.y > from.y;
    if (swap) std::swap(from, to);
    const glm::dvec2 q = from + 0.25 * (to - from);
    expectColour(shot, int(std::floor(q.x)), int(std::floor(q.y)), colour,
                 "line " + std::to_string(i + 1));
  }
}

// A viewer on the bowl with `tool`, the panel hidden.
class ToolSession {
 public:
  ToolSession(const std::string& tool, const std::vector<std::string>& extra = {})
      : cloud_(dir_.write("bowl.ply", bowlPly())), display_(dir_) {
    if (display_.name().empty()) return;
    std::vector<std::string> args = {cloud_.string(),    "--no-vsync",        "--tool", tool,
                                     "--screenshot-dir", dir_.path().string()};
    args.insert(args.end(), extra.begin(), extra.end());
    for (const std::string& option : lookOptions()) args.push_back(option);
    viewer_.emplace(dir_, display_.name(), args, "viewer.log");
  }
  // Fatal where the viewer did not come up.
  void start() {
    ASSERT_FALSE(display_.name().empty()) << "Xvfb did not start: " << readFile(dir_ / "xvfb.log");
    ASSERT_TRUE(viewer_->hasWindow()) << "no viewer window: " << viewer_->log();
    ASSERT_TRUE(viewer_->logged("parallax view: first picture after")) << viewer_->log();
    viewer_->key("g");
  }
  // Clicks each vertex's pixel from `first` on (those before it are already the measurement's);
  // the viewer must name exactly that point of the file.
  void clickVertices(const std::string& kind, const std::vector<glm::dvec3>& vertices,
                     std::size_t first = 0) {
    for (std::size_t i = first; i < vertices.size(); ++i) {
      const Pixel pixel = pixelOf(vertices[i]);
      ASSERT_GE(pixel.column, 10);
      ASSERT_LT(pixel.column, kWidth - 10);
      ASSERT_GE(pixel.row, 10);
      ASSERT_LT(pixel.row, kHeight - 10);
      viewer_->click(pixel.column, pixel.row);
      const std::string prefix =
          "parallax view: " + kind + " point " + std::to_string(i + 1) + ": ";
      ASSERT_TRUE(viewer_->logged(prefix)) << viewer_->log();
      const std::string log = viewer_->log();
      std::istringstream line(log.substr(log.find(prefix) + prefix.size()));
      double x = 0, y = 0, z = 0;
      line >> x >> y >> z;
      EXPECT_EQ(x, vertices[i].x) << kind << " point " << i + 1 << ": " << log;
      EXPECT_EQ(y, vertices[i].y) << kind << " point " << i + 1;
      EXPECT_EQ(z, vertices[i].z) << kind << " point " << i + 1;
    }
  }
  ViewerProcess& viewer() { return *viewer_; }
  const TempDir& dir() const { return dir_; }

 private:
  TempDir dir_;
  std::filesystem::path cloud_;
  Display display_;
  std::optional<ViewerProcess> viewer_;
};

bool haveXvfbAndXdotool() {
  return onPath("Xvfb") && onPath("xdotool");
}

// The measurement kinds' colours (measure/measurement_overlay.cpp), in 8 bits.
constexpr std::array<int, 3> kDistanceColour{255, 217, 26};
constexpr std::array<int, 3> kHeightColour{77, 255, 102};
constexpr std::array<int, 3> kAreaColour{77, 179, 255};
constexpr std::array<int, 3> kAngleColour{255, 128, 255};
constexpr std::array<int, 3> kProfileColour{255, 153, 51};

// Two clicks and Enter: the distance of the two points; Ctrl + E reopens it (the measurement just
// finished is the selected one), a third click extends the polyline and Enter gives the total.
TEST(ViewerTools, DistanceToolPrintsThePolylineOfKnownPointsAndDrawsIt) {
  if (!haveXvfbAndXdotool()) GTEST_SKIP() << "needs Xvfb and xdotool (Debian packages)";
  const std::vector<glm::dvec3> points = {bowlPoint(6, 8), bowlPoint(28, 14), bowlPoint(34, 32)};
  const auto length = [](const glm::dvec3& a, const glm::dvec3& b) {
    return std::sqrt((b.x - a.x) * (b.x - a.x) + (b.y - a.y) * (b.y - a.y) +
                     (b.z - a.z) * (b.z - a.z));
  };

  ToolSession session("distance");
  ASSERT_NO_FATAL_FAILURE(session.start());
  ViewerProcess& viewer = session.viewer();
  ASSERT_NO_FATAL_FAILURE(session.clickVertices("distance", {points[0], points[1]}));
  viewer.key("Return");
  ASSERT_TRUE(viewer.logged(" m (2 points)", 10s)) << viewer.log();
  auto values = numbersAfter(viewer.log(), "parallax view: distance ", " m (2 points)");
  ASSERT_EQ(values.size(), 1u) << viewer.log();
  EXPECT_NEAR(values[0], length(points[0], points[1]), 5e-7);

  viewer.key("ctrl+e");
  ASSERT_NO_FATAL_FAILURE(session.clickVertices("distance", points, 2));
  viewer.key("Return");
  ASSERT_TRUE(viewer.logged(" m (3 points)", 10s)) << viewer.log();
  values = numbersAfter(viewer.log(), "parallax view: distance ", " m (3 points)");
  ASSERT_EQ(values.size(), 1u) << viewer.log();
  EXPECT_NEAR(values[0], length(points[0], points[1]) + length(points[1], points[2]), 5e-7);
  expectOverlay(viewer.screenshot(session.dir().path()), points, false, kDistanceColour);
  EXPECT_EQ(viewer.quit(), 0) << viewer.log();
}

TEST(ViewerTools, HeightToolPrintsTheHeightOfTwoKnownPointsAndDrawsIt) {
  if (!haveXvfbAndXdotool()) GTEST_SKIP() << "needs Xvfb and xdotool (Debian packages)";
  const std::vector<glm::dvec3> points = {bowlPoint(4, 6), bowlPoint(30, 28)};
  const glm::dvec3 d = points[1] - points[0];
  const double dz = d.z, horizontal = std::sqrt(d.x * d.x + d.y * d.y);
  const double distance = std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
  ASSERT_GT(std::abs(dz), 0.1);

  ToolSession session("height");
  ASSERT_NO_FATAL_FAILURE(session.start());
  ASSERT_NO_FATAL_FAILURE(session.clickVertices("height", points));
  // Two points finish a height by themselves.
  ASSERT_TRUE(session.viewer().logged("parallax view: height difference ", 10s))
      << session.viewer().log();
  const auto values = numbersAfter(session.viewer().log(), "parallax view: height difference ");
  ASSERT_EQ(values.size(), 3u) << session.viewer().log();
  EXPECT_NEAR(values[0], dz, 5e-7);
  EXPECT_NEAR(values[1], horizontal, 5e-7);
  EXPECT_NEAR(values[2], distance, 5e-7);
  expectOverlay(session.viewer().screenshot(session.dir().path()), points, false, kHeightColour);
  EXPECT_EQ(session.viewer().quit(), 0) << session.viewer().log();
}

TEST(ViewerTools, AreaToolPrintsTheAreaOfAKnownPolygonAndDrawsIt) {
  if (!haveXvfbAndXdotool()) GTEST_SKIP() << "needs Xvfb and xdotool (Debian packages)";
  // On the bowl's side, so that it is tilted: its 3D area well above its map's.
  const std::vector<glm::dvec3> points = {bowlPoint(22, 4), bowlPoint(38, 6), bowlPoint(36, 22),
                                          bowlPoint(24, 20)};
  // The 3D area as the triangles of a fan from the first vertex (the vector area of a
  // non-planar polygon), the map's area as a sum of trapezoids, the closed perimeter.
  glm::dvec3 vector_area{0.0};
  for (std::size_t i = 1; i + 1 < points.size(); ++i) {
    vector_area += glm::cross(points[i] - points[0], points[i + 1] - points[0]) / 2.0;
  }
  double trapezoids = 0, perimeter = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const glm::dvec3& a = points[i];
    const glm::dvec3& b = points[(i + 1) % points.size()];
    trapezoids += (b.x - a.x) * (a.y + b.y) / 2;
    perimeter += glm::length(b - a);
  }
  const double area_3d = glm::length(vector_area), projected = std::abs(trapezoids);
  ASSERT_GT(area_3d, projected + 0.01) << "the polygon is not tilted";

  ToolSession session("area");
  ASSERT_NO_FATAL_FAILURE(session.start());
  ASSERT_NO_FATAL_FAILURE(session.clickVertices("area", points));
  session.viewer().key("Return");
  ASSERT_TRUE(session.viewer().logged("parallax view: area 3D ", 10s)) << session.viewer().log();
  const auto values = numbersAfter(session.viewer().log(), "parallax view: area 3D ");
  ASSERT_EQ(values.size(), 3u) << session.viewer().log();
  EXPECT_NEAR(values[0], area_3d, 5e-7);
  EXPECT_NEAR(values[1], projected, 5e-7);
  EXPECT_NEAR(values[2], perimeter, 5e-7);
  EXPECT_NE(session.viewer().log().find(" m (4 points)"), std::string::npos);
  expectOverlay(session.viewer().screenshot(session.dir().path()), points, true, kAreaColour);
  EXPECT_EQ(session.viewer().quit(), 0) << session.viewer().log();
}

TEST(ViewerTools, AngleToolPrintsTheAngleAtTheMiddlePointAndDrawsIt) {
  if (!haveXvfbAndXdotool()) GTEST_SKIP() << "needs Xvfb and xdotool (Debian packages)";
  // The vertex at the far side (up in the picture), the arms towards the viewer.
  const std::vector<glm::dvec3> points = {bowlPoint(6, 10), bowlPoint(20, 32), bowlPoint(34, 14)};
  const glm::dvec3 a = glm::normalize(points[0] - points[1]);
  const glm::dvec3 b = glm::normalize(points[2] - points[1]);
  const double degrees = std::acos(glm::dot(a, b)) * 180.0 / M_PI;

  ToolSession session("angle");
  ASSERT_NO_FATAL_FAILURE(session.start());
  ASSERT_NO_FATAL_FAILURE(session.clickVertices("angle", points));
  ASSERT_TRUE(session.viewer().logged("parallax view: angle ", 10s) &&
              session.viewer().logged(" degrees (3 points)", 10s))
      << session.viewer().log();
  const auto values = numbersAfter(session.viewer().log(), "parallax view: angle ", " degrees");
  ASSERT_EQ(values.size(), 1u) << session.viewer().log();
  EXPECT_NEAR(values[0], degrees, 5e-7);
  expectOverlay(session.viewer().screenshot(session.dir().path()), points, false, kAngleColour);
  EXPECT_EQ(session.viewer().quit(), 0) << session.viewer().log();
}

// The profile's corridor and its export: the CSV (Ctrl + X) holds exactly the points a brute-force
// count puts within half the width of the line, each once, and the LAS (Ctrl + Shift + X) the
// same points.
TEST(ViewerTools, ProfileExportHoldsExactlyThePointsOfItsCorridor) {
  if (!haveXvfbAndXdotool()) GTEST_SKIP() << "needs Xvfb and xdotool (Debian packages)";
  const int i0 = 5, j0 = 9, i1 = 35, j1 = 27;
  const std::vector<glm::dvec3> ends = {bowlPoint(i0, j0), bowlPoint(i1, j1)};
  // In whole grid steps, so that nothing is rounded: along = (p - a) . d must lie in
  // [0, |d|²] and the cross product's square at most (width / 2)² |d|², (width / 2 = 0.15 =
  // 2.4 steps). |d|² = 1224 is no multiple of 25: no point lies on the corridor's sides.
  const int dx = i1 - i0, dy = j1 - j0, length2 = dx * dx + dy * dy;
  std::set<std::tuple<double, double, double>> inside;
  for (int j = 0; j < kGrid; ++j) {
    for (int i = 0; i < kGrid; ++i) {
      const int along = (i - i0) * dx + (j - j0) * dy, across = dx * (j - j0) - dy * (i - i0);
      if (along >= 0 && along <= length2 && across * across * 25 <= 144 * length2) {
        const glm::dvec3 p = bowlPoint(i, j);
        inside.insert({p.x, p.y, p.z});
      }
    }
  }
  ASSERT_GT(inside.size(), 100u);

  ToolSession session("profile", {"--profile-width", "0.3"});
  ASSERT_NO_FATAL_FAILURE(session.start());
  ASSERT_NO_FATAL_FAILURE(session.clickVertices("profile", ends));
  ViewerProcess& viewer = session.viewer();
  viewer.key("Return");
  ASSERT_TRUE(viewer.logged("parallax view: profile of measurement 1: ", 10s)) << viewer.log();
  EXPECT_NE(viewer.log().find("parallax view: profile of measurement 1: " +
                              std::to_string(inside.size()) + " points from every point"),
            std::string::npos)
      << "expected " << inside.size() << " points: " << viewer.log();
  expectOverlay(viewer.screenshot(session.dir().path()), ends, false, kProfileColour);

  viewer.key("ctrl+x");
  const auto csv = session.dir() / "profile-1.csv";
  ASSERT_TRUE(viewer.logged("parallax view: profile written to " + csv.string())) << viewer.log();
  std::istringstream rows(readFile(csv));
  std::string row;
  std::getline(rows, row);
  EXPECT_EQ(row, "station,height,offset,x,y,z");
  std::set<std::tuple<double, double, double>> exported;
  std::size_t lines = 0;
  while (std::getline(rows, row)) {
    std::array<double, 6> v{};
    std::istringstream fields(row);
    for (double& value : v) {
      std::string field;
      std::getline(fields, field, ',');
      value = std::stod(field);
    }
    exported.insert({v[3], v[4], v[5]});
    ++lines;
    EXPECT_EQ(v[1], v[5]) << row;  // the height is z
  }
  EXPECT_EQ(lines, inside.size());
  EXPECT_EQ(exported, inside);
  for (const auto& [x, y, z] : inside) {
    EXPECT_TRUE(exported.count({x, y, z})) << "not exported: " << x << " " << y << " " << z;
  }

  viewer.key("ctrl+shift+x");
  const auto las = session.dir() / "profile-1.las";
  ASSERT_TRUE(viewer.logged("parallax view: profile written to " + las.string())) << viewer.log();
  const PointCloud saved = readPointFile(las);
  ASSERT_EQ(saved.count, inside.size());
  std::vector<std::array<double, 3>> read, expected;
  for (std::size_t k = 0; k < saved.count; ++k) {
    read.push_back({saved.worldX(k), saved.worldY(k), saved.worldZ(k)});
  }
  for (const auto& [x, y, z] : inside) expected.push_back({x, y, z});
  std::sort(read.begin(), read.end());
  for (std::size_t k = 0; k < read.size(); ++k) {
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(read[k][a], expected[k][a], 1e-3) << k;
  }
  EXPECT_EQ(viewer.quit(), 0) << viewer.log();
}

}  // namespace
}  // namespace parallax::test
