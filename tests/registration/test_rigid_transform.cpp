// RigidTransform's algebra against hand-computed values, the --init text form (errors naming the
// file and line), and transformCloud on a cloud far from the origin.
#include <gtest/gtest.h>

#include <cmath>

#include "core/error.h"
#include "registration/rigid_transform.h"

namespace parallax {
namespace {

std::string messageOf(const std::string& text) {
  try {
    parseRigidTransform(text, "init.txt");
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(RigidTransform, RotationComposeInverseAndAngle) {
  const RigidTransform r = RigidTransform::rotation(0, 0, 1, 90);
  const auto p = r.apply({1, 0, 0});
  EXPECT_NEAR(p[0], 0.0, 1e-15);
  EXPECT_NEAR(p[1], 1.0, 1e-15);
  const RigidTransform t = RigidTransform::translation(500000, 4e6, 10) * r;
  const RigidTransform back = t.inverse() * t;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) EXPECT_NEAR(back.m[i][j], i == j ? 1.0 : 0.0, 1e-9);
  EXPECT_NEAR(RigidTransform::rotation(1, 2, 3, 3.5).angleDegrees(), 3.5, 1e-12);
  EXPECT_NEAR(RigidTransform::rotation(1, 2, 3, 1e-7).angleDegrees(), 1e-7, 1e-19);
  // Rz Ry Rx of small angles equals the rotation about x alone when the others are 0.
  const RigidTransform x = RigidTransform::fromEuler(0.25, 0, 0);
  const RigidTransform ax = RigidTransform::rotation(1, 0, 0, 0.25 * 180.0 / M_PI);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) EXPECT_NEAR(x.m[i][j], ax.m[i][j], 1e-15);
}

TEST(RigidTransform, TextFormReadsBackExactly) {
  const RigidTransform t = RigidTransform::translation(-8242596.125, 4966606.5, 0.001) *
                           RigidTransform::rotation(0.3, -1, 0.2, 2.75);
  const RigidTransform back = parseRigidTransform(formatRigidTransform(t), "t.txt");
  EXPECT_EQ(back.m, t.m);
  const RigidTransform commas =
      parseRigidTransform("# from CloudCompare\n1,0,0,5\n0\t1 0 6\n\n0 0 1 7\r\n0 0 0 1\n", "c");
  EXPECT_EQ(commas.m[0][3], 5.0);
  EXPECT_EQ(commas.m[2][3], 7.0);
}

TEST(RigidTransform, BadMatricesAreErrorsNamingTheFileAndLine) {
  EXPECT_EQ(messageOf("1 0 0 0\n0 1 0 0\n0 0 1 0\n"),
            "init.txt: line 3: expected four rows of four numbers (a 4x4 matrix), found 3 rows");
  EXPECT_EQ(messageOf("1 0 0 0\n0 1 x 0\n0 0 1 0\n0 0 0 1\n"),
            "init.txt: line 2: expected four numbers on row 2, found 'x'");
  EXPECT_EQ(messageOf("1 0 0\n"), "init.txt: line 1: expected four numbers on row 1, found 3");
  EXPECT_EQ(messageOf("1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 2\n"),
            "init.txt: line 4: expected a last row of 0 0 0 1 (a rigid transform), found another "
            "last row");
  EXPECT_NE(messageOf("2 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n").find("a rotation"),
            std::string::npos);
  EXPECT_NE(messageOf("-1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n").find("a reflection"),
            std::string::npos);
  EXPECT_NE(messageOf("1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n1 0 0 0\n").find("line 5"),
            std::string::npos);
  try {
    readRigidTransform("/nonexistent/init.txt");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/init.txt"), std::string::npos);
  }
}

TEST(RigidTransform, TransformCloudMovesPositionsAndRotatesNormals) {
  PointCloud cloud;
  cloud.count = 2;
  cloud.quantization.scale = {0.001, 0.001, 0.001};
  cloud.quantization.offset = {500000, 4000000, 0};
  cloud.positions = Column<Int3>(2);
  cloud.positions[0] = {1000, 2000, 3000};  // (500001, 4000002, 3)
  cloud.positions[1] = {-5000, 0, 0};
  cloud.normals = Column<Float3>(2);
  cloud.normals[0] = {1, 0, 0};
  cloud.normals[1] = {0, 0, 1};
  const RigidTransform t =
      RigidTransform::translation(10, -20, 0.5) * RigidTransform::rotation(0, 0, 1, 90);
  transformCloud(cloud, t);
  // (x, y) -> (-y, x) + (10, -20): (500001, 4000002) -> (-3999992, 499981).
  EXPECT_NEAR(cloud.worldX(0), -4000002.0 + 10.0, 1e-9);
  EXPECT_NEAR(cloud.worldY(0), 500001.0 - 20.0, 1e-9);
  EXPECT_NEAR(cloud.worldZ(0), 3.5, 1e-9);
  EXPECT_NEAR(cloud.normals[0].x, 0.0f, 1e-7);
  EXPECT_NEAR(cloud.normals[0].y, 1.0f, 1e-7);
  EXPECT_EQ(cloud.normals[1].z, 1.0f);
}

}  // namespace
}  // namespace parallax
