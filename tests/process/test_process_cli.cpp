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

// A real LAS file processed into a Potree directory: every point, its scale, offset and CRS
// (the LAS file of the result the octree is built from keeps them), the normals as nx ny nz;
// `info` lists them and `render` draws the octree.
TEST(ProcessCli, ALasFileIntoAnOctreeKeepsItsCrsAndScale) {
  TempDir dir;
  const std::filesystem::path las = test::testDataFile("laz/1815.las");
  const auto octree = dir / "octree";
  auto run = runParallax(dir, "process " + las.string() + " -o " + octree.string() +
                                  "/ --normals 8 --outliers statistical:8,3 -q");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  auto points = runParallax(dir, "process " + las.string() + " -o " + (dir / "p.las").string() +
                                     " --normals 8 --outliers statistical:8,3 -q");
  ASSERT_EQ(points.exit_code, 0) << points.err;
  const PointCloud expected = readPointFile(dir / "p.las");
  auto info = runParallax(dir, "info " + octree.string());
  ASSERT_EQ(info.exit_code, 0) << info.err;
  EXPECT_NE(info.out.find("points        " + std::to_string(expected.count)), std::string::npos)
      << info.out;
  EXPECT_NE(info.out.find("scale (1e-05, 1e-05, 1e-05)"), std::string::npos) << info.out;
  EXPECT_NE(info.out.find("projection    EPSG:6580"), std::string::npos) << info.out;
  EXPECT_NE(info.out.find(" nx ny nz"), std::string::npos) << info.out;
  auto render =
      runParallax(dir, "render " + octree.string() + " -o " + (dir / "octree.png").string() +
                           " --width 64 --height 64 --color elevation");
  EXPECT_EQ(render.exit_code, 0) << render.err;
  EXPECT_TRUE(std::filesystem::exists(dir / "octree.png"));
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
