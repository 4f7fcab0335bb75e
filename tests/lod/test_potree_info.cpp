// `parallax info DIR` on a Potree 2.0 directory: runs the built executable (PARALLAX_EXECUTABLE)
// on the hand-made dataset and checks its summary, as text and as JSON.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "lod/potree_test_dataset.h"
#include "support/run_parallax.h"
#include "support/temp_dir.h"

namespace parallax {
namespace {

using test::readText;
using test::runParallax;
using test::RunResult;

TEST(PotreeInfo, JsonHasTheKeysOfFilesAndTheWholeHierarchy) {
  test::TempDir dir;
  test::potreeTestDataset().writeTo(dir / "cloud");
  const RunResult run = runParallax(dir, "info " + (dir / "cloud").string() + " --json");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const auto json = nlohmann::json::parse(run.out);
  EXPECT_EQ(json["format"], "potree");
  EXPECT_EQ(json["points"], 6);
  EXPECT_TRUE(json["elements"].is_null());
  EXPECT_EQ(json["bounds"]["min"], nlohmann::json({1001, 2002, 31}));
  EXPECT_EQ(json["bounds"]["max"], nlohmann::json({1008, 2009, 39}));
  EXPECT_EQ(json["quantization"]["scale"], nlohmann::json({0.001, 0.001, 0.001}));
  EXPECT_EQ(json["quantization"]["offset"], nlohmann::json({1000, 2000, 30}));
  EXPECT_EQ(json["attributes"],
            nlohmann::json({"x", "y", "z", "red", "green", "blue", "intensity", "classification",
                            "return_number", "number_of_returns", "scan_angle_rank", "user_data",
                            "point_source_id", "gps_time"}));
  EXPECT_EQ(json["attribute_ranges"]["x"]["min"], 1001);
  EXPECT_EQ(json["attribute_ranges"]["gps-time"]["max"], 1e9);
  EXPECT_EQ(json["attribute_ranges"]["rgb"]["max"], nlohmann::json({65535, 65535, 65535}));
  const auto& details = json["format_details"];
  EXPECT_EQ(details["version"], "2.0");
  EXPECT_EQ(details["encoding"], "DEFAULT");
  EXPECT_EQ(details["record_bytes"], 35);
  EXPECT_EQ(details["nodes"], 4);  // the proxy's chunk read too
  EXPECT_EQ(details["depth"], 2);
  EXPECT_EQ(details["declared_depth"], 0);
  EXPECT_EQ(details["potree_attributes"][5]["name"], "scan angle rank");
  EXPECT_EQ(details["potree_attributes"][5]["type"], "uint8");
  EXPECT_EQ(json["file_bytes"], readText(dir / "cloud/metadata.json").size() + 154 + 210);
  for (const char* key : {"file", "load_seconds", "mb_per_second", "million_points_per_second"}) {
    EXPECT_TRUE(json.contains(key)) << key;
  }
}

TEST(PotreeInfo, TextFromTheMetadataFilesPath) {
  test::TempDir dir;
  test::potreeTestDataset().writeTo(dir / "cloud");
  const RunResult run = runParallax(dir, "info " + (dir / "cloud/metadata.json").string());
  ASSERT_EQ(run.exit_code, 0) << run.err;
  for (const char* part :
       {"Potree 2.0, DEFAULT encoding, 35-byte records", "nodes 4 (depth 2; metadata says 0)",
        "attribute scan angle rank uint8", "points        6\n", "x y z red green blue intensity"}) {
    EXPECT_NE(run.out.find(part), std::string::npos) << part << " not in:\n" << run.out;
  }
}

TEST(PotreeInfo, ABrokenHierarchyIsAClearError) {
  test::TempDir dir;
  test::PotreeTestDataset d = test::potreeTestDataset();
  test::setEntry(d.hierarchy, 6, 1, 0, 2, 4 * 35, 3 * 35);  // r61: 2 points, 3 records
  d.writeTo(dir / "cloud");
  const RunResult run = runParallax(dir, "info " + (dir / "cloud").string());
  EXPECT_EQ(run.exit_code, 2);
  for (const char* part : {"hierarchy.bin: byte offset 132, element 'node r61'",
                           "byteSize = 2 points x 35 bytes = 70", "found byteSize 105"}) {
    EXPECT_NE(run.err.find(part), std::string::npos) << part << " not in:\n" << run.err;
  }
}

}  // namespace
}  // namespace parallax
