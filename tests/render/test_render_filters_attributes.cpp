// `parallax render --returns / --intensity / --elevation / --gps-time / --clip-polygon`, with both
// rasterizers: the picture of a file drawn through the filter equals, pixel for pixel, the
// picture of the points kept by hand (exact integer arithmetic on the scene's millimetres,
// microseconds and intensities) and written to a file first (filter_scene.h). The bounds lie
// half a step between the values the points have, at UTM coordinates and GPS times of 4e8 s a
// microsecond apart, where single floats could not decide: the shaders' tests must be exact.
#include <fstream>
#include <functional>

#include "filter_scene.h"

namespace parallax::test {
namespace {

using namespace filter_scene;

const std::array<double, 3> kUtm{500123.456, 5000456.789, 250.0};

class RenderAttributeFilters : public ::testing::TestWithParam<std::string> {
 protected:
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

  // The filtered render of the whole scene (as a PLY file, or as what `prepare` makes of it: an
  // octree) equals the render of the points `keep` accepts, and lights one pixel per kept point.
  void expectFilterMatches(
      const Scene& scene, const std::string& options, const std::function<bool(const Point&)>& keep,
      const std::function<std::filesystem::path(const std::filesystem::path&)>& prepare = {}) {
    std::vector<Point> kept;
    for (const Point& p : scene.points) {
      if (keep(p)) kept.push_back(p);
    }
    ASSERT_GT(kept.size(), 100u) << options;
    ASSERT_LT(kept.size(), scene.points.size()) << options;
    const auto all = dir_.write("all.ply", plyOf(scene.points, true, true));
    const auto cpu = dir_.write("kept.ply", plyOf(kept, true, true));
    const RgbaImage filtered = render(scene, prepare ? prepare(all) : all, options, "filtered");
    const RgbaImage expected = render(scene, cpu, "", "expected");
    expectSamePicture(filtered, expected, kept.size(), options);
  }

