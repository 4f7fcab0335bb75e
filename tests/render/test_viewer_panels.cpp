// The terrain issue's panels in a real window under Xvfb, driven with xdotool.
//
// The registration panel's point-pairs picking: two copies of a scan, one moved by a known rigid
// transform; a wrong click taken back (Backspace), then three pairs clicked at the pixels the
// test's own projection (support/reference_projection.h) gives their points, in the viewer's
// default look (adaptive round points). The viewer must name exactly the clicked points, label
// the first pair on both clouds, fit the known transform from them, refine it by ICP (Enter) and
// write it (Ctrl + T) as `register --init` reads it.
//
// M3C2 distances through the diverging ramp, with the legend over the window: the same oracle as
// `render --legend`'s test (signed_legend_scene.h).
//
// The Volume tool (measurement panel): an area drawn around a cone pile on a sloped base, Ctrl + V:
// the cone's closed-form volume, and what `parallax volume` gives for the same polygon; the same
// over a base raster of the slope (`view --volume-base DEM.tif`), and the error once it is gone.
//
// The raster layer (`view CLOUD --raster DEM.tif`): each cell's colour at its projected centre,
// the same oracle as `render --raster`'s test (tests/raster/raster_plane_scene.h).
//
// Needs the Debian packages xvfb and xdotool; skipped (with the reason) where they are missing.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "raster/geotiff.h"
#include "raster/raster_plane_scene.h"
#include "raster/volume_piles.h"
#include "registration/rigid_transform.h"
#include "signed_legend_scene.h"
#include "support/reference_projection.h"
#include "support/temp_dir.h"
#include "viewer_window_support.h"

namespace parallax::test {
namespace {

using namespace std::chrono_literals;

constexpr int kRegWidth = 640, kRegHeight = 400;
constexpr int kRegGrid = 25;  // points a side

// The picked points: three survey targets standing 0.08 above the surface at grid (i, j), nearer
// the camera than every neighbour (a click on one picks it, whatever its neighbours' splats
// cover), and not on one line.
constexpr std::array<std::array<int, 2>, 3> kSurveyTargets{{{4, 4}, {20, 6}, {12, 20}}};

bool isSurveyTarget(int i, int j) {
  for (const auto& t : kSurveyTargets) {
    if (t[0] == i && t[1] == j) return true;
  }
  return false;
}

// A saddle over [-0.75, 0.75]² in steps of 1/16 (curved both ways: ICP has every direction
// fixed), with the survey targets raised.
std::array<double, 3> scanPoint(int i, int j) {
  const double x = (i - kRegGrid / 2) / 16.0, y = (j - kRegGrid / 2) / 16.0;
  return {x, y, 0.12 * (x * x - y * y) + (isSurveyTarget(i, j) ? 0.08 : 0.0)};
}

// The scan moved by `motion`, as a PLY of doubles (17 digits: the file holds the moved values).
std::string scanPly(const RigidTransform& motion) {
  std::ostringstream ply;
  ply << "ply\nformat ascii 1.0\nelement vertex " << kRegGrid * kRegGrid
      << "\nproperty double x\nproperty double y\nproperty double z\nend_header\n";
  ply.precision(17);
  for (int j = 0; j < kRegGrid; ++j) {
    for (int i = 0; i < kRegGrid; ++i) {
      const auto p = motion.apply(scanPoint(i, j));
      ply << p[0] << ' ' << p[1] << ' ' << p[2] << '\n';
    }
  }
  return ply.str();
}

// The camera, as the command line gives it and as the reference projection reads it: from above,
// about 20 degrees off the vertical, both clouds in view (the copy beside the scan and above it,
// so that the first pair's labels are in plain view: a label behind points is drawn faded).
ReferenceView registrationView() {
  ReferenceView view;
  view.eye = {0.75, -1.2, 3.35}, view.target = {0.45, 0.0, 0.15}, view.fov_y_deg = 40.0;
  view.width = kRegWidth, view.height = kRegHeight;
  return view;
}

std::vector<std::string> registrationCamera() {
  return {"--width",        "640",      "--height",    "400",   "--eye",
          "0.75,-1.2,3.35", "--target", "0.45,0,0.15", "--fov", "40"};
}

// The numbers after `prefix` on the first line of `log` that starts with it.
std::vector<double> loggedNumbers(const std::string& log, const std::string& prefix) {
  std::vector<double> numbers;
  const auto at = log.find(prefix);
  if (at == std::string::npos) return numbers;
  std::istringstream line(log.substr(at + prefix.size(), log.find('\n', at) - at - prefix.size()));
  for (double value = 0; line >> value;) numbers.push_back(value);
  return numbers;
}

void expectTransformNear(const std::vector<double>& rows, const RigidTransform& expected,
                         double tolerance, const std::string& what) {
  ASSERT_EQ(rows.size(), 12u) << what;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 4; ++c) {
      EXPECT_NEAR(rows[std::size_t(r * 4 + c)], expected.m[std::size_t(r)][std::size_t(c)],
                  tolerance)
          << what << " row " << r << " column " << c;
    }
  }
}

