// `parallax render --classes / --clip-box / --clip-mode`, with both rasterizers: the picture of a
// file drawn through the filter equals, pixel for pixel, the picture of the points the filter
// keeps, chosen on the CPU (by hand, in millimetres) and written to a file first. The points are
// placed one to a pixel, away from pixel edges, so that every kept point lights exactly one pixel
// of its own colour: the pictures must be equal, and the lit pixels are counted too. A cloud at
// UTM coordinates (~500 000, 5 000 000) with box faces half a millimetre from points shows that
// the clip planes keep double precision (float world coordinates there are good to 0.5 m).
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
    return readPng(png);
  }

  // The filtered render of the whole scene equals the render of the hand-filtered points, and
  // lights one pixel per kept point.
  void expectFilterMatches(const Scene& scene, const std::string& options, const HandFilter& f) {
    const std::vector<Point> kept = f.of(scene.points);
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
           {"--clip-box 1,1,1,0,2,2", "--clip-box: XMIN '1' is greater than XMAX '0'"}}) {
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