  TempDir dir_;
};

TEST_P(RenderAttributeFilters, ReturnKinds) {
  const Scene scene = makeScene(kUtm, true);
  expectFilterMatches(scene, "--returns first", [](const Point& p) { return p.ret == 1; });
  expectFilterMatches(scene, "--returns last", [](const Point& p) { return p.ret == p.returns; });
  expectFilterMatches(scene, "--returns intermediate,single", [](const Point& p) {
    return (p.ret > 1 && p.ret < p.returns) || p.returns == 1;
  });
}

TEST_P(RenderAttributeFilters, ReturnNumbersWithAKind) {
  const Scene scene = makeScene(kUtm, true);
  expectFilterMatches(scene, "--returns 2,3-3,last", [](const Point& p) {
    return p.ret == 2 || p.ret == 3 || p.ret == p.returns;
  });
}

TEST_P(RenderAttributeFilters, IntensityRangeIsInclusive) {
  const Scene scene = makeScene(kUtm, true);
  expectFilterMatches(scene, "--intensity 250,700",
                      [](const Point& p) { return p.intensity >= 250 && p.intensity <= 700; });
  // Bounds between whole intensities: rounded inwards, not to the nearest 16-bit step.
  expectFilterMatches(scene, "--intensity 100.5,899.5",
                      [](const Point& p) { return p.intensity >= 101 && p.intensity <= 899; });
}

TEST_P(RenderAttributeFilters, ElevationHalfAMillimetreFromPointsAtUtmCoordinates) {
  const Scene scene = makeScene(kUtm, true);
  const long long c = std::llround(kUtm[2] * 1000.0);
  // z from c - 200 mm to c + 300 mm, the bounds half a millimetre outside.
  expectFilterMatches(scene, "--elevation 249.7995,250.3005",
                      [&](const Point& p) { return p.mm[2] >= c - 200 && p.mm[2] <= c + 300; });
}

TEST_P(RenderAttributeFilters, GpsTimeToTheMicrosecondAt4e8Seconds) {
  const Scene scene = makeScene(kUtm, true);
  // From 20.0000015 s to 70.0000005 s past the base: points at whole microseconds 20000002 to
  // 70000000. One float relative to a chunk spanning 100 s steps by 7.6 us.
  expectFilterMatches(scene, "--gps-time 400000020.0000015,400000070.0000005",
                      [](const Point& p) { return p.gps_us >= 20000002 && p.gps_us <= 70000000; });
}

TEST_P(RenderAttributeFilters, EveryFilterTogether) {
  const Scene scene = makeScene(kUtm, true);
  expectFilterMatches(scene,
                      "--returns first --intensity 100,800 --gps-time 400000010,400000090 "
                      "--classes 1-9",
                      [](const Point& p) {
                        return p.ret == 1 && p.intensity >= 100 && p.intensity <= 800 &&
                               p.gps_us >= 10000000 && p.gps_us <= 90000000 && p.cls >= 1 &&
                               p.cls <= 9;
                      });
}

// The same filters on octrees made of the scene (Potree directory, COPC file): the nodes carry
// returns, intensity and GPS time, and the level-of-detail path filters them alike.
TEST_P(RenderAttributeFilters, OctreesFilterLikeTheFile) {
  const Scene scene = makeScene(kUtm, true);
  const auto keep = [](const Point& p) {
    return p.ret == p.returns && p.intensity >= 200 && p.gps_us >= 20000002 && p.gps_us <= 70000000;
  };
  const std::string options =
      "--returns last --intensity 199.5,1000 --gps-time 400000020.0000015,400000070.0000005";
  for (const std::string output : {"octree", "octree.copc.laz"}) {
    SCOPED_TRACE(output);
    expectFilterMatches(scene, options, keep, [&](const std::filesystem::path& ply) {
      const auto converted = dir_ / output;
      std::filesystem::remove_all(converted);
      const RunResult r = runParallax(
          dir_, "convert -q " + quoted(ply.string()) + " -o " + quoted(converted.string()));
      EXPECT_EQ(r.exit_code, 0) << r.err;
      return converted;
    });
  }
}

// A concave polygon (an L) at UTM coordinates, vertices on odd half millimetres: the hand test
// is the crossing number in exact integers (half millimetres), and the scene is checked to hold
// no point within 0.05 mm of an edge, where float and double may disagree.
struct HandPolygon {
  std::vector<std::array<long long, 2>> half_mm;  // relative to the scene's centre

  bool inside(const Point& p, const std::array<long long, 2>& c) const {
    const long long x = 2 * (p.mm[0] - c[0]), y = 2 * (p.mm[1] - c[1]);
    bool in = false;
    for (std::size_t i = 0, j = half_mm.size() - 1; i < half_mm.size(); j = i++) {
      const auto& a = half_mm[i];
      const auto& b = half_mm[j];
      if ((a[1] > y) == (b[1] > y)) continue;
      // x < (b.x - a.x) (y - a.y) / (b.y - a.y) + a.x, multiplied out by b.y - a.y.
      const long long lhs = (x - a[0]) * (b[1] - a[1]), rhs = (b[0] - a[0]) * (y - a[1]);
      if (b[1] > a[1] ? lhs < rhs : lhs > rhs) in = !in;
    }
    return in;
  }

  double distanceToEdges(const Point& p, const std::array<long long, 2>& c) const {
    const double x = double(2 * (p.mm[0] - c[0])), y = double(2 * (p.mm[1] - c[1]));
    double best = INFINITY;
    for (std::size_t i = 0, j = half_mm.size() - 1; i < half_mm.size(); j = i++) {
      const double ax = double(half_mm[i][0]), ay = double(half_mm[i][1]);
      const double dx = double(half_mm[j][0]) - ax, dy = double(half_mm[j][1]) - ay;
      const double t = std::clamp(((x - ax) * dx + (y - ay) * dy) / (dx * dx + dy * dy), 0.0, 1.0);
      best = std::min(best, std::hypot(x - ax - t * dx, y - ay - t * dy));
    }
    return best / 2.0;  // millimetres
  }