// Three pairs clicked on a scan and its copy moved by a known turn (12 degrees about a tilted
// axis) and shift (0.9 sideways, 0.3 up: they overlap in part, the copy in front): the pairs'
// fit is that motion, ICP from it keeps it, Ctrl + T writes it.
TEST(ViewerWindow, PointPairsPickedOnTwoCopiesGiveTheirMotionBack) {
  if (!onPath("Xvfb") || !onPath("xdotool")) {
    GTEST_SKIP() << "needs Xvfb and xdotool (Debian packages xvfb, xdotool)";
  }
  TempDir dir;
  const RigidTransform motion =
      RigidTransform::translation(0.9, 0.05, 0.3) * RigidTransform::rotation(0.2, 0.3, 1, 12);
  const auto source = dir.write("source.ply", scanPly(RigidTransform{}));
  const auto target = dir.write("target.ply", scanPly(motion));
  const auto written = dir / "source-to-target.txt";

  Display display(dir);
  ASSERT_FALSE(display.name().empty()) << "Xvfb did not start: " << readFile(dir / "xvfb.log");
  std::vector<std::string> args = {source.string(),  "--no-vsync",       "--register-with",
                                   target.string(),  "--pick-pairs",     "--write-transform",
                                   written.string(), "--screenshot-dir", dir.path().string()};
  const auto camera = registrationCamera();
  args.insert(args.end(), camera.begin(), camera.end());
  ViewerProcess viewer(dir, display.name(), args, "viewer.log");
  ASSERT_TRUE(viewer.hasWindow()) << "no viewer window: " << viewer.log();
  ASSERT_TRUE(viewer.logged("parallax view: pick pairs: ")) << viewer.log();
  viewer.key("g");  // the panel off the picture

  const auto pixelOfPoint = [&](const std::array<double, 3>& p) {
    const auto projected = referenceProject(registrationView(), {p[0], p[1], p[2]});
    EXPECT_TRUE(projected.has_value()) << p[0] << " " << p[1] << " " << p[2] << " out of view";
    return projected ? std::array<int, 2>{projected->column(), projected->row(kRegHeight)}
                     : std::array<int, 2>{0, 0};
  };
  const auto click = [&](const std::array<double, 3>& p) {
    const auto [column, row] = pixelOfPoint(p);
    viewer.click(column, row);
  };
  // The labels' white (the clouds are orange and blue on black): near-white pixels in the box up
  // and right of `at` where a label's text sits, or in the whole picture.
  const auto whitePixels = [](const RgbaImage& image, std::array<int, 2> at, int reach) {
    int count = 0;
    for (int y = std::max(at[1] - reach, 0); y <= std::min(at[1] + 4, image.height - 1); ++y) {
      for (int x = std::max(at[0] - 4, 0); x <= std::min(at[0] + reach, image.width - 1); ++x) {
        const std::uint8_t* c = &image.pixels[(std::size_t(y) * image.width + x) * 4];
        count += c[0] >= 230 && c[1] >= 230 && c[2] >= 230;
      }
    }
    return count;
  };
  const std::array<int, 2> middle{kRegWidth / 2, kRegHeight / 2};
  // (One screenshot each: the key that asks for it is taken after the frame of the last input.)
  EXPECT_EQ(whitePixels(viewer.screenshot(dir.path()), middle, kRegWidth), 0)
      << "white before any label";
  // A wrong first click (a point of the surface), taken back with Backspace: the next click is
  // the source's again.
  ASSERT_NO_FATAL_FAILURE(click(scanPoint(8, 14)));
  ASSERT_TRUE(viewer.logged("parallax view: pair 1 source point: ")) << viewer.log();
  viewer.key("BackSpace");
  ASSERT_TRUE(viewer.logged("parallax view: pairs: removed the source point of pair 1"))
      << viewer.log();
  const std::size_t undone = viewer.log().size();
  const auto logAfterUndo = [&] { return viewer.log().substr(undone); };
  for (std::size_t k = 0; k < kSurveyTargets.size(); ++k) {
    const auto p = scanPoint(kSurveyTargets[k][0], kSurveyTargets[k][1]);
    const auto q = motion.apply(p);
    const std::string pair = "parallax view: pair " + std::to_string(k + 1);
    ASSERT_NO_FATAL_FAILURE(click(p));
    ASSERT_TRUE(waitFor(
        [&] { return logAfterUndo().find(pair + " source point: ") != std::string::npos; }, 30s))
        << viewer.log();
    ASSERT_NO_FATAL_FAILURE(click(q));
    ASSERT_TRUE(viewer.logged(pair + " target point: ")) << viewer.log();
    // Exactly the clicked survey target on each side: the file's values, as the reader holds
    // them (on a binary grid of about 1e-9 here; core/quantization.h), the grid's step 0.0625.
    const auto logged_p = loggedNumbers(logAfterUndo(), pair + " source point: ");
    const auto logged_q = loggedNumbers(logAfterUndo(), pair + " target point: ");
    ASSERT_EQ(logged_p.size(), 3u) << viewer.log();
    ASSERT_EQ(logged_q.size(), 3u) << viewer.log();
    for (int a = 0; a < 3; ++a) {
      EXPECT_NEAR(logged_p[std::size_t(a)], p[std::size_t(a)], 1e-8) << pair;
      EXPECT_NEAR(logged_q[std::size_t(a)], q[std::size_t(a)], 1e-8) << pair;
    }
    if (k == 0) {  // S1 on the source's point and T1 on the target's, before any fit
      const RgbaImage shot = viewer.screenshot(dir.path());
      EXPECT_GE(whitePixels(shot, pixelOfPoint(p), 30), 5) << "no label S1 by its point";
      EXPECT_GE(whitePixels(shot, pixelOfPoint(q), 30), 5) << "no label T1 by its point";
    }
  }
  // The fit from the three pairs at once: the motion, and an RMS of nothing over exact pairs.
  ASSERT_TRUE(viewer.logged("parallax view: pairs transform: ")) << viewer.log();
  expectTransformNear(loggedNumbers(viewer.log(), "parallax view: pairs transform: "), motion, 1e-7,
                      "the pairs' fit");
  const auto fit_rms = loggedNumbers(viewer.log(), "parallax view: pairs fit: rms ");
  ASSERT_FALSE(fit_rms.empty()) << viewer.log();
  EXPECT_LT(fit_rms[0], 1e-8) << viewer.log();

  // Enter: ICP from the pairs' transform, over every point (the copies match exactly).
  viewer.key("Return");
  ASSERT_TRUE(viewer.logged("parallax view: registered transform: ")) << viewer.log();
  expectTransformNear(loggedNumbers(viewer.log(), "parallax view: registered transform: "), motion,
                      1e-6, "ICP from the pairs");
  // Its preview, after: the source drawn onto the target. Where the first pair's source point
  // was (beside the copy) nothing is left; on the copy, the clouds' colours without holes.
  {
    const RgbaImage after = viewer.settledScreenshot(dir.path());
    const auto pixel = [&](std::array<int, 2> at) {
      const std::uint8_t* c = &after.pixels[(std::size_t(at[1]) * after.width + at[0]) * 4];
      return std::array<int, 3>{c[0], c[1], c[2]};
    };
    const auto first = scanPoint(kSurveyTargets[0][0], kSurveyTargets[0][1]);
    EXPECT_EQ(pixel(pixelOfPoint(first)), (std::array<int, 3>{0, 0, 0}));
    int holes = 0;
    for (int j = 2; j < kRegGrid - 2; j += 3) {
      for (int i = 2; i < kRegGrid - 2; i += 3) {
        holes += pixel(pixelOfPoint(motion.apply(scanPoint(i, j)))) == std::array<int, 3>{0, 0, 0};
      }
    }
    EXPECT_EQ(holes, 0) << "background on the aligned clouds";
  }
  // Ctrl + T: written as `register --init` reads it.
  viewer.key("ctrl+t");
  ASSERT_TRUE(viewer.logged("parallax view: wrote the transform to ")) << viewer.log();
  const RigidTransform read = readRigidTransform(written);
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) {
      EXPECT_NEAR(read.m[std::size_t(r)][std::size_t(c)], motion.m[std::size_t(r)][std::size_t(c)],
                  1e-6);
    }
  }
  EXPECT_EQ(viewer.log().find("no point of the"), std::string::npos) << viewer.log();
  EXPECT_EQ(viewer.quit(), 0) << "the viewer did not quit on Escape: " << viewer.log();
}

