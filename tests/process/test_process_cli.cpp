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

TEST(ProcessCli, M3c2OfACloudAgainstItselfAtCorePoints) {
  // A real aerial LAS file (1 247 points about 28 m apart) against itself: both epochs hold the
  // same points in every cylinder, so the distance is 0, the counts equal, nothing significant.
  TempDir dir;
  const std::string las = test::testDataFile("laz/1815.las").string();
  auto r = runParallax(
      dir, "process " + las + " -o " + (dir / "cores.ply").string() + " --subsample random:50 -q");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = runParallax(dir,
                  "process " + las + " -o " + (dir / "m3c2.ply").string() + " --m3c2 " + las +
                      " --core-points " + (dir / "cores.ply").string() +
                      " --normal-radius 200 --cylinder-radius 40 --cylinder-half-length 50 -q");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const PointCloud out = readPointFile(dir / "m3c2.ply");
  ASSERT_EQ(out.count, 50u);
  const ScalarColumn* distance = out.findScalar("m3c2_distance");
  const ScalarColumn* n1 = out.findScalar("m3c2_count1");
  const ScalarColumn* n2 = out.findScalar("m3c2_count2");
  const ScalarColumn* significant = out.findScalar("m3c2_significant");
  ASSERT_TRUE(distance && n1 && n2 && significant);
  std::size_t measured = 0;
  for (std::size_t i = 0; i < out.count; ++i) {
    EXPECT_EQ(n1->valueAsDouble(i), n2->valueAsDouble(i)) << i;
    EXPECT_EQ(significant->valueAsDouble(i), 0.0) << i;
    if (n1->valueAsDouble(i) > 0) {
      EXPECT_EQ(distance->valueAsDouble(i), 0.0) << i;
      ++measured;
    }
  }
  EXPECT_GT(measured, 25u);
  r = runParallax(dir, "process " + las + " -o " + (dir / "o.ply").string() + " --m3c2 " + las +
                           " --normal-radius 2 --cylinder-radius 1");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("--m3c2 " + las + ": --cylinder-half-length H must be a positive number"),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "o.ply"));
}

}  // namespace
}  // namespace parallax
