// hello_xr (Debian's libopenxr-utils: the Khronos sample application) against the project's test
// runtime (issue 24, item 5), through the real loader and under the core validation layer: the
// runtime is an OpenXR runtime any application can use, not one shaped around `view --xr`.
//
// hello_xr's OpenGL plug-in opens its own GLX window (ksGpuWindow_Create), which asks for the
// XFree86-VidMode extension: Xvfb has none and hello_xr crashes there. The X server here is Xorg
// with the dummy video driver (Debian's xserver-xorg-video-dummy), which has it; GL is Mesa's
// llvmpipe through GLX. Xorg picks a free display itself (-displayfd).
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "../render/viewer_window_support.h"
#include "render/image_file.h"
#include "support/run_parallax.h"
#include "support/temp_dir.h"

namespace parallax {
namespace {

using test::quoted;

// Xorg with the dummy driver on a display of its own, for as long as the object lives.
class DummyXServer {
 public:
  explicit DummyXServer(const test::TempDir& dir) : dir_(dir.path()) {
    std::ofstream(dir / "xorg.conf")
        << "Section \"Device\"\n  Identifier \"dummy\"\n  Driver \"dummy\"\n  VideoRam 65536\n"
           "EndSection\n"
           "Section \"Monitor\"\n  Identifier \"monitor\"\n  HorizSync 5.0 - 1000.0\n"
           "  VertRefresh 5.0 - 200.0\nEndSection\n"
           "Section \"Screen\"\n  Identifier \"screen\"\n  Device \"dummy\"\n"
           "  Monitor \"monitor\"\n  DefaultDepth 24\n  SubSection \"Display\"\n    Depth 24\n"
           "    Virtual 1024 768\n  EndSubSection\nEndSection\n";
    xorg_ = std::make_unique<test::Child>(
        std::vector<std::string>{
            "sh", "-c",
            "exec Xorg -displayfd 3 -config " + quoted((dir / "xorg.conf").string()) +
                " -logfile " + quoted((dir / "xorg.log").string()) + " -noreset -nolisten tcp 3>" +
                quoted((dir / "display").string())},
        std::vector<std::string>{}, (dir / "xorg.out").string());
    if (test::waitFor([&] { return !test::readFile(dir / "display").empty(); },
                      std::chrono::seconds(20))) {
      name_ = ":";
      name_ += std::to_string(std::stoi(test::readFile(dir / "display")));
    }
  }
  const std::string& name() const { return name_; }  // empty: Xorg did not start
  std::string log() const {
    return test::readFile(dir_ / "xorg.out") + test::readFile(dir_ / "xorg.log");
  }

 private:
  std::filesystem::path dir_;
  std::unique_ptr<test::Child> xorg_;
  std::string name_;
};

TEST(HelloXr, RunsItsSessionAgainstTheTestRuntimeUnderTheValidationLayer) {
  test::TempDir dir;
  ASSERT_TRUE(test::onPath("hello_xr")) << "hello_xr not found: install libopenxr-utils";
  ASSERT_TRUE(test::onPath("Xorg"))
      << "Xorg not found: install xserver-xorg-core and xserver-xorg-video-dummy";
  DummyXServer x(dir);
  ASSERT_FALSE(x.name().empty()) << "Xorg (dummy driver) did not start: " << x.log();

  constexpr int kFrames = 4;
  nlohmann::json views = nlohmann::json::array();
  for (double eye_x : {-0.032, 0.032}) {
    views.push_back({{"fov", {{"left", -0.8}, {"right", 0.8}, {"up", 0.8}, {"down", -0.8}}},
                     {"pose", {{"position", {eye_x, 1.6, 0.0}}, {"orientation", {0, 0, 0, 1}}}}});
  }
  std::ofstream(dir / "headset.json") << nlohmann::json{
      {"views", views},
      {"width", 64},
      {"height", 64},
      {"frames", kFrames},
      {"output", (dir / "out").string()}}.dump();
  // hello_xr quits when a key is read from its standard input: a FIFO opened read-write never
  // gives one (and never an end of file), so it runs until the runtime ends its session.
  ASSERT_EQ(::mkfifo((dir / "stdin").c_str(), 0600), 0);
  // In a sanitizer tree the runtime library needs the sanitizer runtime in hello_xr, which has
  // none of its own (tests/xr/CMakeLists.txt); hello_xr's own leaks are not ours to report.
  const std::string preload(PARALLAX_HOST_SANITIZER_PRELOAD);
  const std::string sanitizer_env =
      preload.empty() ? ""
                      : " env LD_PRELOAD=" + quoted(preload) +
                            " ASAN_OPTIONS=\"${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0\"";
  const std::string command =
      "DISPLAY=" + x.name() + " XR_RUNTIME_JSON=" + quoted(PARALLAX_XR_TEST_RUNTIME) +
      " PARALLAX_XR_TEST=" + quoted((dir / "headset.json").string()) +
      " XR_ENABLE_API_LAYERS=XR_APILAYER_LUNARG_core_validation timeout 120" + sanitizer_env +
      " hello_xr -g OpenGL 0<>" + quoted((dir / "stdin").string()) + " >" +
      quoted((dir / "out.txt").string()) + " 2>" + quoted((dir / "err.txt").string());
  const int status = std::system(command.c_str());
  const std::string out = test::readFile(dir / "out.txt"), err = test::readFile(dir / "err.txt");
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << status << "\n" << out << err;
  // The layer ran and reported nothing (its messages start "[VALID_").
  EXPECT_NE(err.find("Core Validation output type"), std::string::npos) << err;
  EXPECT_EQ(out.find("[VALID_"), std::string::npos) << out;
  EXPECT_EQ(err.find("[VALID_"), std::string::npos) << err;
  // Every frame came to the runtime, no more; each eye is hello_xr's picture: its clear colour
  // (DarkSlateGray, 47 79 79 in an 8-bit swapchain) behind the cubes it draws at the hands and
  // about the room.
  EXPECT_TRUE(
      std::filesystem::exists(dir / "out" / ("frame_" + std::to_string(kFrames - 1) + ".json")));
  EXPECT_FALSE(
      std::filesystem::exists(dir / "out" / ("frame_" + std::to_string(kFrames) + ".json")));
  for (int v = 0; v < 2; ++v) {
    const RgbaImage image =
        readPng(dir / "out" /
                ("frame_" + std::to_string(kFrames - 1) + "_view_" + std::to_string(v) + ".png"));
    ASSERT_EQ(image.width, 64);
    ASSERT_EQ(image.height, 64);
    std::size_t clear = 0, other = 0;
    for (std::size_t i = 0; i < image.pixels.size(); i += 4) {
      const bool slate = std::abs(image.pixels[i] - 47) <= 1 &&
                         std::abs(image.pixels[i + 1] - 79) <= 1 &&
                         std::abs(image.pixels[i + 2] - 79) <= 1;
      (slate ? clear : other) += 1;
    }
    EXPECT_GT(clear, 64u * 64u / 2) << "view " << v << ": not hello_xr's clear colour";
    EXPECT_GT(other, 20u) << "view " << v << ": no cube drawn";
  }
}

}  // namespace
}  // namespace parallax