// `view CLOUD --raster DEM.tif`: the layer drawn with the cloud, each cell in the grey of its
// height shaded by the plane's hillshade, the hole left empty, as `render --raster` draws it.
TEST(ViewerWindow, ARasterLayerIsDrawnWithTheCloudCellByCell) {
  if (!onPath("Xvfb") || !onPath("xdotool")) {
    GTEST_SKIP() << "needs Xvfb and xdotool (Debian packages xvfb, xdotool)";
  }
  TempDir dir;
  const auto tif = dir / "plane.tif";
  writeGeoTiff(planeRaster(), tif);
  const auto ply = dir.write("corners.ply", cornersPly());
  Display display(dir);
  ASSERT_FALSE(display.name().empty()) << "Xvfb did not start: " << readFile(dir / "xvfb.log");
  std::vector<std::string> args = {ply.string(), "--no-vsync",       "--raster",
                                   tif.string(), "--screenshot-dir", dir.path().string()};
  std::istringstream look(kPlaneLayerLook);
  for (std::string word; look >> word;) args.push_back(word);
  ViewerProcess viewer(dir, display.name(), args, "viewer.log");
  ASSERT_TRUE(viewer.hasWindow()) << "no viewer window: " << viewer.log();
  ASSERT_TRUE(viewer.logged("parallax view: raster ")) << viewer.log();
  EXPECT_TRUE(viewer.logged(" 199 cells shown")) << viewer.log();
  expectPlaneLayerPicture(viewer.settledScreenshot(dir.path()));
  EXPECT_EQ(viewer.quit(), 0) << "the viewer did not quit on Escape: " << viewer.log();
}

