// A headset's frames never wait for an octree's loading (issue 24): `view URL --xr` of an octree
// served by nginx through the fault proxy, which holds every node's answer back. The first frame
// is submitted before any node has arrived (it shows nothing), and later frames draw what has
// arrived since, more and more, as the window's progressive frames do.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "../net/loopback_servers.h"
#include "render/image_file.h"
#include "support/run_parallax.h"
#include "support/temp_dir.h"

namespace parallax {
namespace {

using test::quoted;

std::size_t litPixelCount(const std::filesystem::path& png) {
  const RgbaImage image = readPng(png);
  std::size_t lit = 0;
  for (std::size_t i = 0; i < image.pixels.size(); i += 4) {
    lit += image.pixels[i] || image.pixels[i + 1] || image.pixels[i + 2];
  }
  return lit;
}

TEST(XrStreaming, FramesDrawWhatHasArrivedAndNeverWaitForTheRest) {
  test::TempDir dir;
  const std::string exe = quoted(PARALLAX_EXECUTABLE);
  const std::filesystem::path ply = dir / "scan.ply", oct = dir / "www" / "oct";
  std::filesystem::create_directories(dir / "www");
  ASSERT_EQ(
      test::runWithoutLeakCheck(exe + " generate -o " + quoted(ply.string()) +
                                " --points 30000 --seed 3 >/dev/null 2>&1 && " + exe + " convert " +
                                quoted(ply.string()) + " -o " + quoted(oct.string()) + " -q"),
      0);
  test::Nginx nginx(dir / "nginx", {.root = dir / "www"});
  // Every node's points come 100 ms late; the metadata and the hierarchy do not. (30 000 points
  // make a root and four children.)
  test::FaultProxy proxy(dir / "proxy", nginx.port(),
                         {"--mode", "delay", "--delay-ms", "100", "--path-suffix", "octree.bin"});

  // Both eyes 0.8 m above the cloud (fitted in 1 m on the floor), looking straight down, close
  // enough that every node is selected; 60 frames, paced at 90 Hz by the runtime: at least
  // 0.66 s after a first frame that compiles the shaders, some three times what the two rounds
  // of loads take (a slower machine draws slower frames, which leaves the loads more time).
  constexpr int kFrames = 60;
  nlohmann::json views = nlohmann::json::array();
  for (double x : {-0.032, 0.032}) {
    views.push_back({{"fov", {{"left", -0.8}, {"right", 0.8}, {"up", 0.8}, {"down", -0.8}}},
                     {"pose",
                      {{"position", {x, 0.8, 0.0}},
                       {"orientation", {-0.70710678118654752, 0.0, 0.0, 0.70710678118654752}}}}});
  }
  std::ofstream(dir / "headset.json") << nlohmann::json{
      {"views", views},
      {"width", 160},
      {"height", 160},
      {"frames", kFrames},
      {"output", (dir / "out").string()}}.dump();
  setenv("XR_RUNTIME_JSON", PARALLAX_XR_TEST_RUNTIME, 1);
  setenv("PARALLAX_XR_TEST", (dir / "headset.json").c_str(), 1);
  setenv("XDG_CACHE_HOME", (dir / "cache").c_str(), 1);
  unsetenv("DISPLAY");
  unsetenv("XR_ENABLE_API_LAYERS");
  for (const char* name : {"http_proxy", "https_proxy", "HTTP_PROXY", "HTTPS_PROXY", "all_proxy",
                           "ALL_PROXY", "no_proxy", "NO_PROXY"}) {
    unsetenv(name);
  }
  const auto result = test::runParallax(
      dir, "view " + quoted(proxy.url("oct/")) + " --xr --xr-tabletop --point-size 1");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  std::vector<std::size_t> lit[2];
  for (int f = 0; f < kFrames; ++f) {
    for (int v = 0; v < 2; ++v) {
      lit[v].push_back(litPixelCount(
          dir / "out" / ("frame_" + std::to_string(f) + "_view_" + std::to_string(v) + ".png")));
    }
  }
  for (int f = 0; f < kFrames; ++f) std::printf("%zu ", lit[0][f]);
  std::printf("\n%s\n", result.err.c_str());
  for (int v = 0; v < 2; ++v) {
    EXPECT_EQ(lit[v].front(), 0u) << "view " << v << ": the first frame waited for a node";
    EXPECT_GT(lit[v].back(), 500u) << "view " << v << ": the nodes never arrived";
    // 1-pixel points, additive levels, a still head: a pixel once lit stays lit.
    for (int f = 1; f < kFrames; ++f) {
      EXPECT_GE(lit[v][f], lit[v][f - 1]) << "view " << v << ", frame " << f;
    }
  }
  // The last frame drew every point: each node was drawn once it had arrived.
  EXPECT_NE(result.err.find("(30000 points"), std::string::npos) << result.err;
  // view --xr counts the frames it drew while nodes were still on their way.
  const auto at = result.err.find(" while nodes were arriving");
  ASSERT_NE(at, std::string::npos) << result.err;
  const auto start = result.err.rfind(", ", at);
  ASSERT_NE(start, std::string::npos);
  EXPECT_GT(std::stoll(result.err.substr(start + 2, at - start - 2)), 0) << result.err;
  int delayed = 0;
  for (const test::ProxyLine& line : proxy.log()) delayed += line.action == "delay";
  EXPECT_GT(delayed, 0) << "no node was held back";
}

}  // namespace
}  // namespace parallax
