// The command line end to end: runs the built `parallax` (PARALLAX_EXECUTABLE) on small files
// written here, and checks exit codes and output.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "support/run_parallax.h"
#include "support/temp_dir.h"

namespace parallax::test {
namespace {

// Three points whose coordinates are exact in float and in any power-of-two quantization, so the
// expected bounds are exact.
constexpr const char* kTinyPly =
    "ply\n"
    "format ascii 1.0\n"
    "comment three points for the CLI tests\n"
    "element vertex 3\n"
    "property float x\n"
    "property float y\n"
    "property float z\n"
    "property uchar red\n"
    "property uchar green\n"
    "property uchar blue\n"
    "property float quality\n"
    "end_header\n"
    "1 2 3 255 0 7 10\n"
    "-4.5 0.25 10 0 128 64 20\n"
    "2 -8 0.5 7 64 0 30\n";

TEST(Cli, VersionListsEveryFormatOfTheTable) {
  // The formats line is the format table's (`info --formats`), not a list kept by hand.
  TempDir dir;
  const RunResult run = runParallax(dir, "--version");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const auto at = run.out.find("  formats: ");
  ASSERT_NE(at, std::string::npos) << run.out;
  const std::string line = run.out.substr(at, run.out.find('\n', at) - at);
  for (const char* name : {"PLY", "LAS", "LAZ", "E57", "PCD", "PTX", "PTS", "text", "COPC"}) {
    EXPECT_NE(line.find(name), std::string::npos) << name << " not in: " << line;
  }
}

TEST(Cli, ADirectoryOrAnEmptyFileIsSaidToBeOne) {
  // Not "byte offset 0: ... found an unknown format": what the input is, and what was expected.
  TempDir dir;
  std::filesystem::create_directory(dir / "folder");
  const auto empty = dir.write("empty.xyz", "");
  RunResult run = runParallax(dir, "info " + quoted((dir / "folder").string()));
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_NE(run.err.find("folder: expected a point cloud file, or a Potree 2.0 octree directory"),
            std::string::npos)
      << run.err;
  EXPECT_NE(run.err.find("found a directory without them"), std::string::npos) << run.err;
  run = runParallax(
      dir, "convert " + quoted(empty.string()) + " -o " + quoted((dir / "out.las").string()));
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_NE(run.err.find("empty.xyz: byte offset 0: expected a point cloud file, found an empty "
                         "file (0 bytes)"),
            std::string::npos)
      << run.err;
}

TEST(Cli, InfoJsonHasExactPointsBoundsAndAttributes) {
  TempDir dir;
  const auto file = dir.write("tiny.ply", kTinyPly);
  const RunResult run = runParallax(dir, "info --json " + quoted(file.string()));
  ASSERT_EQ(run.exit_code, 0) << run.err;

  const auto json = nlohmann::json::parse(run.out);  // throws (fails the test) unless one object
  ASSERT_TRUE(json.is_object());
  EXPECT_TRUE(json["points"].is_number_integer());
  EXPECT_EQ(json["points"].get<std::int64_t>(), 3);
  EXPECT_EQ(json["bounds"]["min"], nlohmann::json({-4.5, -8.0, 0.5}));
  EXPECT_EQ(json["bounds"]["max"], nlohmann::json({2.0, 2.0, 10.0}));
  EXPECT_EQ(json["attributes"], nlohmann::json({"x", "y", "z", "red", "green", "blue", "quality"}));
  EXPECT_EQ(json["format"], "ply");
  EXPECT_EQ(json["file_bytes"].get<std::uint64_t>(), std::string(kTinyPly).size());
  EXPECT_EQ(json["attribute_ranges"]["red"], nlohmann::json({{"min", 0.0}, {"max", 255.0}}));
  EXPECT_EQ(json["attribute_ranges"]["quality"], nlohmann::json({{"min", 10.0}, {"max", 30.0}}));
  EXPECT_EQ(json["attribute_ranges"]["z"], nlohmann::json({{"min", 0.5}, {"max", 10.0}}));
  ASSERT_EQ(json["elements"].size(), 1u);
  EXPECT_EQ(json["elements"][0]["name"], "vertex");
  EXPECT_EQ(json["elements"][0]["count"], 3);
  EXPECT_EQ(json["elements"][0]["properties"].size(), 7u);
  EXPECT_EQ(json["format_details"]["comments"][0], "three points for the CLI tests");
  EXPECT_TRUE(json["load_seconds"].is_number());
}

TEST(Cli, InfoPrintsHeaderAndRanges) {
  TempDir dir;
  const auto file = dir.write("tiny.ply", kTinyPly);
  const RunResult run = runParallax(dir, "info " + quoted(file.string()));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.out.find("ascii 1.0"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("element vertex 3"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("property uchar red"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("points        3"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("quality"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("M points/s"), std::string::npos) << run.out;
}

TEST(Cli, InfoOnMalformedFileFailsNamingTheFile) {
  TempDir dir;
  const auto file = dir.write("broken_values.ply",
                              "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\n"
                              "property float y\nproperty float z\nend_header\n1 2 3\n4 abc 6\n");
  const RunResult run = runParallax(dir, "info --json " + quoted(file.string()));
  EXPECT_EQ(run.exit_code, 2) << run.err;  // bad input, not a crash (128 + signal)
  EXPECT_NE(run.err.find("broken_values.ply"), std::string::npos) << run.err;
  EXPECT_EQ(run.out, "");  // nothing half-printed on stdout
}

TEST(Cli, InfoOnMissingFileFailsNamingTheFile) {
  TempDir dir;
  const RunResult run = runParallax(dir, "info " + quoted((dir / "no_such_file.ply").string()));
  EXPECT_EQ(run.exit_code, 2) << run.err;  // bad input, not a crash (128 + signal)
  EXPECT_NE(run.err.find("no_such_file.ply"), std::string::npos) << run.err;
}

TEST(Cli, InfoOnNonPointFileFails) {
  TempDir dir;
  const auto file = dir.write("notes.bin", std::string("\x01\x02\x03\x04 not points", 16));
  const RunResult run = runParallax(dir, "info " + quoted(file.string()));
  EXPECT_EQ(run.exit_code, 2) << run.err;  // bad input, not a crash (128 + signal)
  EXPECT_NE(run.err.find("notes.bin"), std::string::npos) << run.err;
}

TEST(Cli, GenerateWritesTheRequestedPointCount) {
  TempDir dir;
  const auto file = dir / "generated.ply";
  const RunResult generate =
      runParallax(dir, "generate -o " + quoted(file.string()) + " --points 10000");
  ASSERT_EQ(generate.exit_code, 0) << generate.err;

  const RunResult info = runParallax(dir, "info --json " + quoted(file.string()));
  ASSERT_EQ(info.exit_code, 0) << info.err;
  const auto json = nlohmann::json::parse(info.out);
  EXPECT_EQ(json["points"].get<std::int64_t>(), 10000);
}

TEST(Cli, BenchLoadPrintsTheRatioToTheReference) {
  TempDir dir;
  const auto file = dir.write("tiny.ply", kTinyPly);
  const RunResult run = runParallax(dir, "bench load " + quoted(file.string()) + " --repeat 2");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.out.find("ratio      load / reference = "), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("3 points"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("peak RSS"), std::string::npos) << run.out;
}

TEST(Cli, BenchWithoutModeIsAUsageError) {
  TempDir dir;
  const RunResult run = runParallax(dir, "bench");
  // CLI11's own usage-error status (RequiredError), whatever its number: a normal exit, neither 0
  // nor a signal's 128 + N, and the reason on stderr.
  EXPECT_GT(run.exit_code, 0);
  EXPECT_LT(run.exit_code, 128);
  EXPECT_NE(run.err.find("A subcommand is required"), std::string::npos) << run.err;
}

}  // namespace
}  // namespace parallax::test
