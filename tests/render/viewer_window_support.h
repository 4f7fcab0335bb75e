// Helpers of the viewer's window tests (test_viewer_window.cpp, test_viewer_measure.cpp): Xvfb
// on a display of its own, the `parallax view` process driven with xdotool, child processes, and
// a small coloured grid to show.
//
// Needs the Debian packages xvfb and xdotool; the tests skip (with the reason) where they are
// missing. Xvfb picks a free display itself (-displayfd), so parallel runs do not collide.
#pragma once

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "render/image_file.h"
#include "support/temp_dir.h"

extern char** environ;

namespace parallax::test {

// The share of the pixels the cloud covers in either picture that have the same colour in both
// (the viewer tests' background is magenta, 255 0 255): 0 for pictures of different sizes.
inline double sameFraction(const RgbaImage& a, const RgbaImage& b) {
  // Over the pixels the cloud covers in either picture: the background would make any two
  // pictures look alike.
  if (a.width != b.width || a.height != b.height || a.pixels.empty()) return 0.0;
  const auto background = [](const RgbaImage& image, std::size_t i) {
    return image.pixels[i] == 255 && image.pixels[i + 1] == 0 && image.pixels[i + 2] == 255;
  };
  std::size_t same = 0, covered = 0;
  for (std::size_t i = 0; i < a.pixels.size(); i += 4) {
    if (background(a, i) && background(b, i)) continue;
    ++covered;
    same += a.pixels[i] == b.pixels[i] && a.pixels[i + 1] == b.pixels[i + 1] &&
            a.pixels[i + 2] == b.pixels[i + 2];
  }
  return covered == 0 ? 0.0 : double(same) / double(covered);
}

inline bool onPath(const std::string& program) {
  return std::system(("command -v " + program + " > /dev/null 2>&1").c_str()) == 0;
}

// A child process; killed (SIGTERM, then SIGKILL) if still running when destroyed.
class Child {
 public:
  Child(const std::vector<std::string>& args, const std::vector<std::string>& extra_env,
        const std::string& output_file) {
    std::vector<char*> argv;
    for (const auto& arg : args) argv.push_back(const_cast<char*>(arg.c_str()));
    argv.push_back(nullptr);
    env_strings_ = extra_env;
    std::vector<char*> envp;
    for (auto& entry : env_strings_) envp.push_back(entry.data());
    for (char** e = environ; *e; ++e) envp.push_back(*e);
    envp.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 1, output_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC,
                                     0644);
    posix_spawn_file_actions_adddup2(&actions, 1, 2);
    if (posix_spawnp(&pid_, args[0].c_str(), &actions, nullptr, argv.data(), envp.data()) != 0) {
      pid_ = -1;
    }
    posix_spawn_file_actions_destroy(&actions);
  }
  ~Child() {
    if (pid_ <= 0) return;
    kill(pid_, SIGTERM);
    for (int i = 0; i < 50 && !exited(); ++i)
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    if (!exited()) {
      kill(pid_, SIGKILL);
      waitpid(pid_, nullptr, 0);
    }
  }
  bool started() const { return pid_ > 0; }
  // Waits up to `timeout` for the process to end; its exit status, or -1.
  int wait(std::chrono::milliseconds timeout) {
    const auto end = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < end) {
      if (exited()) return WIFEXITED(status_) ? WEXITSTATUS(status_) : -1;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return -1;
  }

 private:
  bool exited() {
    if (done_) return true;
    if (waitpid(pid_, &status_, WNOHANG) == pid_) done_ = true;
    return done_;
  }
  pid_t pid_ = -1;
  int status_ = 0;
  bool done_ = false;
  std::vector<std::string> env_strings_;
};