// `view --color m3c2_distance --color-ramp coolwarm --color-percentiles 10,90`: each point in the
// ramp's colour over the symmetric percentile range, and the legend at the window's right edge,
// bar, box and labels, as `render --legend` paints them.
TEST(ViewerWindow, M3c2DistancesThroughTheDivergingRampWithTheirLegend) {
  if (!onPath("Xvfb") || !onPath("xdotool")) {
    GTEST_SKIP() << "needs Xvfb and xdotool (Debian packages xvfb, xdotool)";
  }
  TempDir dir;
  const auto ply = dir.write("signed.ply", signedPly());
  Display display(dir);
  ASSERT_FALSE(display.name().empty()) << "Xvfb did not start: " << readFile(dir / "xvfb.log");
  std::vector<std::string> args = {
      ply.string(), "--no-vsync",          "--color", "m3c2_distance",    "--color-ramp",
      "coolwarm",   "--color-percentiles", "10,90",   "--screenshot-dir", dir.path().string()};
  std::istringstream look(kSignedLook);
  for (std::string word; look >> word;) args.push_back(word);
  ViewerProcess viewer(dir, display.name(), args, "viewer.log");
  ASSERT_TRUE(viewer.hasWindow()) << "no viewer window: " << viewer.log();
  EXPECT_TRUE(viewer.logged("parallax view: first picture after")) << viewer.log();
  viewer.key("g");  // the panel off; the legend stays
  viewer.settledScreenshot(dir.path());
  // Finite values' ranks 1 and 6 of 8 (-0.2 and 0.3), made symmetric: -0.3 .. 0.3 (floats).
  expectSignedLegendPicture(viewer.windowShot(dir.path()), double(0.3f));
  EXPECT_EQ(viewer.quit(), 0) << "the viewer did not quit on Escape: " << viewer.log();
}

