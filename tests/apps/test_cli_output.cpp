// What the command line prints and leaves behind: -q/--quiet on every long-running command and
// the same progress bar otherwise (seen through a pseudo-terminal, as a user's terminal shows
// it), --properties on convert, and the partial outputs of a conversion killed with SIGKILL.
#include <gtest/gtest.h>
#include <pty.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "support/run_parallax.h"
#include "support/temp_dir.h"

extern char** environ;

namespace parallax::test {
namespace {

// `parallax ARGS` with stdout and stderr on a pseudo-terminal: what a user sees. Returns the
// exit code (128 + signal when killed) and everything written.
RunResult runInTerminal(const std::vector<std::string>& args) {
  int master = -1;
  winsize size{};
  size.ws_col = 120;
  size.ws_row = 40;
  const pid_t child = ::forkpty(&master, nullptr, nullptr, &size);
  if (child == 0) {
    std::vector<char*> argv;
    argv.push_back(const_cast<char*>(PARALLAX_EXECUTABLE));
    for (const std::string& arg : args) argv.push_back(const_cast<char*>(arg.c_str()));
    argv.push_back(nullptr);
    ::execv(PARALLAX_EXECUTABLE, argv.data());
    ::_exit(127);
  }
  RunResult result;
  if (child < 0) {
    ADD_FAILURE() << "forkpty: " << std::strerror(errno);
    return result;
  }
  char buffer[4096];
  for (;;) {
    const ssize_t got = ::read(master, buffer, sizeof buffer);
    if (got > 0) {
      result.out.append(buffer, std::size_t(got));
    } else if (got < 0 && errno == EINTR) {
      continue;
    } else {
      break;  // EIO once the child has closed the terminal
    }
  }
  ::close(master);
  int status = 0;
  ::waitpid(child, &status, 0);
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  return result;
}

std::string str(const std::filesystem::path& path) {
  return path.string();
}

bool has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// ---------------------------------------------------------------------------------------------
// -q/--quiet and the progress bar

TEST(CliProgress, EveryLongRunningCommandDrawsTheBarOnATerminal) {
  TempDir dir;
  const std::string ply = str(dir / "scan.ply");
  RunResult run = runInTerminal({"generate", "--points", "60000", "-o", ply});
  ASSERT_EQ(run.exit_code, 0) << run.out;
  // The bar (label, [###...], percentage) and its last line with the count and the time.
  EXPECT_TRUE(has(run.out, "\r\033[Kgenerate [")) << run.out;
  EXPECT_TRUE(has(run.out, "generate: 60000 points in ")) << run.out;

  run = runInTerminal({"convert", ply, "-o", str(dir / "scan.xyz")});
  ASSERT_EQ(run.exit_code, 0) << run.out;
  EXPECT_TRUE(has(run.out, "reading: 60000 points in ")) << run.out;
  EXPECT_TRUE(has(run.out, "writing: 60000 points in ")) << run.out;

  // A text file: the bar counts its bytes.
  run = runInTerminal({"info", str(dir / "scan.xyz")});
  ASSERT_EQ(run.exit_code, 0) << run.out;
  EXPECT_TRUE(has(
      run.out, "loading scan.xyz: " + std::to_string(std::filesystem::file_size(dir / "scan.xyz")) +
                   " bytes in "))
      << run.out;

  run = runInTerminal({"convert", ply, "-o", str(dir / "octree/"), "--memory", "64"});
  ASSERT_EQ(run.exit_code, 0) << run.out;
  for (const char* stage : {"scanning: ", "counting: ", "distributing: "}) {
    EXPECT_TRUE(has(run.out, std::string(stage) + "60000 points in ")) << stage << run.out;
  }

  run = runInTerminal({"bench", "load", ply, "--repeat", "2"});
  ASSERT_EQ(run.exit_code, 0) << run.out;
  EXPECT_TRUE(has(run.out, "bench load: 2 loads in ")) << run.out;
  EXPECT_TRUE(has(run.out, "ratio      load / reference")) << run.out;
}

TEST(CliProgress, QuietCommandsPrintNothingButTheirResults) {
  TempDir dir;
  const std::string ply = str(dir / "scan.ply");
  RunResult run = runInTerminal({"generate", "-q", "--points", "60000", "-o", ply});
  ASSERT_EQ(run.exit_code, 0) << run.out;
  EXPECT_EQ(run.out, "");
  ASSERT_TRUE(std::filesystem::exists(ply));

  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"convert", "-q", ply, "-o", str(dir / "scan.xyz")},
        std::vector<std::string>{"convert", "--quiet", ply, "-o", str(dir / "octree/"), "--memory",
                                 "64"}}) {
    run = runInTerminal(args);
    ASSERT_EQ(run.exit_code, 0) << run.out;
    EXPECT_EQ(run.out, "") << args[3];
  }
  // Commands whose result is their output print it, and nothing else.
  run = runInTerminal({"info", "-q", str(dir / "scan.xyz")});
  ASSERT_EQ(run.exit_code, 0) << run.out;
  EXPECT_FALSE(has(run.out, "loading")) << run.out;
  EXPECT_TRUE(has(run.out, "60000")) << run.out;
  run = runInTerminal({"bench", "load", "-q", ply, "--repeat", "2"});
  ASSERT_EQ(run.exit_code, 0) << run.out;
  EXPECT_FALSE(has(run.out, "bench load:")) << run.out;
  EXPECT_TRUE(has(run.out, "ratio      load / reference")) << run.out;
}