inline std::string readFile(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

inline bool waitFor(const std::function<bool()>& condition, std::chrono::milliseconds timeout) {
  const auto end = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < end) {
    if (condition()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return condition();
}

inline int run(const std::string& command) {
  return std::system(command.c_str());
}

// A coloured 60 x 60 grid on a gentle dome, as an ASCII PLY; `classified`: with a
// classification, class 2 (ground) where x < 0 and class 6 (building) elsewhere.
inline std::string gridPly(bool classified = false) {
  std::ostringstream ply;
  ply << "ply\nformat ascii 1.0\nelement vertex 3600\nproperty float x\nproperty float y\n"
         "property float z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\n"
      << (classified ? "property uchar classification\n" : "") << "end_header\n";
  for (int j = 0; j < 60; ++j) {
    for (int i = 0; i < 60; ++i) {
      const double x = i / 59.0 - 0.5, y = j / 59.0 - 0.5;
      ply << x << ' ' << y << ' ' << 0.3 * (0.5 - x * x - y * y) << ' ' << 40 + 3 * i << ' '
          << 40 + 3 * j << " 60";
      if (classified) ply << ' ' << (x < 0 ? 2 : 6);
      ply << '\n';
    }
  }
  return ply.str();
}

class Display {
 public:
  explicit Display(const TempDir& dir)
      : xvfb_({"sh", "-c",
               "exec Xvfb -displayfd 3 -screen 0 1024x768x24 -nolisten tcp 3>" +
                   (dir / "display").string()},
              {}, (dir / "xvfb.log").string()) {
    if (waitFor([&] { return !readFile(dir / "display").empty(); }, std::chrono::seconds(20))) {
      // Appended, not `":" + ...`: GCC 12 warns (-Wrestrict) on that inlined operator+.
      name_ = ":";
      name_ += std::to_string(std::stoi(readFile(dir / "display")));
    }
  }
  const std::string& name() const { return name_; }  // empty: Xvfb did not start

 private:
  Child xvfb_;
  std::string name_;
};

// The parallax viewer on `display`, its window found by xdotool.
class ViewerProcess {
 public:
  // `extra_env`: more NAME=VALUE pairs for the viewer (test hooks).
  ViewerProcess(const TempDir& dir, const std::string& display, std::vector<std::string> args,
                const std::string& log_name, std::vector<std::string> extra_env = {})
      : log_(dir / log_name),
        env_("DISPLAY=" + display + " "),
        viewer_(
            [&] {
              args.insert(args.begin(), {PARALLAX_EXECUTABLE, "view"});
              return args;
            }(),
            [&] {
              extra_env.insert(extra_env.begin(),
                               {"DISPLAY=" + display, "ASAN_OPTIONS=detect_leaks=0",
                                "PARALLAX_VIEW_TRACE_KEYS=1"});
              return extra_env;
            }(),
            log_.string()) {
    const auto window_file = dir / (log_name + ".window");
    if (run(env_ + "timeout 60 xdotool search --sync --name Parallax > " + window_file.string()) ==
        0) {
      window_ = std::to_string(std::stol(readFile(window_file)));
    }
  }
  bool hasWindow() const { return !window_.empty(); }
  std::string log() const { return readFile(log_); }
  bool logged(const std::string& text,
              std::chrono::milliseconds timeout = std::chrono::seconds(30)) const {
    return waitFor([&] { return log().find(text) != std::string::npos; }, timeout);
  }
  void key(const std::string& name) {
    EXPECT_EQ(run(env_ + "xdotool key --window " + window_ + " " + name + " > /dev/null 2>&1"), 0)
        << name;
    sync();
  }
  // Waits (at most 30 s) until the viewer has handled every input sent before and drawn a frame
  // after it: a Pause key (bound to nothing) follows them, and PARALLAX_VIEW_TRACE_KEYS makes the
  // viewer log each key once the frame that took it is drawn. X delivers the events in order, so
  // the next input lands in a later frame: two clicks are never taken as one.
  void sync() {
    EXPECT_EQ(run(env_ + "xdotool key --window " + window_ + " Pause > /dev/null 2>&1"), 0);
    const std::size_t expected = ++syncs_;
    EXPECT_TRUE(waitFor(
        [&] {
          const std::string text = log();
          std::size_t count = 0;
          for (auto at = text.find(kPauseHandled); at != std::string::npos;
               at = text.find(kPauseHandled, at + 1)) {
            ++count;
          }
          return count >= expected;
        },
        std::chrono::seconds(30)))
        << "the viewer did not take input " << expected << ": " << log();
  }
  // A left-button drag from (x0, y0) to (x1, y1), window coordinates.
  void drag(int x0, int y0, int x1, int y1) {
    const std::string at = "mousemove --window " + window_ + " ";
    EXPECT_EQ(run(env_ + "xdotool " + at + std::to_string(x0) + " " + std::to_string(y0) +
                  " mousedown 1 " + at + std::to_string((x0 + x1) / 2) + " " +
                  std::to_string((y0 + y1) / 2) + " > /dev/null 2>&1"),
              0);
    sync();  // each step of the drag in a frame of its own: the camera follows it
    EXPECT_EQ(run(env_ + "xdotool " + at + std::to_string(x1) + " " + std::to_string(y1) +
                  " > /dev/null 2>&1"),
              0);
    sync();
    EXPECT_EQ(run(env_ + "xdotool mouseup 1 > /dev/null 2>&1"), 0);
    sync();
  }
  // A left click with Ctrl held at (x, y), window coordinates: picks a point.
  void ctrlClick(int x, int y) {
    EXPECT_EQ(run(env_ + "xdotool mousemove --window " + window_ + " " + std::to_string(x) + " " +
                  std::to_string(y) + " keydown ctrl click 1 keyup ctrl > /dev/null 2>&1"),
              0);
    sync();
  }
  // A plain left click at (x, y), window coordinates (with a measurement tool: adds a point).
  void click(int x, int y) {
    EXPECT_EQ(run(env_ + "xdotool mousemove --window " + window_ + " " + std::to_string(x) + " " +
                  std::to_string(y) + " click 1 > /dev/null 2>&1"),
              0);
    sync();
  }
  // `clicks` steps of the wheel forward (towards the cloud) at the window's middle.
  void scroll(int clicks) {
    for (int i = 0; i < clicks; ++i) {
      EXPECT_EQ(run(env_ + "xdotool click --window " + window_ + " 4 > /dev/null 2>&1"), 0);
      sync();
    }
  }
  // `clicks` steps of the wheel backwards (down a scrolled panel) with the pointer at (x, y).
  void scrollDownAt(int x, int y, int clicks) {
    EXPECT_EQ(run(env_ + "xdotool mousemove --window " + window_ + " " + std::to_string(x) + " " +
                  std::to_string(y) + " > /dev/null 2>&1"),
              0);
    for (int i = 0; i < clicks; ++i) {
      EXPECT_EQ(run(env_ + "xdotool click --window " + window_ + " 5 > /dev/null 2>&1"), 0);
      sync();
    }
  }
  RgbaImage screenshot(const std::filesystem::path& shots) {
    const auto path = shots / ("parallax-screenshot-" + std::to_string(++shots_) + ".png");
    key("p");
    EXPECT_TRUE(waitFor([&] { return std::filesystem::exists(path); }, std::chrono::seconds(30)))
        << "no screenshot " << path << ": " << log();
    return readPng(path);
  }
  // Screenshots (P) until one equals the screenshot before it and `ready` holds for it, for at
  // most `timeout`: what was loading has arrived and the last input has been drawn. The picture
  // the test's assertions then read (the last one taken when none did: they fail, saying what
  // they saw). A wait on what the test expects to see, never for a fixed time.
  RgbaImage settledScreenshot(
      const std::filesystem::path& shots,
      const std::function<bool(const RgbaImage&)>& ready = [](const RgbaImage&) { return true; },
      std::chrono::milliseconds timeout = std::chrono::seconds(30)) {
    const auto end = std::chrono::steady_clock::now() + timeout;
    RgbaImage last = screenshot(shots);
    for (;;) {
      RgbaImage next = screenshot(shots);
      const bool settled = next.width == last.width && next.height == last.height &&
                           next.pixels == last.pixels && ready(next);
      if (settled || std::chrono::steady_clock::now() >= end) return next;
      last = std::move(next);
    }
  }
  // Shift + P: the window as seen, the panel included (P writes the picture alone).
  RgbaImage windowShot(const std::filesystem::path& shots) {
    const auto path = shots / ("parallax-screenshot-" + std::to_string(++shots_) + ".png");
    key("shift+p");
    EXPECT_TRUE(waitFor([&] { return std::filesystem::exists(path); }, std::chrono::seconds(30)))
        << "no window screenshot " << path << ": " << log();
    return readPng(path);
  }
  // Holds `name` down for `seconds` (fly mode's W A S D move while held).
  void hold(const std::string& name, double seconds) {
    EXPECT_EQ(run(env_ + "xdotool keydown --window " + window_ + " " + name + " sleep " +
                  std::to_string(seconds) + " keyup --window " + window_ + " " + name +
                  " > /dev/null 2>&1"),
              0)
        << name;
    sync();
  }
  // Waits up to `timeout` for the viewer to end; its exit status, or -1 while it runs.
  int wait(std::chrono::milliseconds timeout) { return viewer_.wait(timeout); }
  int quit() {
    // xdotool may fail on the key release when the window is already gone: the exit status of
    // the viewer is what counts.
    run(env_ + "xdotool key --window " + window_ + " Escape > /dev/null 2>&1");
    return viewer_.wait(std::chrono::seconds(20));
  }

 private:
  std::filesystem::path log_;
  std::string env_;
  Child viewer_;
  static constexpr const char* kPauseHandled = "parallax view: key 284 handled and drawn";
  std::string window_;
  int shots_ = 0;
  std::size_t syncs_ = 0;
};

}  // namespace parallax::test