// The viewer on the cone pile on its sloped base (volume_piles.h), orthographic from above,
// centred on (10, 10), the area tool on; `extra`: more options.
std::vector<std::string> coneViewArgs(const std::filesystem::path& cloud,
                                      const std::vector<std::string>& extra = {}) {
  std::vector<std::string> args = {
      cloud.string(), "--no-vsync",   "--tool", "area",         "--width",  "400",      "--height",
      "400",          "--ortho",      "--eye",  "10,10,100",    "--target", "10,10,20", "--up",
      "0,1,0",        "--point-size", "4",      "--rasterizer", "points"};
  args.insert(args.end(), extra.begin(), extra.end());
  return args;
}

// Four clicks near the corners of [0, 20]^2, well outside the cone, and Enter: the area. The
// view's height is the extent's largest side (22) over 400 pixels. `polygon`: the clicked
// points' x and y as the viewer logs them, one vertex a line (as `volume --polygon` reads them).
void clickAreaAroundTheCone(ViewerProcess& viewer, std::string& polygon) {
  const std::array<std::array<double, 2>, 4> corners{
      {{0.25, 0.25}, {19.75, 0.25}, {19.75, 19.75}, {0.25, 19.75}}};
  std::ostringstream vertices;
  vertices.precision(17);
  for (std::size_t i = 0; i < corners.size(); ++i) {
    const double per_unit = 400.0 / 22.0;
    viewer.click(int(std::floor(200 + (corners[i][0] - 10) * per_unit)),
                 int(std::floor(200 - (corners[i][1] - 10) * per_unit)));
    const std::string prefix = "parallax view: area point " + std::to_string(i + 1) + ": ";
    ASSERT_TRUE(viewer.logged(prefix)) << viewer.log();
    const auto p = loggedNumbers(viewer.log(), prefix);
    ASSERT_EQ(p.size(), 3u) << viewer.log();
    // A point of the cloud near the corner: the polygon holds the whole cone.
    EXPECT_NEAR(p[0], corners[i][0], 1.0) << viewer.log();
    EXPECT_NEAR(p[1], corners[i][1], 1.0) << viewer.log();
    vertices << p[0] << ' ' << p[1] << '\n';
  }
  viewer.key("Return");
  polygon = vertices.str();
}

