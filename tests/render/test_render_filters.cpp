// `parallax render --classes / --clip-box / --clip-mode`, with both rasterizers: the picture of a
// file drawn through the filter equals, pixel for pixel, the picture of the points the filter
// keeps, chosen on the CPU (by hand, in millimetres) and written to a file first. The points are
// placed one to a pixel, away from pixel edges, so that every kept point lights exactly one pixel
// of its own colour: the pictures must be equal, and the lit pixels are counted too. A cloud at
// UTM coordinates (~500 000, 5 000 000) with box faces half a millimetre from points shows that
// the clip planes keep double precision (float world coordinates there are good to 0.5 m).
#include <numbers>

#include "filter_scene.h"

namespace parallax::test {
namespace {

using namespace filter_scene;

// The filter by hand: classes (empty: all) and a box in millimetres, inclusive.
struct HandFilter {
  std::vector<int> classes;
  bool box = false, outside = false;
  long long min[3] = {0, 0, 0}, max[3] = {0, 0, 0};

  std::vector<Point> of(const std::vector<Point>& all) const {
    std::vector<Point> kept;
    for (const Point& p : all) {
      if (!classes.empty() && std::find(classes.begin(), classes.end(), p.cls) == classes.end()) {
        continue;
      }
      bool inside = true;
      for (int a = 0; a < 3; ++a) inside = inside && p.mm[a] >= min[a] && p.mm[a] <= max[a];
      if (box && inside == outside) continue;
      kept.push_back(p);
    }
    return kept;
  }
};

// A box over the middle of the scene whose faces lie half a millimetre off the grid: the
// option's text and the same box in whole millimetres.
std::pair<std::string, HandFilter> middleBox(const Scene& scene, bool outside) {
  HandFilter f;
  f.box = true, f.outside = outside;
  const long long lo[3] = {-1200, -700, -300}, hi[3] = {900, 800, 250};
  std::ostringstream option;
  option << "--clip-box ";
  for (int end = 0; end < 2; ++end) {
    for (int a = 0; a < 3; ++a) {
      const long long c = std::llround(scene.center[std::size_t(a)] * 1000.0);
      // The face at c + offset - 0.5 mm (min) or + 0.5 mm (max): the points inside are those
      // from c + lo to c + hi, whole millimetres.
      const long long mm = c + (end == 0 ? lo[a] : hi[a]);
      const long long half_mm_units = mm * 10 + (end == 0 ? -5 : 5);  // tenths of a millimetre
      option << (end || a ? "," : "") << half_mm_units / 10000 << '.' << std::setw(4)
             << std::setfill('0') << half_mm_units % 10000 << std::setfill(' ');
      (end == 0 ? f.min : f.max)[a] = mm;
    }
  }
  if (outside) option << " --clip-mode outside";
  return {option.str(), f};
}

// Tenths of a millimetre as metres: "500123.4565".
std::string metresOfTenths(long long tenths) {
  std::ostringstream text;
  text << (tenths < 0 ? "-" : "") << std::llabs(tenths) / 10000 << '.' << std::setw(4)
       << std::setfill('0') << std::llabs(tenths) % 10000;
  return text.str();
}

// A box turned by `yaw` degrees about its centre, in tenths of a millimetre from the scene's
// centre (faces at half millimetres); the points it keeps found in double from the millimetre
// grid, each at least 0.01 mm from every face (else the scene cannot tell a float test from a
// double one, and the test says so).
struct TurnedBox {
  long long lo[3], hi[3];  // tenths of a millimetre from the scene's centre
  double yaw;

  std::string option(const Scene& scene) const {
    std::string text = "--clip-box ";
    for (int end = 0; end < 2; ++end) {
      for (int a = 0; a < 3; ++a) {
        const long long centre = std::llround(scene.center[std::size_t(a)] * 10000.0);
        if (end || a) text += ',';
        text += metresOfTenths(centre + (end ? hi[a] : lo[a]));
      }
    }
    std::ostringstream yaw_text;
    yaw_text << std::setprecision(17) << yaw;
    return text + "," + yaw_text.str();
  }

