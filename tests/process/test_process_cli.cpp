// `parallax process` as a user runs it: the steps in the order given, attributes of a real LAS
// file kept, errors naming the step.
#include <gtest/gtest.h>

#include "io/point_file.h"
#include "support/run_parallax.h"
#include "support/test_data.h"

namespace parallax {
namespace {

using test::runParallax;
using test::TempDir;

TEST(ProcessCli, StepsRunInTheOrderGivenAndAttributesAreKept) {
  TempDir dir;
  const std::filesystem::path las = test::testDataFile("laz/1815.las");
  const PointCloud input = readPointFile(las);
  // Subsampling to 300 points then normals: every output point has a normal. Normals then
  // subsampling gives the same points (normals remove nothing) but from other neighbourhoods.
  auto a = runParallax(dir, "process " + las.string() + " -o " + (dir / "a.ply").string() +
                                " --subsample random:300 --normals 8 -q");
  ASSERT_EQ(a.exit_code, 0) << a.err;
  auto b = runParallax(dir, "process " + las.string() + " -o " + (dir / "b.ply").string() +
                                " --normals 8 --subsample random:300 -q");
  ASSERT_EQ(b.exit_code, 0) << b.err;
  const PointCloud pa = readPointFile(dir / "a.ply"), pb = readPointFile(dir / "b.ply");
  ASSERT_EQ(pa.count, 300u);
  ASSERT_EQ(pb.count, 300u);
  ASSERT_TRUE(pa.hasNormals());
  bool differ = false;
  for (std::size_t i = 0; i < pa.count; ++i) {
    EXPECT_EQ(pa.positions[i], pb.positions[i]);
    differ = differ || !(pa.normals[i] == pb.normals[i]);
  }
  EXPECT_TRUE(differ) << "the normals of 300 points and of 1247 points should differ somewhere";
  // The LAS attributes travel into the PLY: intensity, classification and the other scalars.
  EXPECT_EQ(pa.hasIntensity(), input.hasIntensity());
  EXPECT_EQ(pa.hasClassification(), input.hasClassification());
  EXPECT_EQ(pa.scalars.size(), input.scalars.size());
}

TEST(ProcessCli, BadParametersExitWithTheStepNamed) {
  TempDir dir;
  const std::filesystem::path las = test::testDataFile("laz/1815.las");
  auto r = runParallax(dir, "process " + las.string() + " -o " + (dir / "o.ply").string() +
                                " --normals 16 --outliers statistical:8");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("--outliers statistical:8: expected statistical:K,S"), std::string::npos)
      << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "o.ply"));
  r = runParallax(dir, "process " + las.string() + " -o " + (dir / "o.ply").string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("no step given"), std::string::npos) << r.err;
  r = runParallax(dir, "process " + (dir / "missing.las").string() + " -o " +
                           (dir / "o.ply").string() + " --normals 8");
  EXPECT_EQ(r.exit_code, 2) << r.err;
}

TEST(ProcessCli, GroundThenHeightAboveGroundFromTheCommandLine) {
  TempDir dir;
  const std::filesystem::path las = test::testDataFile("laz/1815.las");
  auto r = runParallax(dir, "process " + las.string() + " -o " + (dir / "g.las").string() +
                                " --ground smrf:cell=30,window=300,slope=0.05 "
                                "--height-above-ground -q");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const PointCloud out = readPointFile(dir / "g.las");
  ASSERT_EQ(out.count, 1247u);
  const ScalarColumn* hag = out.findScalar("height_above_ground");
  ASSERT_NE(hag, nullptr);
  std::size_t ground = 0;
  for (std::size_t i = 0; i < out.count; ++i) {
    ASSERT_TRUE(out.classification[i] == 1 || out.classification[i] == 2);
    if (out.classification[i] == 2) {
      ++ground;
      EXPECT_EQ(hag->as<float>()[i], 0.0f);  // a vertex of the ground's triangulation
    }
  }
  EXPECT_GT(ground, 100u);
  // Heights before any ground: the input's own class 2 points (1815.las has 244).
  r = runParallax(dir, "process " + las.string() + " -o " + (dir / "h.las").string() +
                           " --height-above-ground -q");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = runParallax(dir, "process " + las.string() + " -o " + (dir / "o.las").string() +
                           " --ground smrf:window=0");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("--ground smrf:window=0: window must be a positive number, got '0'"),
            std::string::npos)
      << r.err;
}

}  // namespace
}  // namespace parallax
