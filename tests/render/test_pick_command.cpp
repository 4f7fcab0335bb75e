// `parallax pick` end to end: the point it names at a pixel is the one a CPU projection (in
// double, written out in the test from the same --eye, --target and --fov:
// support/reference_projection.h, not the product's camera) puts in front there, with the file's
// exact coordinates (a LAS file at UTM scale, scale 0.001) and attribute values; in each eye of
// sbs stereo; on the same points as a Potree directory and as a COPC file; nothing on the
// background; clear errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "io/test_las_builder.h"
#include "support/reference_projection.h"
#include "support/run_parallax.h"
#include "support/temp_dir.h"

namespace parallax::test {
namespace {

constexpr double kScale = 0.001;
constexpr double kOffset[3] = {500000.0, 5000000.0, 100.0};
constexpr int kWidth = 160, kHeight = 120;
// The camera of every test, in the file's coordinates.
const glm::dvec3 kEye{500030.0, 4999985.0, 108.0}, kTarget{500000.0, 5000000.0, 100.0};
constexpr double kFov = 30.0;

// 4000 points in a 24 x 24 x 8 m box at UTM coordinates, every attribute a function of the
// point's index, so that a test knows what the file says about any point.
LasTestFile utmCloud() {
  LasTestFile file;
  file.format = 3;  // gps time and rgb
  for (int a = 0; a < 3; ++a) file.scale[a] = kScale, file.offset[a] = kOffset[a];
  std::mt19937 random(12);
  std::uniform_int_distribution<std::int32_t> horizontal(-12000, 12000), vertical(-4000, 4000);
  for (int i = 0; i < 4000; ++i) {
    LasTestPoint p;
    p.x = horizontal(random), p.y = horizontal(random), p.z = vertical(random);
    p.intensity = std::uint16_t(i * 7 + 3);
    p.return_number = std::uint8_t(1 + i % 3), p.number_of_returns = 3;
    p.classification = std::uint8_t(i % 10);
    p.scan_angle = std::int16_t(i % 60 - 30);
    p.user_data = std::uint8_t(i % 251);
    p.point_source_id = std::uint16_t(1000 + i);
    p.gps_time = 123456.0 + i * 0.25;
    p.red = std::uint16_t(i % 256), p.green = std::uint16_t(i * 3 % 256);
    p.blue = std::uint16_t(i * 7 % 256);
    file.points.push_back(p);
  }
  return file;
}

double world(const LasTestPoint& p, int axis) {
  const std::int32_t q = axis == 0 ? p.x : axis == 1 ? p.y : p.z;
  return double(q) * kScale + kOffset[axis];
}

// The picture of cameraArgs(): one view, or the two eyes of sbs stereo (the left half and the
// right half of the picture, each eye half the separation to its side).
std::vector<ReferenceView> monoViews() {
  ReferenceView view;
  view.eye = kEye, view.target = kTarget, view.up = {0, 0, 1}, view.fov_y_deg = kFov;
  view.width = kWidth, view.height = kHeight;
  return {view};
}

std::vector<ReferenceView> sideBySideViews(double separation, double convergence) {
  ReferenceView left = monoViews()[0];
  left.width = kWidth / 2;
  left.eye_offset = -separation / 2, left.convergence = convergence;
  ReferenceView right = left;
  right.x = kWidth / 2;
  right.eye_offset = separation / 2;
  return {left, right};
}

std::string cameraArgs() {
  return " --width " + std::to_string(kWidth) + " --height " + std::to_string(kHeight) +
         " --eye 500030,4999985,108 --target 500000,5000000,100 --up 0,0,1 --fov 30";
}

// A pixel (of the picture, top row 0) whose front-most point is certain: the point is well
// inside the pixel and clearly nearer than every other point that lands there or may (within
// 0.05 pixels of its edges, where the GPU's rounding may put it on either side).
struct ExpectedPick {
  int x = 0, y = 0;
  std::size_t point = 0;
  int view = 0;
  int candidates = 0;  // points that land in the pixel
};

std::vector<ExpectedPick> certainPixels(const LasTestFile& file,
                                        const std::vector<ReferenceView>& views) {
  std::vector<ExpectedPick> out;
  for (std::size_t v = 0; v < views.size(); ++v) {
    const ReferenceView& view = views[v];
    struct Hit {
      double depth;
      std::size_t point;
      bool sure;
    };
    std::map<std::pair<int, int>, std::vector<Hit>> pixels;
    for (std::size_t i = 0; i < file.points.size(); ++i) {
      const glm::dvec3 p{world(file.points[i], 0), world(file.points[i], 1),
                         world(file.points[i], 2)};
      const auto projected = referenceProject(view, p);
      if (!projected) continue;
      const double x = projected->window.x, y = projected->window.y;
      const double fx = x - std::floor(x), fy = y - std::floor(y);
      const bool sure = fx > 0.05 && fx < 0.95 && fy > 0.05 && fy < 0.95;
      for (double ox : {-0.05, 0.0, 0.05}) {
        for (double oy : {-0.05, 0.0, 0.05}) {
          const int px = int(std::floor(x + ox)), py = int(std::floor(y + oy));
          if (px < view.x || py < view.y || px >= view.x + view.width ||
              py >= view.y + view.height) {
            continue;
          }
          auto& hits = pixels[{px, py}];
          if (hits.empty() || hits.back().point != i) hits.push_back({projected->depth, i, sure});
        }
      }
    }
    for (auto& [pixel, hits] : pixels) {
      std::sort(hits.begin(), hits.end(),
                [](const Hit& a, const Hit& b) { return a.depth < b.depth; });
      if (!hits[0].sure) continue;
      if (hits.size() > 1 && hits[1].depth - hits[0].depth < 1e-3 * hits[0].depth) continue;
      ExpectedPick pick;
      pick.x = pixel.first, pick.y = kHeight - 1 - pixel.second;
      pick.point = hits[0].point;
      pick.view = int(v);
      pick.candidates = int(hits.size());
      out.push_back(pick);
    }
  }
  return out;
}

// Up to `n` certain pixels of a view, those with the most points behind the front one first.
std::vector<ExpectedPick> choose(std::vector<ExpectedPick> picks, int view, std::size_t n) {
  std::erase_if(picks, [&](const ExpectedPick& p) { return p.view != view; });
  std::stable_sort(picks.begin(), picks.end(), [](const ExpectedPick& a, const ExpectedPick& b) {
    return a.candidates > b.candidates;
  });
  if (picks.size() > n) picks.resize(n);
  return picks;
}

nlohmann::json pick(const TempDir& dir, const std::string& input, const std::string& args) {
  const RunResult run = runParallax(dir, "pick " + quoted(input) + args + " --json");
  EXPECT_EQ(run.exit_code, 0) << run.err;
  return nlohmann::json::parse(run.out);
}

// Every attribute the LAS file holds for point `p`, as pick names them.
void expectAttributes(const nlohmann::json& point, const LasTestPoint& p, bool exact_position) {
  for (int a = 0; a < 3; ++a) {
    const char* name = a == 0 ? "x" : a == 1 ? "y" : "z";
    if (exact_position) {
      EXPECT_EQ(point.at(name).get<double>(), world(p, a)) << name;
    } else {
      EXPECT_NEAR(point.at(name).get<double>(), world(p, a), 1e-6) << name;
    }
  }
  EXPECT_EQ(point.at("intensity"), p.intensity);
  EXPECT_EQ(point.at("classification"), p.classification);
  EXPECT_EQ(point.at("return_number"), p.return_number);
  EXPECT_EQ(point.at("number_of_returns"), p.number_of_returns);
  if (point.contains("scan_angle_rank")) {
    EXPECT_EQ(point.at("scan_angle_rank"), p.scan_angle);
  } else {  // COPC holds formats 6-8: the angle in steps of 0.006 degrees (LAS 1.4 R15, Table 16)
    EXPECT_EQ(point.at("scan_angle"), std::lround(p.scan_angle / 0.006));
  }
  EXPECT_EQ(point.at("user_data"), p.user_data);
  EXPECT_EQ(point.at("point_source_id"), p.point_source_id);
  EXPECT_EQ(point.at("gps_time").get<double>(), p.gps_time);
  EXPECT_EQ(point.at("red"), p.red);
  EXPECT_EQ(point.at("green"), p.green);
  EXPECT_EQ(point.at("blue"), p.blue);
}

std::string pixelArg(const ExpectedPick& p) {
  return " --pixel " + std::to_string(p.x) + "," + std::to_string(p.y);
}

// Picks the chosen pixels of `input` with `args` and checks each answer.
void expectPicks(const TempDir& dir, const std::string& input, const std::string& args,
                 const LasTestFile& file, const std::vector<ExpectedPick>& picks,
                 bool exact_position) {
  ASSERT_FALSE(picks.empty());
  for (const ExpectedPick& expected : picks) {
    SCOPED_TRACE("pixel " + std::to_string(expected.x) + "," + std::to_string(expected.y));
    const nlohmann::json answer = pick(dir, input, args + pixelArg(expected));
    ASSERT_TRUE(answer.at("found").get<bool>()) << answer.dump();
    EXPECT_EQ(answer.at("view"), expected.view);
    EXPECT_EQ(answer.at("distance_px"), 0.0);
    EXPECT_EQ(answer.at("pixel"), nlohmann::json({expected.x, expected.y}));
    expectAttributes(answer.at("point"), file.points[expected.point], exact_position);
  }
}

TEST(PickCommand, LasFileGivesTheFrontMostPointWithExactCoordinatesAndAttributes) {
  TempDir dir;
  const LasTestFile file = utmCloud();
  const auto las = dir.write("utm.las", makeLas(file));
  const auto picks = choose(certainPixels(file, monoViews()), 0, 4);
  ASSERT_GE(picks.size(), 4u);
  EXPECT_GE(picks.front().candidates, 2) << "no pixel where the front-most point matters";
  expectPicks(dir, las.string(), cameraArgs(), file, picks, true);
  // Drawn by GL_POINTS, the frame is drawn again by the compute rasterizer to know the point.
  expectPicks(dir, las.string(), cameraArgs() + " --rasterizer points", file,
              {picks.begin(), picks.begin() + 2}, true);
}

// With a filter, pick answers with the front-most point the filter keeps: a point the filter
// hides is never picked, even where it is the nearest.
TEST(PickCommand, APointTheFilterHidesIsNeverPicked) {
  TempDir dir;
  const LasTestFile file = utmCloud();
  const auto las = dir.write("utm.las", makeLas(file));
  LasTestFile kept = file;
  std::erase_if(kept.points, [](const LasTestPoint& p) { return p.return_number != 2; });
  const std::vector<ExpectedPick> whole = certainPixels(file, monoViews());
  std::vector<ExpectedPick> picks;
  for (const ExpectedPick& p : choose(certainPixels(kept, monoViews()), 0, 1000)) {
    // Pixels whose front-most point in the whole file is one the filter hides.
    const auto front = std::find_if(whole.begin(), whole.end(), [&](const ExpectedPick& w) {
      return w.x == p.x && w.y == p.y && w.view == p.view;
    });
    if (front != whole.end() && file.points[front->point].return_number != 2) picks.push_back(p);
    if (picks.size() == 4) break;
  }
  ASSERT_GE(picks.size(), 2u) << "no pixel where the filter hides the front-most point";
  expectPicks(dir, las.string(), cameraArgs() + " --returns 2", kept, picks, true);
}

TEST(PickCommand, EachEyeOfSideBySideStereo) {
  TempDir dir;
  const LasTestFile file = utmCloud();
  const auto las = dir.write("utm.las", makeLas(file));
  const std::string args = cameraArgs() + " --stereo sbs --eye-separation 2 --convergence 30";
  const auto all = certainPixels(file, sideBySideViews(2.0, 30.0));
  for (int view : {0, 1}) {
    SCOPED_TRACE("view " + std::to_string(view));
    expectPicks(dir, las.string(), args, file, choose(all, view, 2), true);
  }
}

TEST(PickCommand, PotreeDirectoryAndCopcFileGiveTheSamePoints) {
  TempDir dir;
  const LasTestFile file = utmCloud();
  const auto las = dir.write("utm.las", makeLas(file));
  const auto potree = dir / "potree", copc = dir / "utm.copc.laz";
  ASSERT_EQ(
      runParallax(dir, "convert -q " + quoted(las.string()) + " -o " + quoted(potree.string()))
          .exit_code,
      0);
  ASSERT_EQ(runParallax(dir, "convert -q " + quoted(las.string()) + " -o " + quoted(copc.string()))
                .exit_code,
            0);
  const auto picks = choose(certainPixels(file, monoViews()), 0, 2);
  // Every node drawn, however small on screen, so that all points compete as in the file.
  const std::string args = cameraArgs() + " --min-node-size 0";
  for (const auto& octree : {potree, copc}) {
    SCOPED_TRACE(octree.string());
    expectPicks(dir, octree.string(), args, file, picks, false);
  }
}

TEST(PickCommand, NearestPointWithinTheRadiusAndNothingOnTheBackground) {
  TempDir dir;
  LasTestFile file;
  file.format = 3;
  for (int a = 0; a < 3; ++a) file.scale[a] = kScale, file.offset[a] = kOffset[a];
  LasTestPoint p;  // one point near the target, so near the picture's centre
  p.x = 137, p.y = 59, p.z = 31;
  p.intensity = 77, p.classification = 6, p.point_source_id = 9, p.gps_time = 5.5;
  file.points.push_back(p);
  LasTestPoint far = p;  // a second one, to give the cloud an extent
  far.x = 2000, far.z = -4000, far.intensity = 1;
  file.points.push_back(far);
  const auto las = dir.write("two.las", makeLas(file));
  const auto picks = certainPixels(file, monoViews());
  const auto centre =
      std::find_if(picks.begin(), picks.end(), [](const ExpectedPick& e) { return e.point == 0; });
  ASSERT_NE(centre, picks.end());
  // Two pixels right of the point: found within the default radius of 3, at distance 2.
  const std::string beside =
      " --pixel " + std::to_string(centre->x + 2) + "," + std::to_string(centre->y);
  nlohmann::json answer = pick(dir, las.string(), cameraArgs() + beside);
  ASSERT_TRUE(answer.at("found").get<bool>()) << answer.dump();
  EXPECT_EQ(answer.at("distance_px"), 2.0);
  EXPECT_EQ(answer.at("point_pixel"), nlohmann::json({centre->x, centre->y}));
  EXPECT_EQ(answer.at("point").at("intensity"), 77);
  EXPECT_EQ(answer.at("point").at("x").get<double>(), world(p, 0));
  // Points of 12 pixels: the splat covers the pixel two to the right of its centre, which names
  // the point itself (distance 0), as the picture shows it.
  answer = pick(dir, las.string(), cameraArgs() + beside + " --point-size 12");
  ASSERT_TRUE(answer.at("found").get<bool>()) << answer.dump();
  EXPECT_EQ(answer.at("point").at("intensity"), 77);
  EXPECT_EQ(answer.at("distance_px"), 0.0);
  EXPECT_EQ(answer.at("point_pixel"), nlohmann::json({centre->x + 2, centre->y}));
  // --radius 1: too far.
  answer = pick(dir, las.string(), cameraArgs() + beside + " --radius 1");
  EXPECT_EQ(answer, nlohmann::json({{"found", false}}));
  // A corner of the picture: background, far from both points.
  answer = pick(dir, las.string(), cameraArgs() + " --pixel 0,0");
  EXPECT_EQ(answer, nlohmann::json({{"found", false}}));
  // The readable listing names the attributes.
  const RunResult text = runParallax(dir, "pick " + quoted(las.string()) + cameraArgs() + beside);
  EXPECT_EQ(text.exit_code, 0) << text.err;
  EXPECT_NE(text.out.find("intensity"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("500000"), std::string::npos) << text.out;
}

TEST(PickCommand, BadPixelIsAClearErrorNamingTheOption) {
  TempDir dir;
  LasTestFile file;
  file.points.resize(2);
  file.points[1].x = 100;
  const auto las = dir.write("small.las", makeLas(file));
  for (const std::string bad : {"12", "a,b", "3,4,5", "1.5,2", ""}) {
    SCOPED_TRACE(bad);
    const RunResult run = runParallax(
        dir, "pick " + quoted(las.string()) + " --width 64 --height 48 --pixel=" + quoted(bad));
    EXPECT_NE(run.exit_code, 0);
    EXPECT_NE(run.err.find("--pixel"), std::string::npos) << run.err;
  }
  for (const std::string outside : {"64,0", "0,48", "-1,3"}) {
    SCOPED_TRACE(outside);
    const RunResult run = runParallax(
        dir, "pick " + quoted(las.string()) + " --width 64 --height 48 --pixel=" + quoted(outside));
    EXPECT_NE(run.exit_code, 0);
    EXPECT_NE(run.err.find("--pixel " + outside + ": outside the 64x48 picture"), std::string::npos)
        << run.err;
  }
}

}  // namespace
}  // namespace parallax::test