  std::vector<Point> of(const Scene& scene, const std::vector<Point>& all) const {
    const double radians = yaw * std::numbers::pi / 180.0;
    const double cs = std::cos(radians), sn = std::sin(radians);
    const double cu = 0.05 * double(lo[0] + hi[0]), cv = 0.05 * double(lo[1] + hi[1]);  // mm
    const double hu = 0.05 * double(hi[0] - lo[0]), hv = 0.05 * double(hi[1] - lo[1]);
    std::vector<Point> kept;
    for (const Point& p : all) {
      double rel[3];
      for (int a = 0; a < 3; ++a) {
        rel[a] = double(p.mm[a] - std::llround(scene.center[std::size_t(a)] * 1000.0));
      }
      const double u = cs * (rel[0] - cu) + sn * (rel[1] - cv);
      const double v = -sn * (rel[0] - cu) + cs * (rel[1] - cv);
      EXPECT_GT(std::min(std::abs(hu - std::abs(u)), std::abs(hv - std::abs(v))), 0.01)
          << "a point lies on a face of the turned box: choose another box";
      if (std::abs(u) <= hu && std::abs(v) <= hv && rel[2] * 10.0 >= double(lo[2]) &&
          rel[2] * 10.0 <= double(hi[2])) {
        kept.push_back(p);
      }
    }
    return kept;
  }
};

class RenderFilters : public ::testing::TestWithParam<std::string> {
 protected:
  // Renders `ply` with the scene's camera and `options`; the picture.
  RgbaImage render(const Scene& scene, const std::filesystem::path& ply, const std::string& options,
                   const std::string& name) {
    const auto png = dir_ / (name + ".png");
    const RunResult r = runParallax(
        dir_, "render " + quoted(ply.string()) + " -o " + quoted(png.string()) + " --width " +
                  std::to_string(kWidth) + " --height " + std::to_string(kHeight) +
                  " --rasterizer " + GetParam() + " " + scene.cameraOptions() + " " + options);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    // The rasterizer asked for drew (none falls back silently).
    EXPECT_NE(r.err.find("parallax render: rasterizer " + GetParam()), std::string::npos) << r.err;
    return readPng(png);
  }

  // The filtered render of the whole scene equals the render of the hand-filtered points, and
  // lights one pixel per kept point.
  void expectFilterMatches(const Scene& scene, const std::string& options, const HandFilter& f) {
    expectFilterKeeps(scene, options, f.of(scene.points));
  }
  void expectFilterKeeps(const Scene& scene, const std::string& options,
                         const std::vector<Point>& kept) {
    ASSERT_GT(kept.size(), 100u) << options;
    ASSERT_LT(kept.size(), scene.points.size()) << options;
    const auto all = dir_.write("all.ply", plyOf(scene.points, scene.classified));
    const auto cpu = dir_.write("kept.ply", plyOf(kept, scene.classified));
    const RgbaImage filtered = render(scene, all, options, "filtered");
    const RgbaImage expected = render(scene, cpu, "", "expected");
    expectSamePicture(filtered, expected, kept.size(), options);
  }

