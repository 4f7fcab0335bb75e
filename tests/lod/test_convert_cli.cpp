// `parallax convert ... -o DIR` end to end: runs the built executable (PARALLAX_EXECUTABLE) on
// small files written here and checks exit codes, messages and the directory it writes.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "io/point_file.h"
#include "lod_test_clouds.h"
#include "support/run_parallax.h"
#include "support/temp_dir.h"

namespace parallax::test {
namespace {

TEST(ConvertCli, WritesAPotreeDirectoryForAnOutputWithoutExtension) {
  TempDir dir;
  writePointFile(makeSurfaceCloud(5000), dir / "in.ply");
  const std::string in = (dir / "in.ply").string(), out = (dir / "octree").string();
  const RunResult run =
      runParallax(dir, "convert '" + in + "' -o '" + out + "' --memory 64 --sampling random");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.err.find("Potree 2.0, 5000 points"), std::string::npos) << run.err;
  const auto metadata = nlohmann::json::parse(readText(dir / "octree" / "metadata.json"));
  EXPECT_EQ(metadata["points"], 5000);
  EXPECT_EQ(metadata["version"], "2.0");
  EXPECT_TRUE(std::filesystem::exists(dir / "octree" / "hierarchy.bin"));
  EXPECT_EQ(std::filesystem::file_size(dir / "octree" / "octree.bin"), 5000u * 36u);
}

TEST(ConvertCli, MergesSeveralInputsAndHonoursFormatPotree) {
  TempDir dir;
  writePointFile(makeSurfaceCloud(1000, 1), dir / "a.ply");
  writePointFile(makeSurfaceCloud(700, 2), dir / "b.ply");
  const RunResult run = runParallax(dir, "convert -q '" + (dir / "a.ply").string() + "' '" +
                                             (dir / "b.ply").string() + "' -o '" +
                                             (dir / "both.potree").string() + "' --format potree");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(run.err, "");  // -q: no progress, no report
  const auto metadata = nlohmann::json::parse(readText(dir / "both.potree" / "metadata.json"));
  EXPECT_EQ(metadata["points"], 1700);
}

TEST(ConvertCli, SeveralInputsIntoOnePointFileIsAnError) {
  TempDir dir;
  writePointFile(makeSurfaceCloud(10, 1), dir / "a.ply");
  const std::string a = (dir / "a.ply").string();
  const RunResult run =
      runParallax(dir, "convert '" + a + "' '" + a + "' -o '" + (dir / "out.ply").string() + "'");
  EXPECT_EQ(run.exit_code, 2);  // reported like bad input; not a crash (128 + signal)
  EXPECT_NE(run.err.find("one input when converting to a point file"), std::string::npos)
      << run.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "out.ply"));
}

TEST(ConvertCli, FileToFileConversionStillWorks) {
  TempDir dir;
  writePointFile(makeSurfaceCloud(100), dir / "in.ply");
  const RunResult run = runParallax(dir, "convert -q '" + (dir / "in.ply").string() + "' -o '" +
                                             (dir / "out.xyz").string() + "'");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(readPointFile(dir / "out.xyz").count, 100u);
}

TEST(ConvertCli, AnUnknownExtensionSaysHowToGetAnOctree) {
  TempDir dir;
  writePointFile(makeSurfaceCloud(50), dir / "in.ply");
  const RunResult run = runParallax(dir, "convert '" + (dir / "in.ply").string() + "' -o '" +
                                             (dir / "scan.potree").string() + "'");
  EXPECT_EQ(run.exit_code, 2) << run.err;
  EXPECT_NE(run.err.find("'.potree'"), std::string::npos) << run.err;
  EXPECT_NE(run.err.find("--format potree"), std::string::npos) << run.err;
  EXPECT_NE(run.err.find("-o scan.potree/"), std::string::npos) << run.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "scan.potree"));
}

TEST(ConvertCli, ANameEndingInASlashIsAnOctree) {
  TempDir dir;
  writePointFile(makeSurfaceCloud(300), dir / "in.ply");
  const RunResult run = runParallax(dir, "convert -q '" + (dir / "in.ply").string() + "' -o '" +
                                             (dir / "scan.potree").string() + "/'");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const auto metadata = nlohmann::json::parse(readText(dir / "scan.potree" / "metadata.json"));
  EXPECT_EQ(metadata["points"], 300);
  EXPECT_EQ(metadata["name"], "scan.potree");
}

TEST(ConvertCli, AnExistingDirectoryIsAnOctreeWhateverItsName) {
  TempDir dir;
  writePointFile(makeSurfaceCloud(200), dir / "in.ply");
  std::filesystem::create_directory(dir / "tiles.las");  // empty: a name, not a LAS file
  const RunResult run = runParallax(dir, "convert -q '" + (dir / "in.ply").string() + "' -o '" +
                                             (dir / "tiles.las").string() + "'");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const auto metadata = nlohmann::json::parse(readText(dir / "tiles.las" / "metadata.json"));
  EXPECT_EQ(metadata["points"], 200);
}

TEST(ConvertCli, FormatPotreeOverridesAPointFileExtension) {
  TempDir dir;
  writePointFile(makeSurfaceCloud(120), dir / "in.ply");
  const RunResult run = runParallax(dir, "convert -q '" + (dir / "in.ply").string() + "' -o '" +
                                             (dir / "octree.ply").string() + "' --format potree");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_TRUE(std::filesystem::is_directory(dir / "octree.ply"));
  const auto metadata = nlohmann::json::parse(readText(dir / "octree.ply" / "metadata.json"));
  EXPECT_EQ(metadata["points"], 120);
}

// --properties on an octree output: only those attributes (and the positions) are kept, in
// Potree's order; a name no input has, and a distributed plan, are refused.
TEST(ConvertCli, PropertiesKeepFewerAttributesInAnOctree) {
  TempDir dir;
  writePointFile(makeSurfaceCloud(3000), dir / "in.laz", {.las_point_format = 7});
  const std::string in = (dir / "in.laz").string();
  const RunResult run = runParallax(dir, "convert -q '" + in + "' -o '" + (dir / "rgb").string() +
                                             "/' --properties blue,green,red");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const auto metadata = nlohmann::json::parse(readText(dir / "rgb" / "metadata.json"));
  std::vector<std::string> names;
  for (const auto& attribute : metadata["attributes"]) names.push_back(attribute["name"]);
  EXPECT_EQ(names, (std::vector<std::string>{"position", "rgb"}));
  EXPECT_EQ(metadata["points"], 3000);

  const RunResult unknown = runParallax(
      dir, "convert '" + in + "' -o '" + (dir / "bad").string() + "/' --properties red,hue");
  EXPECT_EQ(unknown.exit_code, 1) << unknown.err;
  EXPECT_NE(
      unknown.err.find("--properties: no attribute 'hue' in " + in + " (" + in + " has x,y,z,"),
      std::string::npos)
      << unknown.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "bad"));

  const RunResult plan = runParallax(dir, "convert '" + in + "' -o '" + (dir / "planned").string() +
                                              "/' --plan --work-dir '" + (dir / "work").string() +
                                              "' --properties red");
  EXPECT_EQ(plan.exit_code, 1) << plan.err;
  EXPECT_NE(plan.err.find("--plan"), std::string::npos) << plan.err;
}

}  // namespace
}  // namespace parallax::test