  // The GeoJSON of the polygon in world coordinates (a closed ring, as RFC 7946 wants).
  std::string geoJson(const std::array<long long, 2>& c) const {
    std::ostringstream json;
    json << R"({"type":"FeatureCollection","features":[{"type":"Feature","properties":{},)"
         << R"("geometry":{"type":"Polygon","coordinates":[[)";
    for (std::size_t i = 0; i <= half_mm.size(); ++i) {
      const auto& v = half_mm[i % half_mm.size()];
      json << (i ? "," : "") << '[';
      for (int a = 0; a < 2; ++a) {
        const long long tenths = (2 * c[std::size_t(a)] + v[std::size_t(a)]) * 5;  // 0.1 mm
        json << (a ? "," : "") << tenths / 10000 << '.' << std::setw(4) << std::setfill('0')
             << tenths % 10000 << std::setfill(' ');
      }
      json << ']';
    }
    json << "]]}}]}";
    return json.str();
  }
};

const HandPolygon kL{
    {{-3001, -2001}, {2999, -1601}, {3201, 401}, {-199, 601}, {1, 2599}, {-2801, 2401}}};

std::array<long long, 2> centreMm(const Scene& scene) {
  return {std::llround(scene.center[0] * 1000.0), std::llround(scene.center[1] * 1000.0)};
}

TEST_P(RenderAttributeFilters, ClipPolygonInsideAndOutsideAtUtmCoordinates) {
  const Scene scene = makeScene(kUtm, true);
  const auto c = centreMm(scene);
  for (const Point& p : scene.points) ASSERT_GT(kL.distanceToEdges(p, c), 0.05);
  const auto file = dir_.write("area.geojson", kL.geoJson(c));
  expectFilterMatches(scene, "--clip-polygon " + quoted(file.string()),
                      [&](const Point& p) { return kL.inside(p, c); });
  expectFilterMatches(scene, "--clip-polygon " + quoted(file.string()) + " --clip-mode outside",
                      [&](const Point& p) { return !kL.inside(p, c); });
}

TEST_P(RenderAttributeFilters, ClipPolygonBoundedInZByABox) {
  const Scene scene = makeScene(kUtm, true);
  const auto c = centreMm(scene);
  const auto file = dir_.write(
      "area.txt", "# the L\n" + [&] {
        // The same polygon as "x y" lines.
        std::string text;
        for (const auto& v : kL.half_mm) {
          std::ostringstream line;
          line << std::fixed << std::setprecision(4) << double(2 * c[0] + v[0]) / 2000.0 << ' '
               << double(2 * c[1] + v[1]) / 2000.0 << '\n';
          text += line.str();
        }
        return text;
      }());
  const long long z = std::llround(kUtm[2] * 1000.0);
  expectFilterMatches(
      scene,
      "--clip-polygon " + quoted(file.string()) + " --clip-box 0,0,249.8995,1e7,1e7,250.1005",
      [&](const Point& p) { return kL.inside(p, c) && p.mm[2] >= z - 100 && p.mm[2] <= z + 100; });
}

// --clip-mode highlight keeps every point and draws the region's half way to orange: the pixels
// of the points inside (those of the CPU-filtered render) change to the mix, every other pixel
// stays as the plain render has it.
TEST_P(RenderAttributeFilters, HighlightTintsThePolygonsPointsAndKeepsTheRest) {
  const Scene scene = makeScene(kUtm, true);
  const auto c = centreMm(scene);
  const auto file = dir_.write("area.geojson", kL.geoJson(c));
  std::vector<Point> inside;
  for (const Point& p : scene.points) {
    if (kL.inside(p, c)) inside.push_back(p);
  }
  ASSERT_GT(inside.size(), 100u);
  const auto all = dir_.write("all.ply", plyOf(scene.points, true, true));
  const auto kept = dir_.write("inside.ply", plyOf(inside, true, true));
  const RgbaImage plain = render(scene, all, "", "plain");
  const RgbaImage tinted = render(
      scene, all, "--clip-polygon " + quoted(file.string()) + " --clip-mode highlight", "tinted");
  const RgbaImage only_inside = render(scene, kept, "", "inside");
  const double tint[3] = {255.0, 0.25 * 255.0, 0.05 * 255.0};
  std::size_t changed = 0, unchanged_lit = 0;
  for (std::size_t i = 0; i < plain.pixels.size(); i += 4) {
    const bool in =
        (only_inside.pixels[i] | only_inside.pixels[i + 1] | only_inside.pixels[i + 2]) != 0;
    if (!in) {
      EXPECT_TRUE(std::equal(&plain.pixels[i], &plain.pixels[i] + 4, &tinted.pixels[i]))
          << "pixel " << i / 4 << " outside the polygon changed";
      unchanged_lit += (plain.pixels[i] | plain.pixels[i + 1] | plain.pixels[i + 2]) != 0;
      continue;
    }
    ++changed;
    for (int k = 0; k < 3; ++k) {
      const double expected = (double(plain.pixels[i + std::size_t(k)]) + tint[k]) / 2.0;
      EXPECT_NEAR(double(tinted.pixels[i + std::size_t(k)]), expected, 1.0)
          << "pixel " << i / 4 << " channel " << k;
    }
  }
  EXPECT_EQ(changed, inside.size());
  EXPECT_EQ(unchanged_lit, scene.points.size() - inside.size());
}

TEST_P(RenderAttributeFilters, BadValuesAndPolygonFilesAreClearErrors) {
  const Scene scene = makeScene({10.0, 20.0, 5.0}, true);
  const auto all = dir_.write("all.ply", plyOf(scene.points, true, true));
  const auto bad_polygon = dir_.write("bad.txt", "0 0\n1 0\n1 one\n");
  std::string big;
  for (int i = 0; i < 300; ++i) {
    big += std::to_string(std::cos(i * 0.021)) + " " + std::to_string(std::sin(i * 0.021)) + "\n";
  }
  const auto big_polygon = dir_.write("big.txt", big);
  // Bad option values exit with 1, a bad file with 2 (as every input error).
  struct Case {
    std::string options, message;
    int exit_code;
  };
  for (const auto& [options, message, exit_code] : std::vector<Case>{
           {"--returns first,lastt", "--returns: item 'lastt' is not a return", 1},
           {"--returns 0", "--returns: item '0' is not a return", 1},
           {"--returns 3-2", "--returns: item '3-2' is not a range", 1},
           {"--intensity 5", "--intensity: expected two numbers MIN,MAX, found 1 items in '5'", 1},
           {"--elevation 10,2", "--elevation: MIN '10' is greater than MAX '2'", 1},
           {"--gps-time 1,x", "--gps-time: MAX 'x' is not a number", 1},
           {"--clip-mode outside", "--clip-mode: needs a region", 1},
           {"--clip-box 0,0,0,1,1,1 --clip-mode tint",
            "--clip-mode: unknown mode 'tint' (use inside|outside|highlight)", 1},
           {"--clip-polygon " + quoted(big_polygon.string()),
            "has 300 vertices; the shaders take at most 256", 1},
           {"--clip-polygon " + quoted(bad_polygon.string()),
            bad_polygon.string() + ": line 3, element 'vertex': expected a vertex 'x y'", 2},
           {"--clip-polygon " + quoted((dir_ / "none.geojson").string()), "none.geojson", 2}}) {
    const RunResult r = runParallax(dir_, "render " + quoted(all.string()) + " -o " +
                                              quoted((dir_ / "bad.png").string()) +
                                              " --rasterizer " + GetParam() + " " + options);
    EXPECT_EQ(r.exit_code, exit_code) << options;
    EXPECT_NE(r.err.find(message), std::string::npos) << options << "\n" << r.err;
    EXPECT_FALSE(std::filesystem::exists(dir_ / "bad.png")) << options;
  }
}

INSTANTIATE_TEST_SUITE_P(BothRasterizers, RenderAttributeFilters,
                         ::testing::Values("points", "compute"));

}  // namespace
}  // namespace parallax::test
