// Point-to-plane ICP on real scans moved by known rigid motions: the motion comes back within
// 1 mm (every point) and 0.01 degree; no overlap is an error.
#include <gtest/gtest.h>

#include <cmath>

#include "io/point_file.h"
#include "registration/point_to_plane_icp.h"
#include "support/test_data.h"

namespace parallax {
namespace {

std::vector<Point3> readScan(const std::string& relative) {
  const PointCloud cloud = readPointFile(test::testDataFile(relative));
  std::vector<Point3> out(cloud.count);
  for (std::size_t i = 0; i < cloud.count; ++i)
    out[i] = {cloud.worldX(i), cloud.worldY(i), cloud.worldZ(i)};
  return out;
}

Point3 centreOf(const std::vector<Point3>& points) {
  Point3 lo = points[0], hi = points[0];
  for (const Point3& p : points) {
    for (std::size_t a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], p[a]);
      hi[a] = std::max(hi[a], p[a]);
    }
  }
  return {(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2};
}

struct Motion {
  Point3 axis;
  double degrees;
  Point3 shift;
};

// A rotation about the cloud's centre, then a shift: what moving a scanner does.
RigidTransform motionAbout(const Point3& c, const Motion& m) {
  return RigidTransform::translation(c[0] + m.shift[0], c[1] + m.shift[1], c[2] + m.shift[2]) *
         RigidTransform::rotation(m.axis[0], m.axis[1], m.axis[2], m.degrees) *
         RigidTransform::translation(-c[0], -c[1], -c[2]);
}

// The largest distance between where the two transforms put a point of `points`.
double largestDisagreement(const RigidTransform& a, const RigidTransform& b,
                           const std::vector<Point3>& points) {
  double worst = 0.0;
  for (const Point3& p : points) {
    const Point3 u = a.apply(p), v = b.apply(p);
    worst =
        std::max(worst, std::sqrt((u[0] - v[0]) * (u[0] - v[0]) + (u[1] - v[1]) * (u[1] - v[1]) +
                                  (u[2] - v[2]) * (u[2] - v[2])));
  }
  return worst;
}

void expectRecovered(const std::vector<Point3>& target, const std::vector<Motion>& motions,
                     double max_distance) {
  const Point3 c = centreOf(target);
  for (const Motion& m : motions) {
    const RigidTransform truth = motionAbout(c, m);
    // The source is the target moved back: registering it must find `truth`.
    const RigidTransform back = truth.inverse();
    std::vector<Point3> source(target.size());
    for (std::size_t i = 0; i < target.size(); ++i) source[i] = back.apply(target[i]);
    IcpOptions options;
    options.max_distance = max_distance;
    const IcpResult result = alignPointToPlane(source, target, {}, options);
    SCOPED_TRACE(std::to_string(m.degrees) + " degrees");
    EXPECT_LT(largestDisagreement(result.transform, truth, source), 1e-3);
    EXPECT_LT((result.transform.inverse() * truth).angleDegrees(), 0.01);
    EXPECT_NEAR(result.transform.angleDegrees(), std::abs(m.degrees), 0.01);
    EXPECT_EQ(result.overlap, 1.0);
    EXPECT_LT(result.rms, 1e-4);
  }
}

TEST(Icp, RecoversKnownMotionsOfAGeoreferencedScan) {
  // copc.js's ellipsoid.laz: 100 000 points on a 300 x 200 x 100 m surface at x = -8 242 746
  // (Web Mercator): coordinates where single precision would lose metres.
  const std::vector<Point3> target = readScan("laz/ellipsoid.laz");
  ASSERT_EQ(target.size(), 100000u);
  expectRecovered(target,
                  {{{1, 2, 3}, 3.0, {0.8, -1.2, 0.5}},
                   {{0, 0, 1}, -2.5, {2.0, 1.0, -0.3}},
                   {{1, -1, 0.5}, 1.5, {-0.5, 0.3, 1.0}}},
                  20.0);
}

TEST(Icp, RecoversKnownMotionsOfASparseAerialScan) {
  // PDAL's PTX file: 1 065 aerial LiDAR points (Autzen) over 3.4 x 4.6 km in state plane
  // coordinates, about 100 m apart: too few for the coarse levels, which are skipped.
  const std::vector<Point3> target = readScan("formats/ptx/1.2-with-color.ptx");
  ASSERT_EQ(target.size(), 1065u);
  expectRecovered(target, {{{0, 0, 1}, 2.0, {5.0, -3.0, 2.0}}, {{1, 1, 0}, -1.0, {0, 0, 4.0}}},
                  300.0);
}

TEST(Icp, NoOverlapIsAnError) {
  const std::vector<Point3> target = readScan("formats/ptx/1.2-with-color.ptx");
  std::vector<Point3> far = target;
  for (Point3& p : far) p[0] += 10000.0;
  IcpOptions options;
  options.max_distance = 50.0;
  try {
    alignPointToPlane(far, target, {}, options);
    FAIL() << "no error";
  } catch (const RegistrationError& e) {
    EXPECT_NE(std::string(e.what()).find("no overlap: 0 of"), std::string::npos) << e.what();
  }
  // --init puts it back: then it aligns.
  options.init = RigidTransform::translation(-10000.0, 0, 0);
  const IcpResult result = alignPointToPlane(far, target, {}, options);
  EXPECT_LT(largestDisagreement(result.transform, options.init, far), 1e-6);
  EXPECT_THROW(alignPointToPlane({}, target, {}, options), std::invalid_argument);
}

}  // namespace
}  // namespace parallax