// Cut, fill and net of the viewer's line "parallax view: volume of measurement 1: ...", and
// the line.
struct ViewerVolume {
  double cut = 0, fill = 0, net = 0;
  std::string line;
};
void loggedVolume(const ViewerProcess& viewer, ViewerVolume& volume) {
  const std::string prefix = "parallax view: volume of measurement 1: cut ";
  ASSERT_TRUE(viewer.logged(prefix)) << viewer.log();
  const std::string log = viewer.log();
  const auto at = log.find(prefix);
  volume.line = log.substr(at, log.find('\n', at) - at);
  ASSERT_EQ(std::sscanf(volume.line.c_str() + prefix.size(), "%lf fill %lf net %lf", &volume.cut,
                        &volume.fill, &volume.net),
            3)
      << volume.line;
}

// What `parallax volume CLOUD --polygon (the clicked polygon) --resolution 0.5 ARGS --json`
// prints.
nlohmann::json volumeCommand(const TempDir& dir, const std::filesystem::path& cloud,
                             const std::string& polygon, const std::string& args) {
  const auto polygon_file = dir.write("area.txt", polygon);
  const auto json_file = dir / "volume.json";
  EXPECT_EQ(
      run(std::string(PARALLAX_EXECUTABLE) + " volume " + cloud.string() + " --polygon " +
          polygon_file.string() + " --resolution 0.5 " + args + " --json > " + json_file.string()),
      0);
  return nlohmann::json::parse(readFile(json_file));
}

// The area tool (G) around the cone, then its volume (Ctrl + V) as the viewer logs it.
void volumeAroundTheCone(ViewerProcess& viewer, std::string& polygon, ViewerVolume& volume) {
  viewer.key("g");
  ASSERT_NO_FATAL_FAILURE(clickAreaAroundTheCone(viewer, polygon));
  viewer.key("ctrl+v");
  ASSERT_NO_FATAL_FAILURE(loggedVolume(viewer, volume));
}

void expectSameVolume(const ViewerVolume& viewer, const nlohmann::json& command) {
  EXPECT_NEAR(viewer.cut, command.at("cut").get<double>(), 1e-6) << command.dump();
  EXPECT_NEAR(viewer.fill, command.at("fill").get<double>(), 1e-6) << command.dump();
  EXPECT_NEAR(viewer.net, command.at("net").get<double>(), 1e-6) << command.dump();
}

// An area drawn with four clicks around a cone (radius 8, height 4) on a sloped base, seen from
// above; Ctrl + V: cut = the cone's pi r^2 h / 3 within 0.5 % (one point at each 0.5 cell's
// centre, the panel's cell size: the midpoint rule), nothing filled, and exactly what `parallax
// volume` prints for the polygon of the clicked points.
TEST(ViewerWindow, TheVolumeToolGivesAConesVolumeInsideAnArea) {
  if (!onPath("Xvfb") || !onPath("xdotool")) {
    GTEST_SKIP() << "needs Xvfb and xdotool (Debian packages xvfb, xdotool)";
  }
  TempDir dir;
  const auto cloud = writeCloud(dir, slopedBase, cone, 0.5, 1);
  Display display(dir);
  ASSERT_FALSE(display.name().empty()) << "Xvfb did not start: " << readFile(dir / "xvfb.log");
  ViewerProcess viewer(dir, display.name(), coneViewArgs(cloud), "viewer.log");
  ASSERT_TRUE(viewer.hasWindow()) << "no viewer window: " << viewer.log();
  EXPECT_TRUE(viewer.logged("parallax view: first picture after")) << viewer.log();
  std::string polygon;
  ViewerVolume volume;
  ASSERT_NO_FATAL_FAILURE(volumeAroundTheCone(viewer, polygon, volume));
  const double cone_volume = std::numbers::pi * 64 * 4 / 3;
  EXPECT_NEAR(volume.cut, cone_volume, 0.005 * cone_volume) << volume.line;
  EXPECT_NEAR(volume.fill, 0.0, 1e-3) << volume.line;
  EXPECT_NEAR(volume.net, volume.cut - volume.fill, 2e-6) << volume.line;
  expectSameVolume(volume, volumeCommand(dir, cloud, polygon, ""));
  EXPECT_EQ(viewer.quit(), 0) << "the viewer did not quit on Escape: " << viewer.log();
}

