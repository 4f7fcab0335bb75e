// `parallax register` as a user runs it: the --json and printed results for a real scan moved by
// a known motion, -o keeping every attribute, and errors naming the file.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "io/point_file.h"
#include "registration/rigid_transform.h"
#include "support/run_parallax.h"
#include "support/test_data.h"

namespace parallax {
namespace {

using test::runParallax;
using test::TempDir;

TEST(RegisterCli, JsonTransformAndAlignedOutputKeepEveryAttribute) {
  TempDir dir;
  const std::filesystem::path las = test::testDataFile("laz/ellipsoid.laz");
  PointCloud moved = readPointFile(las);
  const PointCloud original = readPointFile(las);
  // The source: the scan moved away by the inverse of `truth` (about its own centre), written
  // with millimetre integers so the motion survives quantization.
  const double c[3] = {-8242596.0, 4966606.0, 0.0};
  const RigidTransform truth = RigidTransform::translation(c[0] + 0.7, c[1] - 0.2, c[2] + 0.4) *
                               RigidTransform::rotation(0.2, -0.4, 1.0, 2.0) *
                               RigidTransform::translation(-c[0], -c[1], -c[2]);
  moved.quantization.scale = {0.0001, 0.0001, 0.0001};
  moved.quantization.offset = {c[0], c[1], c[2]};
  for (std::size_t i = 0; i < moved.count; ++i) {
    const auto p =
        truth.inverse().apply({original.worldX(i), original.worldY(i), original.worldZ(i)});
    moved.positions[i] = {moved.quantization.toQuantized(0, p[0]),
                          moved.quantization.toQuantized(1, p[1]),
                          moved.quantization.toQuantized(2, p[2])};
  }
  writePointFile(moved, dir / "source.ply");
  auto r = runParallax(dir, "register " + (dir / "source.ply").string() + " " + las.string() +
                                " --max-distance 20 --json -o " + (dir / "aligned.ply").string() +
                                " -q");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json out = nlohmann::json::parse(r.out);
  ASSERT_EQ(out["transform"].size(), 4u);
  RigidTransform found;
  for (int i = 0; i < 4; ++i) {
    ASSERT_EQ(out["transform"][i].size(), 4u);
    for (int j = 0; j < 4; ++j) found.m[i][j] = out["transform"][i][j].get<double>();
  }
  EXPECT_LT((found.inverse() * truth).angleDegrees(), 0.01);
  const auto a = found.apply({c[0] + 100, c[1] + 50, 20}),
             b = truth.apply({c[0] + 100, c[1] + 50, 20});
  EXPECT_NEAR(a[0], b[0], 1e-3);
  EXPECT_NEAR(a[1], b[1], 1e-3);
  EXPECT_NEAR(a[2], b[2], 1e-3);
  EXPECT_EQ(out["overlap"].get<double>(), 1.0);
  // The LAS file's centimetres moved by up to 0.1 mm of rounding: the RMS is of that order.
  EXPECT_LT(out["rms"].get<double>(), 1e-3);
  const PointCloud aligned = readPointFile(dir / "aligned.ply");
  ASSERT_EQ(aligned.count, original.count);
  EXPECT_EQ(aligned.scalars.size(), original.scalars.size());
  ASSERT_TRUE(aligned.hasColors());
  for (std::size_t i = 0; i < aligned.count; i += 997) {
    EXPECT_NEAR(aligned.worldX(i), original.worldX(i), 2e-3) << i;
    EXPECT_NEAR(aligned.worldZ(i), original.worldZ(i), 2e-3) << i;
    EXPECT_EQ(aligned.colors[i], original.colors[i]);
  }

  r = runParallax(dir, "register " + (dir / "source.ply").string() + " " + las.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("rms "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("overlap 1.000000 (100000 of 100000 source points"), std::string::npos)
      << r.out;
}

TEST(RegisterCli, MissingFilesAndNoOverlapAreErrorsNamingThem) {
  TempDir dir;
  const std::string las = test::testDataFile("laz/1815.las").string();
  auto r = runParallax(dir, "register " + (dir / "missing.ply").string() + " " + las);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("missing.ply"), std::string::npos) << r.err;
  r = runParallax(dir, "register " + las + " " + las + " --init " + (dir / "init.txt").string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("init.txt"), std::string::npos) << r.err;
  // Moved 100 km away by --init: nothing within the maximum distance.
  dir.write("far.txt", "1 0 0 100000\n0 1 0 0\n0 0 1 0\n0 0 0 1\n");
  r = runParallax(dir, "register " + las + " " + las + " --max-distance 5 --init " +
                           (dir / "far.txt").string() + " -o " + (dir / "o.ply").string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("register " + las + " to " + las + ": no overlap: 0 of"), std::string::npos)
      << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "o.ply"));
}

}  // namespace
}  // namespace parallax