  TempDir dir_;
};

TEST_P(RenderFilters, ClassesEqualTheCpuFilteredRender) {
  const Scene scene = makeScene({10.0, 20.0, 5.0}, true);
  expectFilterMatches(scene, "--classes 2,6,9-12", {.classes = {2, 6, 9, 10, 11, 12}});
}

TEST_P(RenderFilters, ClassesAtUtmCoordinates) {
  const Scene scene = makeScene({500123.456, 5000456.789, 250.0}, true);
  expectFilterMatches(scene, "--classes 0-3,7", {.classes = {0, 1, 2, 3, 7}});
}

TEST_P(RenderFilters, ClipBoxInsideAtUtmCoordinatesKeepsHalfMillimetrePrecision) {
  const Scene scene = makeScene({500123.456, 5000456.789, 250.0}, true);
  const auto [option, filter] = middleBox(scene, false);
  expectFilterMatches(scene, option, filter);
}

TEST_P(RenderFilters, ClipBoxOutsideAtUtmCoordinatesHidesTheBoxContent) {
  const Scene scene = makeScene({500123.456, 5000456.789, 250.0}, true);
  const auto [option, filter] = middleBox(scene, true);
  expectFilterMatches(scene, option, filter);
}

TEST_P(RenderFilters, ClassesAndClipBoxOutsideTogether) {
  const Scene scene = makeScene({10.0, 20.0, 5.0}, true);
  auto [option, filter] = middleBox(scene, true);
  filter.classes = {1, 2, 5};
  expectFilterMatches(scene, option + " --classes 1,2,5", filter);
}

// A box turned 35 degrees about its centre (what the viewer's "turn" sets): the GPU's float
// planes keep what the CPU keeps in double, at UTM coordinates; inside and outside.
TEST_P(RenderFilters, TurnedClipBoxAtUtmCoordinates) {
  const Scene scene = makeScene({500123.456, 5000456.789, 250.0}, true);
  const TurnedBox box{{-13005, -6505, -3005}, {11005, 7505, 2505}, 35.0};
  const std::vector<Point> inside = box.of(scene, scene.points);
  expectFilterKeeps(scene, box.option(scene), inside);
  std::vector<Point> outside;
  for (const Point& p : scene.points) {
    const bool in = std::any_of(inside.begin(), inside.end(), [&](const Point& q) {
      return std::equal(std::begin(p.mm), std::end(p.mm), std::begin(q.mm));
    });
    if (!in) outside.push_back(p);
  }
  expectFilterKeeps(scene, box.option(scene) + " --clip-mode outside", outside);
}

// A file without classification is class 0 to the filter (the GPU buffers hold 1 there, what
// the classification colour shows).
TEST_P(RenderFilters, WithoutClassificationEveryPointIsClassZero) {
  const Scene scene = makeScene({10.0, 20.0, 5.0}, false);
  const auto all = dir_.write("all.ply", plyOf(scene.points, false));
  const RgbaImage none = render(scene, all, "--classes 1-255", "none");
  std::size_t lit = 0;
  for (std::size_t i = 0; i < none.pixels.size(); i += 4) {
    lit += (none.pixels[i] | none.pixels[i + 1] | none.pixels[i + 2]) != 0;
  }
  EXPECT_EQ(lit, 0u);
  const RgbaImage every = render(scene, all, "--classes 0", "every");
  const RgbaImage plain = render(scene, all, "", "plain");
  EXPECT_EQ(every.pixels, plain.pixels);
}

TEST_P(RenderFilters, MalformedListsAreClearErrors) {
  const Scene scene = makeScene({10.0, 20.0, 5.0}, true);
  const auto all = dir_.write("all.ply", plyOf(scene.points, true));
  for (const auto& [options, message] : std::vector<std::pair<std::string, std::string>>{
           {"--classes 2,6,x", "--classes: item 'x' is not a class"},
           {"--classes 12-9", "--classes: range '12-9' runs backwards"},
           {"--clip-box 1,1,1,0,2,2", "--clip-box: XMIN '1' is greater than XMAX '0'"},
           {"--clip-box 0,0,0,1,1,1,north", "--clip-box: YAW 'north' is not a number"},
           {"--clip-box 0,0,0,1,1,1,30,2", "and optionally a seventh, YAW, found 8 items"}}) {
    const RunResult r = runParallax(dir_, "render " + quoted(all.string()) + " -o " +
                                              quoted((dir_ / "bad.png").string()) +
                                              " --rasterizer " + GetParam() + " " + options);
    EXPECT_NE(r.exit_code, 0) << options;
    EXPECT_NE(r.err.find(message), std::string::npos) << options << "\n" << r.err;
  }
}

INSTANTIATE_TEST_SUITE_P(BothRasterizers, RenderFilters, ::testing::Values("points", "compute"));

}  // namespace
}  // namespace parallax::test