// Pixels of the viewer's error colour (1, 0.35, 0.35: 255 89 89) in `image`: the fully covered
// pixels of an error's text.
int errorTextPixels(const RgbaImage& image) {
  int count = 0;
  for (std::size_t i = 0; i < image.pixels.size(); i += 4) {
    count += image.pixels[i] == 255 && image.pixels[i + 1] == 89 && image.pixels[i + 2] == 89;
  }
  return count;
}

// The same area over a base raster (`view --volume-base DEM.tif`, the panel's raster field): a
// GeoTIFF of the sloped plane written here through GDAL, cells of 0.5 whose centres are the
// volume's: cut = the cone's volume within 0.5 %, and exactly what `parallax volume --base
// DEM.tif` prints. The file removed, Ctrl + V again: the error, naming it, on stderr and over
// the picture (the panel hidden), where a failure to open is shown.
TEST(ViewerWindow, TheVolumeToolTakesABaseRasterAndShowsWhenItIsMissing) {
  if (!onPath("Xvfb") || !onPath("xdotool")) {
    GTEST_SKIP() << "needs Xvfb and xdotool (Debian packages xvfb, xdotool)";
  }
  TempDir dir;
  const auto cloud = writeCloud(dir, slopedBase, cone, 0.5, 1);
  const auto base = dir / "slope-dtm.tif";
  writeGeoTiff(slopedBaseRaster(-1, -1, 21, 21), base);
  Display display(dir);
  ASSERT_FALSE(display.name().empty()) << "Xvfb did not start: " << readFile(dir / "xvfb.log");
  ViewerProcess viewer(dir, display.name(),
                       coneViewArgs(cloud, {"--volume-base", base.string(), "--screenshot-dir",
                                            dir.path().string()}),
                       "viewer.log");
  ASSERT_TRUE(viewer.hasWindow()) << "no viewer window: " << viewer.log();
  EXPECT_TRUE(viewer.logged("parallax view: first picture after")) << viewer.log();
  std::string polygon;
  ViewerVolume volume;
  ASSERT_NO_FATAL_FAILURE(volumeAroundTheCone(viewer, polygon, volume));
  EXPECT_NE(volume.line.find("base raster " + base.string()), std::string::npos) << volume.line;
  const double cone_volume = std::numbers::pi * 64 * 4 / 3;
  EXPECT_NEAR(volume.cut, cone_volume, 0.005 * cone_volume) << volume.line;
  EXPECT_NEAR(volume.fill, 0.0, 1e-3) << volume.line;
  const nlohmann::json expected = volumeCommand(dir, cloud, polygon, "--base " + base.string());
  EXPECT_EQ(expected.at("base"), "raster") << expected.dump();
  expectSameVolume(volume, expected);

  EXPECT_EQ(errorTextPixels(viewer.windowShot(dir.path())), 0) << "an error shown before any";
  std::filesystem::remove(base);
  viewer.key("ctrl+v");
  const std::string error =
      "parallax view: volume: --base: expected plane, lowest or a raster "
      "file, found '" +
      base.string() + "' (no such file)";
  EXPECT_TRUE(viewer.logged(error)) << viewer.log();
  EXPECT_GE(errorTextPixels(viewer.windowShot(dir.path())), 50) << "no error over the picture";
  EXPECT_EQ(viewer.quit(), 0) << "the viewer did not quit on Escape: " << viewer.log();
}

}  // namespace
}  // namespace parallax::test