TEST(CliProgress, QuietRenderOfAFileOverTheBudget) {
  TempDir dir;
  const std::string ply = str(dir / "scan.ply");
  ASSERT_EQ(runInTerminal({"generate", "-q", "--points", "30000", "-o", ply}).exit_code, 0);
  RunResult run =
      runInTerminal({"render", ply, "-o", str(dir / "a.png"), "--budget", "10000", "--width", "32",
                     "--height", "24", "--cache-dir", str(dir / "cache")});
  ASSERT_EQ(run.exit_code, 0) << run.out;
  EXPECT_TRUE(has(run.out, "scanning: 30000 points in ")) << run.out;
  EXPECT_TRUE(has(run.out, "parallax render: ")) << run.out;
  run = runInTerminal({"render", "-q", ply, "-o", str(dir / "b.png"), "--budget", "10000",
                       "--width", "32", "--height", "24", "--no-cache"});
  ASSERT_EQ(run.exit_code, 0) << run.out;
  EXPECT_EQ(run.out, "");
  EXPECT_TRUE(std::filesystem::exists(dir / "b.png"));
}

TEST(CliProgress, OutsideATerminalThereIsNoBar) {
  TempDir dir;
  const RunResult run =
      runParallax(dir, "generate --points 50000 -o " + quoted(str(dir / "scan.ply")));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(run.err, "");
  EXPECT_TRUE(has(run.out, "50000 points")) << run.out;
}

// ---------------------------------------------------------------------------------------------
// --properties

TEST(CliProperties, ConvertWritesTheChosenPropertiesInTheirOrder) {
  TempDir dir;
  dir.write("in.csv",
            "x,y,z,nx,ny,nz,r,g,b\n"
            "1.5,2.25,3,0,0.6,0.8,10,20,30\n"
            "4,5.5,-6.125,1,0,0,255,0,128\n");
  RunResult run = runParallax(dir, "convert " + quoted(str(dir / "in.csv")) + " -o " +
                                       quoted(str(dir / "out.xyz")) + " --properties blue,x,y,z");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_TRUE(has(run.err, "dropped or changed: red green nx ny nz (not in --properties)"))
      << run.err;
  EXPECT_EQ(readText(dir / "out.xyz"), "blue x y z\n30 1.5 2.25 3.000\n128 4.0 5.50 -6.125\n");
  // Without the option: the input's order, every column.
  run = runParallax(
      dir, "convert -q " + quoted(str(dir / "in.csv")) + " -o " + quoted(str(dir / "all.csv")));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(readText(dir / "all.csv").substr(0, 34), "x,y,z,nx,ny,nz,red,green,blue\n1.5,");
}

TEST(CliProperties, UnknownNamesAndFixedLayoutsAreRefusedBeforeWriting) {
  TempDir dir;
  dir.write("in.xyz", "1 2 3 4 5 6\n");
  RunResult run = runParallax(dir, "convert " + quoted(str(dir / "in.xyz")) + " -o " +
                                       quoted(str(dir / "out.ply")) + " --properties x,y,z,hue");
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_TRUE(has(run.err, "--properties: no attribute 'hue' (there are x,y,z,red,green,blue)"))
      << run.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "out.ply"));
  run = runParallax(dir, "convert " + quoted(str(dir / "in.xyz")) + " -o " +
                             quoted(str(dir / "out.las")) + " --properties x,y,z");
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_TRUE(has(run.err, "fixed record layout")) << run.err;
}

// ---------------------------------------------------------------------------------------------
// Partial outputs of a killed conversion

std::uint64_t bytesUnder(const std::filesystem::path& path) {
  std::uint64_t bytes = 0;
  std::error_code error;
  for (auto it = std::filesystem::recursive_directory_iterator(path, error);
       !error && it != std::filesystem::recursive_directory_iterator(); it.increment(error)) {
    std::error_code size_error;
    if (it->is_regular_file(size_error)) bytes += it->file_size(size_error);
  }
  return bytes;
}

