// `parallax bench render` on a point file and an octree, end to end on small inputs: the look
// (the viewer's choice with --look viewer, the options' otherwise), the orbit's JSON (frame-time
// order, the frames, the size, the reference), and clear errors for bad options. No figure is
// asserted: only what the command must say about what it measured.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <string>

#include "support/run_parallax.h"
#include "support/temp_dir.h"

namespace parallax::test {
namespace {

// A 10 x 10 grid of points 0.5 apart without normals: the spacing is known, no lighting.
std::string gridPly() {
  std::ostringstream ply;
  ply << "ply\nformat ascii 1.0\nelement vertex 100\nproperty float x\nproperty float y\n"
         "property float z\nend_header\n";
  for (int i = 0; i < 10; ++i) {
    for (int j = 0; j < 10; ++j) ply << 0.5 * i << ' ' << 0.5 * j << ' ' << 0.1 * i << '\n';
  }
  return ply.str();
}

// The generated scan (20 000 points, with normals and colours) in `dir`.
std::filesystem::path generatedScan(const TempDir& dir) {
  const auto ply = dir / "scan.ply";
  const RunResult run =
      runParallax(dir, "generate -q -o " + quoted(ply.string()) + " --points 20000 --seed 3");
  EXPECT_EQ(run.exit_code, 0) << run.err;
  return ply;
}

void expectOrderedFrameTimes(const nlohmann::json& json) {
  ASSERT_TRUE(json["median_ms"].is_number()) << json;
  ASSERT_TRUE(json["p90_ms"].is_number()) << json;
  ASSERT_TRUE(json["worst_ms"].is_number()) << json;
  EXPECT_GT(json["median_ms"].get<double>(), 0.0);
  EXPECT_LE(json["median_ms"].get<double>(), json["p90_ms"].get<double>());
  EXPECT_LE(json["p90_ms"].get<double>(), json["worst_ms"].get<double>());
}

// The rasterizer that drew, and the 64-bit atomics only where compute drew.
void expectRasterizerReported(const nlohmann::json& json) {
  const std::string rasterizer = json["rasterizer"].get<std::string>();
  EXPECT_TRUE(rasterizer == "compute" || rasterizer == "points") << rasterizer;
  ASSERT_TRUE(json["atomic64"].is_boolean()) << json;
  if (rasterizer == "points") {
    EXPECT_FALSE(json["atomic64"].get<bool>());
  }
}

TEST(CliBenchRender, ViewerLookOrbitOfAFileWithNormalsIsRoundAdaptiveAndLit) {
  TempDir dir;
  const auto ply = generatedScan(dir);
  const RunResult run = runParallax(dir, "bench render " + quoted(ply.string()) +
                                             " --look viewer --orbit 3 --json --width 64 "
                                             "--height 48");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const auto json = nlohmann::json::parse(run.out);  // one object, nothing else on stdout
  expectOrderedFrameTimes(json);
  EXPECT_EQ(json["mode"], "orbit");
  EXPECT_EQ(json["frames"], 3);
  EXPECT_EQ(json["width"], 64);
  EXPECT_EQ(json["height"], 48);
  EXPECT_EQ(json["points"], 20000);
  EXPECT_EQ(json["points_drawn"], 20000);  // the whole cloud every frame
  EXPECT_EQ(json["settings"]["look"], "viewer");
  EXPECT_EQ(json["settings"]["size_mode"], "adaptive");
  EXPECT_EQ(json["settings"]["shape"], "round");
  EXPECT_EQ(json["settings"]["lighting"], true);
  EXPECT_EQ(json["settings"]["stereo"], "mono");
  expectRasterizerReported(json);
  // The same-run reference and the ratio to it.
  EXPECT_EQ(json["reference"]["rasterizer"], "points");
  EXPECT_TRUE(json["reference"]["name"].is_string());
  EXPECT_LE(json["reference"]["median_ms"].get<double>(),
            json["reference"]["p90_ms"].get<double>());
  EXPECT_GT(json["ratio"].get<double>(), 0.0);
  EXPECT_EQ(json["load_average"]["before"].size(), 3u);
}

// --look viewer measures the viewer's moving frames: progressive refinement within the viewer's
// frame budget (1000 / 15 ms) unless --frame-budget says otherwise; render's look draws whole
// frames. A 20 000-point file is one chunk, drawn whole by every plan.
TEST(CliBenchRender, ViewerLookOrbitRefinesWithinTheViewersFrameBudget) {
  TempDir dir;
  const auto ply = generatedScan(dir);
  const std::string base =
      "bench render " + quoted(ply.string()) + " --orbit 2 --json --width 32 --height 32 ";
  const struct {
    std::string options;
    double budget_ms;
  } cases[] = {{"--look viewer", 1000.0 / 15.0},
               {"--look viewer --frame-budget 0", 0.0},
               {"--look viewer --frame-budget 40", 40.0},
               {"", 0.0},
               {"--frame-budget 25", 25.0}};
  for (const auto& c : cases) {
    const RunResult run = runParallax(dir, base + c.options);
    ASSERT_EQ(run.exit_code, 0) << c.options << ": " << run.err;
    const auto json = nlohmann::json::parse(run.out);
    ASSERT_TRUE(json["frame_budget_ms"].is_number()) << c.options << ": " << json;
    EXPECT_DOUBLE_EQ(json["frame_budget_ms"].get<double>(), c.budget_ms) << c.options;
    EXPECT_EQ(json["points_drawn"], 20000) << c.options;
    expectOrderedFrameTimes(json);
  }
}

TEST(CliBenchRender, ViewerLookLeavesWhatTheOptionsSay) {
  TempDir dir;
  const auto ply = generatedScan(dir);
  const RunResult run = runParallax(dir, "bench render " + quoted(ply.string()) +
                                             " --look viewer --shape square --lighting=false "
                                             "--orbit 2 --json --width 32 --height 32");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const auto json = nlohmann::json::parse(run.out);
  EXPECT_EQ(json["settings"]["size_mode"], "fixed");
  EXPECT_EQ(json["settings"]["shape"], "square");
  EXPECT_EQ(json["settings"]["lighting"], false);
}

TEST(CliBenchRender, ViewerLookOfACloudWithoutNormalsIsUnlit) {
  TempDir dir;
  const auto ply = dir.write("grid.ply", gridPly());
  const RunResult run = runParallax(dir, "bench render " + quoted(ply.string()) +
                                             " --look viewer --orbit 2 --json --width 32 "
                                             "--height 32 --stereo sbs");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const auto json = nlohmann::json::parse(run.out);
  expectOrderedFrameTimes(json);
  EXPECT_EQ(json["points"], 100);
  EXPECT_EQ(json["settings"]["size_mode"], "adaptive");
  EXPECT_EQ(json["settings"]["shape"], "round");
  EXPECT_EQ(json["settings"]["lighting"], false);
  EXPECT_EQ(json["settings"]["stereo"], "sbs");
}

TEST(CliBenchRender, RenderLookIsTheOptionsAsRenderReadsThem) {
  TempDir dir;
  const auto ply = dir.write("grid.ply", gridPly());
  const RunResult run = runParallax(dir, "bench render " + quoted(ply.string()) +
                                             " --json --width 32 --height 32 -n 2 --edl "
                                             "--color elevation --rasterizer points");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const auto json = nlohmann::json::parse(run.out);
  expectOrderedFrameTimes(json);
  EXPECT_EQ(json["mode"], "still");
  EXPECT_EQ(json["frames"], 2);
  EXPECT_EQ(json["rasterizer"], "points");
  EXPECT_EQ(json["atomic64"], false);
  EXPECT_EQ(json["settings"]["look"], "render");
  EXPECT_EQ(json["settings"]["size_mode"], "fixed");
  EXPECT_EQ(json["settings"]["shape"], "square");
  EXPECT_EQ(json["settings"]["lighting"], false);
  EXPECT_EQ(json["settings"]["edl"], true);
  EXPECT_EQ(json["settings"]["color"], "elevation");
}

// The generated scan converted to an octree in `dir`; empty (and a failure recorded) when the
// conversion fails.
std::filesystem::path convertedScan(const TempDir& dir) {
  const auto ply = generatedScan(dir);
  const auto octree = dir / "scan_octree";
  const RunResult convert =
      runParallax(dir, "convert -q " + quoted(ply.string()) + " -o " + quoted(octree.string()));
  EXPECT_EQ(convert.exit_code, 0) << convert.err;
  return convert.exit_code == 0 ? octree : std::filesystem::path();
}

TEST(CliBenchRender, OrbitOfAnOctreeGivesOrderedFrameTimesAndTheViewerLook) {
  TempDir dir;
  const auto octree = convertedScan(dir);
  ASSERT_FALSE(octree.empty());
  const RunResult run = runParallax(dir, "bench render " + quoted(octree.string()) +
                                             " --look viewer --orbit 3 --json --width 64 "
                                             "--height 48 --budget 5000");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const auto json = nlohmann::json::parse(run.out);
  expectOrderedFrameTimes(json);
  EXPECT_EQ(json["frames"], 3);
  EXPECT_EQ(json["points"], 20000);
  EXPECT_EQ(json["budget"], 5000);
  // (A 20 000-point octree may be one node: the budget cannot cut below it.)
  EXPECT_GT(json["points_drawn"].get<double>(), 0.0);
  EXPECT_LE(json["points_drawn"].get<double>(), 20000.0);
  EXPECT_EQ(json["settings"]["size_mode"], "adaptive");
  EXPECT_EQ(json["settings"]["shape"], "round");
  expectRasterizerReported(json);
}

// --stereo on an octree: mono and sbs frames alternated, each side's medians and the ratio of
// the draws' medians (what issue 23's figure reads), and with --pass-times the compute
// rasterizer's passes for both sides.
TEST(CliBenchRender, StereoOfAnOctreeGivesTheRatioOfTheAlternatedMedians) {
  TempDir dir;
  const auto octree = convertedScan(dir);
  ASSERT_FALSE(octree.empty());
  const RunResult run = runParallax(dir, "bench render " + quoted(octree.string()) +
                                             " --stereo sbs -n 2 --pass-times --width 64 "
                                             "--height 48 --budget 5000 --rasterizer compute");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const std::regex draw_line(
      R"((mono|sbs) +loaded in [^\n]*\n +update +[0-9.]+ ms \+ draw +([0-9.]+) ms)");
  double draw_ms[2] = {0, 0};
  int sides = 0;
  for (std::sregex_iterator it(run.out.begin(), run.out.end(), draw_line), end; it != end; ++it) {
    draw_ms[(*it)[1] == "sbs" ? 1 : 0] = std::stod((*it)[2]);
    ++sides;
  }
  ASSERT_EQ(sides, 2) << run.out;
  std::smatch ratio;
  ASSERT_TRUE(std::regex_search(run.out, ratio, std::regex(R"(sbs / mono: draw ([0-9.]+)x)")))
      << run.out;
  // The ratio of the printed medians, within their rounding (0.05 ms each, 0.005 the ratio).
  const double printed = std::stod(ratio[1]);
  ASSERT_GT(draw_ms[0], 0.05) << run.out;
  EXPECT_LE(printed, (draw_ms[1] + 0.05) / (draw_ms[0] - 0.05) + 0.005) << run.out;
  EXPECT_GE(printed, (draw_ms[1] - 0.05) / (draw_ms[0] + 0.05) - 0.005) << run.out;
  EXPECT_NE(run.out.find("(medians of 2 frames of each, alternated"), std::string::npos) << run.out;
  // Both sides' passes, each pass timed. Printed to 0.1 ms: a pass of this 64x48 frame can print
  // 0.0 on a fast machine, so the check is that each is a number, not that it is positive.
  for (const char* side : {"mono", "sbs"}) {
    std::smatch passes;
    ASSERT_TRUE(std::regex_search(
        run.out, passes,
        std::regex(std::string(side) + R"(, passes \(wall / CPU ms, medians\): clears and setup )"
                                       R"([0-9.]+ / [0-9.]+, pass 1 ([0-9.]+) / [0-9.]+, pass 2 )"
                                       R"(([0-9.]+) / [0-9.]+, resolve ([0-9.]+))")))
        << run.out;
    EXPECT_GE(std::stod(passes[1]), 0.0) << run.out;
    EXPECT_GE(std::stod(passes[2]), 0.0) << run.out;
    EXPECT_GE(std::stod(passes[3]), 0.0) << run.out;
  }
}

// Option errors: status 1 and the option named, as `render` reports its own (bad input is 2).
TEST(CliBenchRender, OrbitOfNoFramesIsAnOptionError) {
  TempDir dir;
  const auto ply = dir.write("grid.ply", gridPly());
  const RunResult run = runParallax(dir, "bench render " + quoted(ply.string()) + " --orbit 0");
  EXPECT_EQ(run.exit_code, 1) << run.err;
  EXPECT_NE(run.err.find("--orbit 0: an orbit needs at least 1 frame"), std::string::npos)
      << run.err;
  EXPECT_EQ(run.out, "");
}

TEST(CliBenchRender, UnknownLookIsAnOptionError) {
  TempDir dir;
  const auto ply = dir.write("grid.ply", gridPly());
  const RunResult run =
      runParallax(dir, "bench render " + quoted(ply.string()) + " --look potree --orbit 2");
  EXPECT_EQ(run.exit_code, 1) << run.err;
  EXPECT_NE(run.err.find("--look: unknown look 'potree' (use render"), std::string::npos)
      << run.err;
}

TEST(CliBenchRender, OrbitOfTwoStereoModesIsAnOptionError) {
  TempDir dir;
  const auto ply = dir.write("grid.ply", gridPly());
  const RunResult run = runParallax(
      dir, "bench render " + quoted(ply.string()) + " --orbit 2 --stereo sbs --stereo anaglyph");
  EXPECT_EQ(run.exit_code, 1) << run.err;
  EXPECT_NE(run.err.find("--stereo: an orbit draws one stereo mode, 2 were given"),
            std::string::npos)
      << run.err;
}

// Mono, listed among the modes, is the baseline every run measures: an orbit asked for it draws
// in mono (it was refused as "not a stereo mode" by the message that listed it).
TEST(CliBenchRender, OrbitInMonoDrawsInMono) {
  TempDir dir;
  const auto ply = dir.write("grid.ply", gridPly());
  const RunResult run = runParallax(dir, "bench render " + quoted(ply.string()) +
                                             " --orbit 2 --json --width 32 --height 32 "
                                             "--stereo mono");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const auto json = nlohmann::json::parse(run.out);
  EXPECT_EQ(json["settings"]["stereo"], "mono");
}

TEST(CliBenchRender, UnknownStereoModeIsAnOptionError) {
  TempDir dir;
  const auto ply = dir.write("grid.ply", gridPly());
  const RunResult run =
      runParallax(dir, "bench render " + quoted(ply.string()) + " --orbit 2 --stereo cross-eyed");
  EXPECT_EQ(run.exit_code, 1) << run.err;
  EXPECT_NE(run.err.find("--stereo: 'cross-eyed' is not a stereo mode (use mono|sbs|"),
            std::string::npos)
      << run.err;
}

TEST(CliBenchRender, OrbitOfRandomPointsIsAnOptionError) {
  TempDir dir;
  const RunResult run = runParallax(dir, "bench render --points 1000 --orbit 2");
  EXPECT_EQ(run.exit_code, 1) << run.err;
  EXPECT_NE(run.err.find("--orbit needs a point file or an octree"), std::string::npos) << run.err;
}

TEST(CliBenchRender, MissingFileIsABadInputError) {
  TempDir dir;
  const RunResult run = runParallax(
      dir, "bench render " + quoted((dir / "no_such_file.ply").string()) + " --orbit 2");
  EXPECT_EQ(run.exit_code, 2) << run.err;
  EXPECT_NE(run.err.find("no_such_file.ply"), std::string::npos) << run.err;
}

}  // namespace
}  // namespace parallax::test