// Starts `parallax convert IN -o OUT/` and kills it with SIGKILL once its partial output holds
// spilled points; returns the killed process's partial output.
std::filesystem::path killedConversion(const TempDir& dir, const std::string& in,
                                       const std::string& out) {
  const std::vector<std::string> args = {"parallax", "convert",  "-q", in,          "-o",
                                         out,        "--memory", "16", "--threads", "1"};
  std::vector<char*> argv;
  for (const std::string& arg : args) argv.push_back(const_cast<char*>(arg.c_str()));
  argv.push_back(nullptr);
  pid_t child = 0;
  EXPECT_EQ(::posix_spawn(&child, PARALLAX_EXECUTABLE, nullptr, nullptr, argv.data(), environ), 0);
  const std::filesystem::path partial =
      dir / ("." + std::filesystem::path(out).parent_path().filename().string() + ".partial-" +
             std::to_string(child));
  bool spilled = false;
  for (int i = 0; i < 60'000 && !spilled; ++i) {
    spilled = bytesUnder(partial / "chunks") > 0;
    if (!spilled) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    int status = 0;
    if (!spilled && ::waitpid(child, &status, WNOHANG) == child) {
      ADD_FAILURE() << "the conversion ended before it could be killed";
      return partial;
    }
  }
  EXPECT_TRUE(spilled) << "no spilled points in " << partial;
  ::kill(child, SIGKILL);
  int status = 0;
  ::waitpid(child, &status, 0);
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL);
  return partial;
}

TEST(CliPartialOutputs, CleanRemovesWhatAKilledConversionLeftAndSaysHowMuch) {
  TempDir dir;
  const std::string ply = str(dir / "scan.ply");
  ASSERT_EQ(runParallax(dir, "generate -q --points 600000 -o " + quoted(ply)).exit_code, 0);
  const std::filesystem::path partial = killedConversion(dir, ply, str(dir / "octree/"));
  ASSERT_TRUE(std::filesystem::exists(partial));
  const std::uint64_t bytes = bytesUnder(partial);
  ASSERT_GT(bytes, 0u);
  EXPECT_FALSE(std::filesystem::exists(dir / "octree"));

  // A partial output of a live process (this test's) is left alone.
  const auto alive = dir / (".octree.partial-" + std::to_string(::getpid()));
  std::filesystem::create_directory(alive);

  const RunResult run = runParallax(dir, "convert --clean -o " + quoted(str(dir / "octree/")));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_TRUE(has(run.err, "removed " + partial.string() + ", left by a killed conversion"))
      << run.err;
  EXPECT_TRUE(has(run.err, "freed " + std::to_string(bytes) + " bytes")) << run.err;
  EXPECT_TRUE(has(run.err, "left " + alive.string() + ": process " + std::to_string(::getpid()) +
                               " is still running"))
      << run.err;
  EXPECT_FALSE(std::filesystem::exists(partial));
  EXPECT_TRUE(std::filesystem::exists(alive));
  EXPECT_FALSE(std::filesystem::exists(dir / "octree"));
}

TEST(CliPartialOutputs, TheNextConversionToTheSameOutputRemovesThem) {
  TempDir dir;
  const std::string ply = str(dir / "scan.ply");
  ASSERT_EQ(runParallax(dir, "generate -q --points 600000 -o " + quoted(ply)).exit_code, 0);
  const std::filesystem::path partial = killedConversion(dir, ply, str(dir / "octree/"));
  const std::uint64_t bytes = bytesUnder(partial);
  ASSERT_GT(bytes, 0u);
  const RunResult run =
      runParallax(dir, "convert " + quoted(ply) + " -o " + quoted(str(dir / "octree/")) +
                           " --memory 64 --sampling random");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_TRUE(has(run.err, "freed " + std::to_string(bytes) + " bytes")) << run.err;
  EXPECT_FALSE(std::filesystem::exists(partial));
  EXPECT_TRUE(std::filesystem::exists(dir / "octree" / "metadata.json"));
  // Nothing else is left beside the output.
  for (const auto& entry : std::filesystem::directory_iterator(dir.path())) {
    EXPECT_EQ(entry.path().filename().string().find(".octree.partial-"), std::string::npos)
        << entry.path();
  }
}

TEST(CliPartialOutputs, CleanWithoutInputsNeedsTheFlag) {
  TempDir dir;
  const RunResult run = runParallax(dir, "convert -o " + quoted(str(dir / "x.ply")));
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_TRUE(has(run.err, "no input")) << run.err;
}

}  // namespace
}  // namespace parallax::test
