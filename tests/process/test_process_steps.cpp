// runProcess end to end on files written here: every step against its definition computed by
// brute force in the test, normals against analytic surfaces, and the same bytes at any --memory.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <fstream>
#include <map>
#include <numbers>
#include <numeric>
#include <random>
#include <set>
#include <sstream>

#include "core/error.h"
#include "core/point_gather.h"
#include "io/e57/e57_writer.h"
#include "io/las_header.h"
#include "io/las_writer.h"
#include "io/laz_writer.h"
#include "io/ply_writer.h"
#include "io/point_file.h"
#include "lod/octree_open.h"
#include "process/process_runner.h"
#include "process_test_clouds.h"
#include "support/temp_dir.h"

namespace parallax {
namespace {

using test::readPositions;
using test::TempDir;
using test::writeCloud;
using test::Xyz;

// The options of a run of `steps` from `in` to `out` within `memory_mb`.
ProcessOptions runOptions(const std::filesystem::path& in, const std::filesystem::path& out,
                          std::vector<ProcessStep> steps, std::uint64_t memory_mb = 2048) {
  ProcessOptions options;
  options.inputs = {ConvertInput{.path = in}};
  options.output = out;
  options.steps = std::move(steps);
  options.memory_mb = memory_mb;
  return options;
}

ProcessReport run(const std::filesystem::path& in, const std::filesystem::path& out,
                  std::vector<ProcessStep> steps, std::uint64_t memory_mb = 2048) {
  return runProcess(runOptions(in, out, std::move(steps), memory_mb));
}

std::vector<std::uint32_t> ids(const PointCloud& cloud) {
  const ScalarColumn* id = cloud.findScalar("id");
  EXPECT_NE(id, nullptr);
  std::vector<std::uint32_t> out;
  for (std::size_t i = 0; id && i < cloud.count; ++i) out.push_back(id->as<std::uint32_t>()[i]);
  return out;
}

double d2(const Xyz& a, const Xyz& b) {
  const double dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
  return (dx * dx + dy * dy) + dz * dz;
}

// The sorted squared distances from point q to the others (brute force).
std::vector<double> distancesFrom(const std::vector<Xyz>& points, std::size_t q) {
  std::vector<double> out;
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (i != q) out.push_back(d2(points[q], points[i]));
  }
  std::sort(out.begin(), out.end());
  return out;
}

// A rough terrain with scattered points above it: outliers for the outlier steps.
std::vector<Xyz> terrainWithNoise(std::size_t count, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 40.0);
  std::normal_distribution<double> noise(0.0, 0.02);
  std::vector<Xyz> points;
  for (std::size_t i = 0; i < count; ++i) {
    const double x = u(rng), y = u(rng);
    double z = std::sin(x * 0.3) + 0.5 * std::cos(y * 0.2) + noise(rng);
    if (i % 97 == 0) z += 2.0 + u(rng) * 0.2;  // a point floating above the ground
    points.push_back({x, y, z});
  }
  return points;
}

double angleDegrees(const Float3& n, const Xyz& expected) {
  const double len =
      std::sqrt(expected[0] * expected[0] + expected[1] * expected[1] + expected[2] * expected[2]);
  const double dot = (n.x * expected[0] + n.y * expected[1] + n.z * expected[2]) / len;
  return std::acos(std::min(1.0, std::abs(dot))) * 180.0 / std::numbers::pi;
}

struct Surface {
  std::string name;
  std::vector<Xyz> points;
  std::vector<Xyz> normals;    // analytic
  std::vector<bool> interior;  // at least 1 from the surface's edge
};

// Plane, sphere and cylinder sampled evenly (golden-angle spirals and grids), optionally with
// Gaussian noise along the normal.
std::vector<Surface> surfaces(double noise_sigma) {
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, noise_sigma);
  auto jitter = [&] { return noise_sigma > 0 ? noise(rng) : 0.0; };
  std::vector<Surface> out;
  Surface plane{"plane", {}, {}, {}};
  const Xyz pn = {0.3, -0.2, 1.0};
  const double pl = std::sqrt(0.09 + 0.04 + 1.0);
  for (int i = 0; i < 120; ++i) {
    for (int j = 0; j < 120; ++j) {
      const double x = i * 0.1 + 0.013 * (j % 7), y = j * 0.1 + 0.011 * (i % 5);
      const double e = jitter();
      const double z = -(0.3 * x - 0.2 * y) + 5.0;
      plane.points.push_back({x + e * pn[0] / pl, y + e * pn[1] / pl, z + e * pn[2] / pl});
      plane.normals.push_back(pn);
      plane.interior.push_back(x > 1.0 && x < 10.9 && y > 1.0 && y < 10.9);
    }
  }
  out.push_back(plane);
  Surface sphere{"sphere", {}, {}, {}};
  const int n = 20000;
  for (int i = 0; i < n; ++i) {
    const double zc = 1.0 - 2.0 * (i + 0.5) / n, r = std::sqrt(1.0 - zc * zc),
                 phi = i * 2.399963229728653;
    const Xyz dir = {r * std::cos(phi), r * std::sin(phi), zc};
    const double radius = 10.0 + jitter();
    sphere.points.push_back({dir[0] * radius, dir[1] * radius, dir[2] * radius});
    sphere.normals.push_back(dir);
    sphere.interior.push_back(true);
  }
  out.push_back(sphere);
  Surface cylinder{"cylinder", {}, {}, {}};
  for (int i = 0; i < 160; ++i) {
    for (int j = 0; j < 120; ++j) {
      const double a = (j + 0.5 * (i % 2)) * 2.0 * std::numbers::pi / 120.0;
      const double radius = 4.0 + jitter();
      cylinder.points.push_back({radius * std::cos(a), radius * std::sin(a), i * 0.2});
      cylinder.normals.push_back({std::cos(a), std::sin(a), 0.0});
      cylinder.interior.push_back(i * 0.2 > 1.0 && i * 0.2 < 30.8);
    }
  }
  out.push_back(cylinder);
  return out;
}

// `interior_only`: the points whose neighbourhood the surface's edge does not cut (a one-sided
// neighbourhood of noisy points tilts: its lever is half as long).
void expectNormalsWithin(double noise_sigma, std::uint32_t k, double degrees, bool interior_only) {
  TempDir dir;
  for (const Surface& s : surfaces(noise_sigma)) {
    const auto in = writeCloud(dir, s.name + ".ply", s.points);
    NormalsStep step;
    step.k = k;
    run(in, dir / (s.name + "_n.ply"), {step});
    const PointCloud out = readPointFile(dir / (s.name + "_n.ply"));
    ASSERT_EQ(out.count, s.points.size());
    ASSERT_TRUE(out.hasNormals());
    double worst = 0.0;
    std::size_t worst_at = 0;
    for (std::size_t i = 0; i < out.count; ++i) {
      const double angle =
          interior_only && !s.interior[i] ? 0.0 : angleDegrees(out.normals[i], s.normals[i]);
      if (angle > worst) {
        worst = angle;
        worst_at = i;
      }
      if (s.name == "plane") {
        EXPECT_GT(out.normals[i].z, 0.0f) << "--orient up";
      }
    }
    EXPECT_LT(worst, degrees) << s.name << " noise " << noise_sigma << " at point " << worst_at;
  }
}

TEST(ProcessNormals, WithinHalfADegreeOfAnalyticSurfaces) {
  expectNormalsWithin(0.0, 16, 0.5, false);  // every point, edges included
}

TEST(ProcessNormals, NoisySurfacesWithinHalfADegree) {
  // Gaussian noise along the normal of a hundredth of the spacing (0.1 plane, 0.22 sphere, 0.2
  // cylinder); 48 neighbours average it out. Within 1 of the plane's and the cylinder's
  // edges the worst point is 1.8 degrees off.
  expectNormalsWithin(0.001, 48, 0.5, true);
}

TEST(ProcessNormals, RadiusAndOrientationTowardsAPointAndCurvature) {
  TempDir dir;
  const Surface sphere = surfaces(0.0)[1];
  const auto in = writeCloud(dir, "sphere.ply", sphere.points);
  NormalsStep step;
  step.radius = 0.8;
  step.curvature = true;
  step.orientation = NormalOrientation::kPoint;  // towards the centre: every normal inwards
  run(in, dir / "out.ply", {step});
  const PointCloud out = readPointFile(dir / "out.ply");
  ASSERT_EQ(out.count, sphere.points.size());
  const ScalarColumn* curvature = out.findScalar("curvature");
  ASSERT_NE(curvature, nullptr);
  for (std::size_t i = 0; i < out.count; ++i) {
    const Xyz& d = sphere.normals[i];
    EXPECT_LT(out.normals[i].x * d[0] + out.normals[i].y * d[1] + out.normals[i].z * d[2], -0.9999);
    // A sphere of radius 10 seen 0.8 around: nearly flat, but not quite.
    EXPECT_GT(curvature->valueAsDouble(i), 0.0);
    EXPECT_LT(curvature->valueAsDouble(i), 0.01);
  }
}

TEST(ProcessNormals, PropagationOrientsAClosedSphereConsistently) {
  // Normals alone are only up to sign; propagated from the top point (turned up), every normal of
  // a closed sphere points out, the lower half included.
  TempDir dir;
  Surface sphere = surfaces(0.0)[1];
  const auto in = writeCloud(dir, "sphere.ply", sphere.points);
  NormalsStep step;
  step.k = 12;
  step.orientation = NormalOrientation::kPropagate;
  run(in, dir / "out.ply", {step});
  const PointCloud out = readPointFile(dir / "out.ply");
  ASSERT_EQ(out.count, sphere.points.size());
  std::size_t inward = 0;
  for (std::size_t i = 0; i < out.count; ++i) {
    const Xyz& d = sphere.normals[i];
    inward += out.normals[i].x * d[0] + out.normals[i].y * d[1] + out.normals[i].z * d[2] < 0.0;
  }
  EXPECT_EQ(inward, 0u);
  // Over several tiles (--memory 1: slabs of 4 096 points, the sphere cut into 5 rings) the
  // orientation crosses every border: every normal still points out, the same as in one tile.
  run(in, dir / "tiled.ply", {step}, 1);
  const PointCloud tiled = readPointFile(dir / "tiled.ply");
  ASSERT_EQ(tiled.count, out.count);
  std::size_t tiled_inward = 0, differing = 0;
  for (std::size_t i = 0; i < tiled.count; ++i) {
    const Xyz& d = sphere.normals[i];
    const auto& n = tiled.normals[i];
    tiled_inward += n.x * d[0] + n.y * d[1] + n.z * d[2] < 0.0;
    differing += n.x != out.normals[i].x || n.y != out.normals[i].y || n.z != out.normals[i].z;
  }
  EXPECT_EQ(tiled_inward, 0u);
  EXPECT_EQ(differing, 0u);
}

TEST(ProcessNormals, PropagationCrossesTileBordersOnAFoldedSheet) {
  // A sheet folded back on itself: z = 0 for x in [0, 10], a half cylinder of radius 0.5 around
  // x = 10, z = 0.5, and z = 1 back over x in [0, 10]. Propagated from the highest point (on the
  // upper layer, turned up) through the fold, the lower layer's normals point down. Cut into
  // slabs of x (--memory 1), the first slabs hold both layers apart, joined only through the
  // last slab: oriented slab by slab the lower layer would turn up.
  TempDir dir;
  std::vector<Xyz> points, expected;
  for (int iy = 0; iy < 40; ++iy) {
    const double y = 0.05 * iy;
    for (int ix = 0; ix < 200; ++ix) {
      points.push_back({0.05 * ix, y, 0.0});
      expected.push_back({0, 0, -1});
      points.push_back({0.05 * ix, y, 1.0});
      expected.push_back({0, 0, 1});
    }
    for (int ia = 1; ia < 31; ++ia) {
      const double a = std::numbers::pi * ia / 31.0;  // from the bottom (a = 0) to the top (a = pi)
      points.push_back({10.0 + 0.5 * std::sin(a), y, 0.5 - 0.5 * std::cos(a)});
      expected.push_back({std::sin(a), 0.0, -std::cos(a)});
    }
  }
  const auto in = writeCloud(dir, "fold.ply", points);
  NormalsStep step;
  step.k = 12;
  step.orientation = NormalOrientation::kPropagate;
  for (std::uint64_t memory : {2048, 1}) {
    SCOPED_TRACE(memory);
    run(in, dir / "out.ply", {step}, memory);
    const PointCloud out = readPointFile(dir / "out.ply");
    ASSERT_EQ(out.count, points.size());
    std::size_t wrong = 0;
    for (std::size_t i = 0; i < out.count; ++i) {
      const Xyz& d = expected[i];
      wrong += out.normals[i].x * d[0] + out.normals[i].y * d[1] + out.normals[i].z * d[2] < 0.5;
    }
    EXPECT_EQ(wrong, 0u);
  }
}

// Points on the plane z = 0 (a jittered grid), for the sensor tests: their normals are +-z, and
// the sensor's side of the plane decides the sign.
std::vector<Xyz> planeGrid(int side, double x0) {
  std::vector<Xyz> points;
  for (int i = 0; i < side; ++i) {
    for (int j = 0; j < side; ++j)
      points.push_back({x0 + i * 0.1 + 0.013 * ((i * 7 + j * 3) % 5), j * 0.1, 0.0});
  }
  return points;
}

std::vector<double> normalZ(const PointCloud& cloud) {
  std::vector<double> out;
  for (std::size_t i = 0; i < cloud.count; ++i) out.push_back(cloud.normals[i].z);
  return out;
}

TEST(ProcessNormals, OrientSensorFromPerPointColumns) {
  // Every other point seen from below (sensor_z -10), the rest from above (+10).
  TempDir dir;
  const std::vector<Xyz> points = planeGrid(30, 0.0);
  std::ostringstream ply;
  ply.precision(17);
  ply << "ply\nformat ascii 1.0\nelement vertex " << points.size()
      << "\nproperty double x\nproperty double y\nproperty double z\n"
         "property float sensor_x\nproperty float sensor_y\nproperty float sensor_z\n"
         "end_header\n";
  for (std::size_t i = 0; i < points.size(); ++i) {
    ply << points[i][0] << ' ' << points[i][1] << ' ' << points[i][2] << " 1.5 1.5 "
        << (i % 2 ? 10 : -10) << '\n';
  }
  const auto in = dir.write("in.ply", ply.str());
  NormalsStep step;
  step.k = 8;
  step.orientation = NormalOrientation::kSensor;
  run(in, dir / "out.ply", {step});
  const std::vector<double> z = normalZ(readPointFile(dir / "out.ply"));
  ASSERT_EQ(z.size(), points.size());
  for (std::size_t i = 0; i < z.size(); ++i) EXPECT_NEAR(z[i], i % 2 ? 1.0 : -1.0, 1e-6) << i;
}

TEST(ProcessNormals, OrientSensorFromPtxScansAndPcdViewpoint) {
  TempDir dir;
  // Two PTX scans of one plane, the first's scanner below it, the second's above (identity
  // transforms: the points are given in the registered frame).
  std::ostringstream ptx;
  const std::vector<Xyz> a = planeGrid(12, 0.5),
                         b = planeGrid(12, 5.0);  // no (0, 0, 0): PTX skips it
  for (const auto& [points, sensor_z] : {std::pair{a, -10}, std::pair{b, 10}}) {
    ptx << "12\n12\n1 1 " << sensor_z
        << "\n1 0 0\n0 1 0\n0 0 1\n1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n";
    for (const Xyz& p : points) ptx << p[0] << ' ' << p[1] << ' ' << p[2] << " 0.5\n";
  }
  const auto in = dir.write("scans.ptx", ptx.str());
  NormalsStep step;
  step.k = 8;
  step.orientation = NormalOrientation::kSensor;
  run(in, dir / "out.ply", {step});
  std::vector<double> z = normalZ(readPointFile(dir / "out.ply"));
  ASSERT_EQ(z.size(), a.size() + b.size());
  for (std::size_t i = 0; i < z.size(); ++i)
    EXPECT_NEAR(z[i], i < a.size() ? -1.0 : 1.0, 1e-6) << i;

  // One viewpoint for a whole PCD file, below the plane.
  std::ostringstream pcd;
  pcd << "VERSION 0.7\nFIELDS x y z\nSIZE 8 8 8\nTYPE F F F\nCOUNT 1 1 1\nWIDTH " << a.size()
      << "\nHEIGHT 1\nVIEWPOINT 1 1 -3 1 0 0 0\nPOINTS " << a.size() << "\nDATA ascii\n";
  for (const Xyz& p : a) pcd << p[0] << ' ' << p[1] << ' ' << p[2] << '\n';
  run(dir.write("view.pcd", pcd.str()), dir / "pcd.ply", {step});
  z = normalZ(readPointFile(dir / "pcd.ply"));
  ASSERT_EQ(z.size(), a.size());
  for (std::size_t i = 0; i < z.size(); ++i) EXPECT_NEAR(z[i], -1.0, 1e-6) << i;
}

TEST(ProcessNormals, OrientSensorFromE57ScanPoses) {
  // Two scans of the plane z = 0 in their own frames (the plane moved by minus the pose's
  // translation), the first scanner below the plane, the second above.
  TempDir dir;
  const std::array<std::vector<Xyz>, 2> plane = {planeGrid(12, 0.0), planeGrid(12, 5.0)};
  const std::array<std::array<double, 3>, 2> scanner = {{{1.0, 1.0, -10.0}, {6.0, 1.0, 10.0}}};
  std::vector<E57ScanSource> scans(2);
  for (std::size_t s = 0; s < 2; ++s) {
    E57ScanSource& scan = scans[s];
    scan.name = "scan " + std::to_string(s);
    scan.record_count = plane[s].size();
    scan.pose.translation = scanner[s];
    for (const char* name : {"cartesianX", "cartesianY", "cartesianZ"}) {
      E57Field f;
      f.name = name;
      f.kind = E57Field::Kind::Float;
      scan.fields.push_back(f);
    }
    scan.fill = [&, s](std::uint64_t first, std::size_t count,
                       std::vector<std::vector<double>>& values) {
      for (std::size_t k = 0; k < count; ++k) {
        for (std::size_t a = 0; a < 3; ++a) values[a][k] = plane[s][first + k][a] - scanner[s][a];
      }
    };
  }
  const auto in = dir / "scans.e57";
  writeE57Scans(scans, in);
  NormalsStep step;
  step.k = 8;
  step.orientation = NormalOrientation::kSensor;
  run(in, dir / "out.ply", {step});
  const std::vector<double> z = normalZ(readPointFile(dir / "out.ply"));
  ASSERT_EQ(z.size(), plane[0].size() + plane[1].size());
  for (std::size_t i = 0; i < z.size(); ++i)
    EXPECT_NEAR(z[i], i < plane[0].size() ? -1.0 : 1.0, 1e-5) << i;
}

TEST(ProcessNormals, OrientSensorWithoutAScannerPositionIsAnErrorNamingTheFile) {
  TempDir dir;
  const auto in = writeCloud(dir, "in.ply", planeGrid(10, 0.0));
  NormalsStep step;
  step.k = 8;
  step.orientation = NormalOrientation::kSensor;
  try {
    run(in, dir / "out.ply", {step});
    FAIL() << "a file without a scanner position was oriented";
  } catch (const std::invalid_argument& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("--normals 8 --orient sensor: " + in.string() +
                           " (ply) has no scanner position"),
              std::string::npos)
        << message;
    EXPECT_NE(message.find("sensor_x/y/z"), std::string::npos) << message;
  }
  EXPECT_FALSE(std::filesystem::exists(dir / "out.ply"));
}

TEST(ProcessOutliers, StatisticalEqualsPclDefinition) {
  TempDir dir;
  const std::vector<Xyz> written = terrainWithNoise(4000, 3);
  const auto in = writeCloud(dir, "in.ply", written);
  const std::vector<Xyz> points = readPositions(in);
  const std::uint32_t k = 8;
  const double s = 1.0;
  // PCL: mean of the k nearest distances (the point itself excluded) as a float; the threshold
  // mean + s * stddev (n - 1) over all points; removed when above it.
  std::vector<float> mean(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const std::vector<double> d = distancesFrom(points, i);
    double sum = 0.0;
    for (std::uint32_t j = 0; j < k; ++j) sum += std::sqrt(d[j]);
    mean[i] = float(sum / k);
  }
  double sum = 0.0, squares = 0.0;
  for (float m : mean) {
    sum += m;
    squares += double(m) * m;
  }
  const double nn = double(points.size());
  const double threshold = sum / nn + s * std::sqrt((squares - sum * sum / nn) / (nn - 1.0));
  std::vector<std::uint32_t> expected;
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (!(double(mean[i]) > threshold)) expected.push_back(std::uint32_t(i));
  }
  OutliersStep step;
  step.k = k;
  step.std_ratio = s;
  const ProcessReport report = run(in, dir / "out.ply", {step});
  EXPECT_EQ(report.input_points, points.size());
  EXPECT_LT(expected.size(), points.size() - 30);  // the floating points are found
  EXPECT_EQ(ids(readPointFile(dir / "out.ply")), expected);

  // --mark-outliers: every point kept, the outliers as class 7, the others class 0.
  step.mark = true;
  run(in, dir / "marked.ply", {step});
  const PointCloud marked = readPointFile(dir / "marked.ply");
  ASSERT_EQ(marked.count, points.size());
  ASSERT_TRUE(marked.hasClassification());
  const std::set<std::uint32_t> inliers(expected.begin(), expected.end());
  for (std::size_t i = 0; i < marked.count; ++i) {
    EXPECT_EQ(marked.classification[i], inliers.count(std::uint32_t(i)) ? 0 : 7) << i;
  }
}

TEST(ProcessOutliers, RadiusEqualsDefinition) {
  TempDir dir;
  const auto in = writeCloud(dir, "in.ply", terrainWithNoise(3000, 4));
  const std::vector<Xyz> points = readPositions(in);
  OutliersStep step;
  step.method = OutliersStep::Method::kRadius;
  step.radius = 0.9;
  step.min_neighbours = 3;
  std::vector<std::uint32_t> expected;
  for (std::size_t i = 0; i < points.size(); ++i) {
    std::size_t within = 0;
    for (std::size_t j = 0; j < points.size(); ++j)
      within += j != i && d2(points[i], points[j]) <= 0.81;
    if (within >= 3) expected.push_back(std::uint32_t(i));
  }
  run(in, dir / "out.ply", {step});
  EXPECT_LT(expected.size(), points.size());
  EXPECT_EQ(ids(readPointFile(dir / "out.ply")), expected);
}

TEST(ProcessSubsample, VoxelKeepsThePointNearestEachOccupiedVoxelsCentroid) {
  TempDir dir;
  const auto in = writeCloud(dir, "in.ply", terrainWithNoise(5000, 5));
  const std::vector<Xyz> points = readPositions(in);
  const double size = 1.5;
  Xyz corner = points[0];
  for (const Xyz& p : points) {
    for (int a = 0; a < 3; ++a)
      corner[std::size_t(a)] = std::min(corner[std::size_t(a)], p[std::size_t(a)]);
  }
  std::map<std::array<std::int64_t, 3>, std::vector<std::uint32_t>> voxels;
  for (std::size_t i = 0; i < points.size(); ++i) {
    std::array<std::int64_t, 3> key;
    for (int a = 0; a < 3; ++a)
      key[std::size_t(a)] =
          std::int64_t(std::floor((points[i][std::size_t(a)] - corner[std::size_t(a)]) / size));
    voxels[key].push_back(std::uint32_t(i));
  }
  std::vector<std::uint32_t> expected;
  for (const auto& [key, members] : voxels) {
    Xyz c = {0, 0, 0};
    for (std::uint32_t m : members) {
      for (int a = 0; a < 3; ++a) c[std::size_t(a)] += points[m][std::size_t(a)];
    }
    for (double& v : c) v /= double(members.size());
    std::uint32_t best = members[0];
    for (std::uint32_t m : members) {
      if (d2(points[m], c) < d2(points[best], c) - 1e-12) best = m;
    }
    expected.push_back(best);
  }
  std::sort(expected.begin(), expected.end());
  SubsampleStep step;
  step.size = size;
  run(in, dir / "out.ply", {step});
  const std::vector<std::uint32_t> kept = ids(readPointFile(dir / "out.ply"));
  EXPECT_EQ(kept.size(), voxels.size()) << "one point per occupied voxel";
  EXPECT_EQ(kept, expected);
}

// A voxel far smaller than the points' spacing holds one point each (a repeated position shares
// one, the smaller id kept): the voxel coordinates, 1e300 and more, used to be converted to
// 64-bit integers out of range, and the points at x 1, 2 and 3 fell in one voxel.
TEST(ProcessSubsample, TinyVoxelKeepsEveryDistinctPoint) {
  TempDir dir;
  const auto in =
      writeCloud(dir, "in.ply", {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}, {2, 0, 0}});
  SubsampleStep step;
  step.size = 1e-300;
  run(in, dir / "out.ply", {step});
  EXPECT_EQ(ids(readPointFile(dir / "out.ply")), (std::vector<std::uint32_t>{0, 1, 2, 3}));
}

// The greedy definition by brute force: columns of width D in x from the minimum x, input order
// within a column; a point is kept when no point kept before it is closer than D.
std::vector<std::uint32_t> greedySpacing(const std::vector<Xyz>& points, double d) {
  double x0 = points[0][0];
  for (const Xyz& p : points) x0 = std::min(x0, p[0]);
  std::vector<std::pair<std::int64_t, std::uint32_t>> order;
  for (std::size_t i = 0; i < points.size(); ++i)
    order.push_back({std::int64_t(std::floor((points[i][0] - x0) / d)), std::uint32_t(i)});
  std::sort(order.begin(), order.end());
  std::vector<std::uint32_t> kept;
  for (const auto& [column, i] : order) {
    bool near = false;
    for (std::uint32_t k : kept) near = near || d2(points[i], points[k]) < d * d;
    if (!near) kept.push_back(i);
  }
  std::sort(kept.begin(), kept.end());
  return kept;
}

TEST(ProcessSubsample, SpacingKeepsNoTwoPointsCloserThanDAndEqualsTheGreedyDefinition) {
  TempDir dir;
  const auto in = writeCloud(dir, "in.ply", terrainWithNoise(6000, 15));
  const std::vector<Xyz> points = readPositions(in);
  const double d = 0.9;
  const std::vector<std::uint32_t> expected = greedySpacing(points, d);
  SubsampleStep step;
  step.method = SubsampleStep::Method::kSpacing;
  step.size = d;
  // At --memory 1 the 6000 points are two slabs: columns and the column before cross the cut.
  const ProcessReport one = run(in, dir / "one.ply", {step});
  const ProcessReport many = run(in, dir / "many.ply", {step}, 1);
  EXPECT_EQ(one.tiles, 1u);
  EXPECT_GE(many.tiles, 2u);
  const std::vector<std::uint32_t> kept = ids(readPointFile(dir / "one.ply"));
  EXPECT_EQ(kept, expected);
  EXPECT_EQ(ids(readPointFile(dir / "many.ply")), expected);
  EXPECT_LT(kept.size(), points.size() / 4);
  // D wider than a slab (two slabs of about 20 units): a column spans both, and the column
  // before it was decided by the other.
  step.size = 27.0;
  run(in, dir / "wide.ply", {step}, 1);
  EXPECT_EQ(ids(readPointFile(dir / "wide.ply")), greedySpacing(points, 27.0));
  // The two properties of the result, checked directly: no two kept points closer than D, and
  // every removed point within D of a kept one.
  std::vector<bool> is_kept(points.size(), false);
  for (std::uint32_t k : kept) is_kept[k] = true;
  for (std::size_t i = 0; i < points.size(); ++i) {
    double nearest = INFINITY;
    for (std::uint32_t k : kept) {
      if (k != i) nearest = std::min(nearest, d2(points[i], points[k]));
    }
    if (is_kept[i]) {
      EXPECT_GE(nearest, d * d) << i;
    } else {
      EXPECT_LT(nearest, d * d) << i;
    }
  }
}

TEST(ProcessSubsample, RandomKeepsExactlyNDistinctPoints) {
  TempDir dir;
  const auto in = writeCloud(dir, "in.ply", terrainWithNoise(5000, 6));
  SubsampleStep step;
  step.method = SubsampleStep::Method::kRandom;
  step.count = 1234;
  run(in, dir / "out.ply", {step});
  const std::vector<std::uint32_t> kept = ids(readPointFile(dir / "out.ply"));
  EXPECT_EQ(kept.size(), 1234u);
  EXPECT_TRUE(std::is_sorted(kept.begin(), kept.end()));
  EXPECT_EQ(std::set<std::uint32_t>(kept.begin(), kept.end()).size(), 1234u);
  step.count = 10000;  // more than there are: all
  run(in, dir / "all.ply", {step});
  EXPECT_EQ(readPointFile(dir / "all.ply").count, 5000u);
}

TEST(ProcessDistance, NearestAndLocalPlaneEqualBruteForce) {
  TempDir dir;
  const auto in = writeCloud(dir, "in.ply", terrainWithNoise(2000, 7));
  std::vector<Xyz> shifted = terrainWithNoise(2500, 8);
  for (Xyz& p : shifted) p[2] += 0.3;
  const auto ref = writeCloud(dir, "ref.ply", shifted);
  const std::vector<Xyz> points = readPositions(in), reference = readPositions(ref);
  DistanceStep step;
  step.reference = ref;
  run(in, dir / "out.ply", {step});
  const PointCloud out = readPointFile(dir / "out.ply");
  ASSERT_EQ(out.count, points.size());
  const ScalarColumn* distance = out.findScalar("distance");
  ASSERT_NE(distance, nullptr);
  for (std::size_t i = 0; i < points.size(); ++i) {
    double best = INFINITY;
    for (const Xyz& r : reference) best = std::min(best, d2(points[i], r));
    EXPECT_EQ(distance->valueAsDouble(i), double(float(std::sqrt(best)))) << i;
  }
}

TEST(ProcessDistance, LocalPlaneOfAnExactPlaneGivesTheOffset) {
  // Reference: the plane z = 0.2 x + 0.1 y sampled on a grid; points at known offsets along its
  // normal, away from its edges.
  TempDir dir;
  std::vector<Xyz> plane_points, points;
  for (int i = 0; i < 100; ++i) {
    for (int j = 0; j < 100; ++j)
      plane_points.push_back({i * 0.1, j * 0.1, 0.2 * i * 0.1 + 0.1 * j * 0.1});
  }
  const double len = std::sqrt(0.04 + 0.01 + 1.0);
  const Xyz normal = {-0.2 / len, -0.1 / len, 1.0 / len};
  std::vector<double> offsets;
  std::mt19937 rng(12);
  std::uniform_real_distribution<double> u(2.0, 8.0), off(-0.3, 0.3);
  for (int i = 0; i < 500; ++i) {
    const double x = u(rng), y = u(rng), o = off(rng);
    points.push_back({x + o * normal[0], y + o * normal[1], 0.2 * x + 0.1 * y + o * normal[2]});
    offsets.push_back(std::abs(o));
  }
  const auto in = writeCloud(dir, "in.ply", points);
  DistanceStep step;
  step.reference = writeCloud(dir, "ref.ply", plane_points);
  step.plane = true;
  step.k = 8;
  run(in, dir / "out.ply", {step});
  const PointCloud out = readPointFile(dir / "out.ply");
  const ScalarColumn* distance = out.findScalar("distance");
  ASSERT_NE(distance, nullptr);
  ASSERT_EQ(out.count, offsets.size());
  for (std::size_t i = 0; i < out.count; ++i)
    EXPECT_NEAR(distance->valueAsDouble(i), offsets[i], 2e-5) << i;
}

TEST(ProcessTiling, SameBytesAtAnyMemoryBudget) {
  TempDir dir;
  // With points far from everything, near tile edges and outside the rest's height: their
  // halos grow in boxes around them (tile_queries.h) until their neighbours are in.
  std::vector<Xyz> cloud = terrainWithNoise(60000, 9);
  cloud.push_back({20.0, 20.0, 300.0});
  cloud.push_back({-250.0, 5.0, 0.0});
  cloud.push_back({10.0, 400.0, -40.0});
  const auto in = writeCloud(dir, "in.ply", cloud);
  const auto ref = writeCloud(dir, "ref.ply", terrainWithNoise(20000, 10));
  NormalsStep normals;
  normals.k = 12;
  normals.curvature = true;
  OutliersStep statistical;
  statistical.k = 6;
  statistical.std_ratio = 2.0;
  OutliersStep radius;
  radius.method = OutliersStep::Method::kRadius;
  radius.radius = 0.5;
  radius.min_neighbours = 2;
  radius.mark = true;
  SubsampleStep voxel;
  voxel.size = 0.2;
  SubsampleStep random;
  random.method = SubsampleStep::Method::kRandom;
  random.count = 20000;
  DistanceStep distance;
  distance.reference = ref;
  DistanceStep plane = distance;
  plane.plane = true;
  SubsampleStep spacing;
  spacing.method = SubsampleStep::Method::kSpacing;
  spacing.size = 0.15;
  const std::vector<ProcessStep> steps = {statistical, normals, radius,  spacing,
                                          voxel,       random,  distance};
  // 1 MB: tiles of 4096 points, so about fifteen tiles against one.
  const ProcessReport small = run(in, dir / "small.ply", steps, 1);
  const ProcessReport large = run(in, dir / "large.ply", steps, 16000);
  EXPECT_GE(small.tiles, 10u);
  EXPECT_EQ(large.tiles, 1u);
  EXPECT_EQ(small.output_points, large.output_points);
  auto bytes = [](const std::filesystem::path& p) {
    std::ifstream f(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(f), {});
  };
  const std::string a = bytes(dir / "small.ply");
  EXPECT_GT(a.size(), 100000u);
  EXPECT_TRUE(a == bytes(dir / "large.ply"));
  // The local plane model too, and a LAS output.
  run(in, dir / "small.las", {normals, plane}, 1);
  run(in, dir / "large.las", {normals, plane}, 16000);
  EXPECT_TRUE(bytes(dir / "small.las") == bytes(dir / "large.las"));
  // Nothing is left beside the output.
  for (const auto& entry : std::filesystem::directory_iterator(dir.path())) {
    EXPECT_NE(entry.path().filename().string().front(), '.') << entry.path();
  }
}

// LAS and LAZ outputs are written as the last pass produces them (LasStreamWriter), in batches of
// the input's reading: over a million points, so several batches, with classes above 31 only in
// the last one (they need LAS 1.4 format 6, which the first batch does not foresee: the pass is
// run again with every kept point's maxima). The bytes equal writeLas and writeLaz of the kept
// points gathered here from the whole input, the kept set read from the PLY output's ids.
TEST(ProcessOutput, LasAndLazAreStreamedWithTheBytesOfTheWholeOutput) {
  TempDir dir;
  constexpr std::size_t kPoints = 1100000;
  PointCloud input;
  input.count = kPoints;
  input.quantization.scale = {1e-3, 1e-3, 1e-3};
  input.positions = Column<Int3>(kPoints);
  input.classification = Column<std::uint8_t>(kPoints);
  ScalarColumn id{"id", ScalarType::UInt32, ByteBuffer(kPoints * 4)};
  for (std::size_t i = 0; i < kPoints; ++i) {
    input.positions[i] = {int((i * 7919) % 400000), int((i * 104729) % 300000), int(i % 977)};
    input.classification[i] = std::uint8_t(i >= 1050000 && i % 1000 == 0 ? 40 : i % 32);
    id.as<std::uint32_t>()[i] = std::uint32_t(i);
  }
  input.scalars.push_back(std::move(id));
  input.source.position = ScalarType::Int32;
  input.computeBounds();
  writePly(input, dir / "in.ply");
  SubsampleStep random;
  random.method = SubsampleStep::Method::kRandom;
  random.count = 1000000;
  run(dir / "in.ply", dir / "out.ply", {random});
  run(dir / "in.ply", dir / "out.las", {random}, 8);  // tiles of 32 768 points
  run(dir / "in.ply", dir / "out.laz", {random});

  const PointCloud whole = readPointFile(dir / "in.ply");
  ASSERT_EQ(whole.count, kPoints);
  std::vector<std::uint64_t> kept;
  for (std::uint32_t i : ids(readPointFile(dir / "out.ply"))) kept.push_back(i);
  ASSERT_EQ(kept.size(), 1000000u);
  const PointCloud expected = gatherPoints(whole, kept);
  std::size_t high_classes = 0;
  for (std::size_t i = 0; i < expected.count; ++i) high_classes += expected.classification[i] > 31;
  EXPECT_GT(high_classes, 10u);
  writeLas(expected, dir / "expected.las");
  writeLaz(expected, dir / "expected.laz");
  auto bytes = [](const std::filesystem::path& p) {
    std::ifstream f(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(f), {});
  };
  const std::string las = bytes(dir / "out.las");
  ASSERT_GT(las.size(), 1000000u * 20);
  EXPECT_EQ(int(las[25]), 4);                 // LAS 1.4
  EXPECT_EQ(int(std::uint8_t(las[104])), 6);  // point format 6
  EXPECT_TRUE(las == bytes(dir / "expected.las"));
  EXPECT_TRUE(bytes(dir / "out.laz") == bytes(dir / "expected.laz"));
  for (const auto& entry : std::filesystem::directory_iterator(dir.path())) {
    EXPECT_NE(entry.path().filename().string().front(), '.') << entry.path();
  }
}

// Each point of a file or octree by its id: x y z, the normal (the normals column) and the
// distance.
std::map<std::uint32_t, std::array<double, 7>> pointsById(const std::filesystem::path& path) {
  std::map<std::uint32_t, std::array<double, 7>> out;
  PointStream stream(path, {});
  PointCloud batch;
  while (stream.next(batch, 1 << 20)) {
    const ScalarColumn* id = batch.findScalar("id");
    const ScalarColumn* distance = batch.findScalar("distance");
    EXPECT_TRUE(id && distance && batch.hasNormals()) << path;
    if (!id || !distance || !batch.hasNormals()) return out;
    for (std::size_t i = 0; i < batch.count; ++i) {
      std::array<double, 7> v = {batch.worldX(i), batch.worldY(i), batch.worldZ(i)};
      for (int a = 0; a < 3; ++a) v[3 + a] = (&batch.normals[i].x)[a];
      v[6] = distance->valueAsDouble(i);
      EXPECT_TRUE(out.emplace(std::uint32_t(id->valueAsDouble(i)), v).second) << path;
    }
  }
  return out;
}

// `-o DIR/` and `-o NAME.copc.laz`: octrees built from the processed points (lod's converters),
// holding every kept point once with the normals and distances of the point file output.
TEST(ProcessOutput, PotreeAndCopcOctreesHoldEveryProcessedPoint) {
  TempDir dir;
  const auto in = writeCloud(dir, "in.ply", terrainWithNoise(30000, 4));
  const auto ref = writeCloud(dir, "ref.ply", terrainWithNoise(5000, 5));
  NormalsStep normals;
  normals.k = 8;
  OutliersStep outliers;
  outliers.k = 6;
  outliers.std_ratio = 2.0;
  DistanceStep distance;
  distance.reference = ref;
  const std::vector<ProcessStep> steps = {outliers, normals, distance};
  const ProcessReport file = run(in, dir / "out.ply", steps);
  EXPECT_LT(file.output_points, 30000u);  // the outliers are gone
  EXPECT_EQ(outputKind(dir / "octree/"), OutputKind::kPotree);
  EXPECT_EQ(outputKind(dir / "octree"), OutputKind::kPotree);
  EXPECT_EQ(outputKind(dir / "out.COPC.LAZ"), OutputKind::kCopc);
  EXPECT_EQ(outputKind(dir / "out.laz"), OutputKind::kPointFile);
  // The rule convert shares (lod/output_kind.h): an existing directory whatever its name, and
  // convert's --format over the name.
  EXPECT_EQ(outputKind(dir.path()), OutputKind::kPotree);
  EXPECT_EQ(outputKind(dir / "out.ply", "potree"), OutputKind::kPotree);
  EXPECT_EQ(outputKind(dir / "out.laz", "copc"), OutputKind::kCopc);
  EXPECT_EQ(outputKind(dir / "out.unknown"), OutputKind::kPointFile);
  run(in, dir / "octree/", steps, 1);
  run(in, dir / "out.copc.laz", steps);
  const auto expected = pointsById(dir / "out.ply");
  ASSERT_EQ(expected.size(), file.output_points);
  for (const char* name : {"octree", "out.copc.laz"}) {
    SCOPED_TRACE(name);
    EXPECT_NE(detectOctreeFormat(dir / name), OctreeFormat::None);
    const auto got = pointsById(dir / name);
    ASSERT_EQ(got.size(), expected.size());
    std::size_t checked = 0;
    for (const auto& [id, v] : expected) {
      const auto it = got.find(id);
      ASSERT_NE(it, got.end()) << id;
      for (int a = 0; a < 3; ++a) ASSERT_NEAR(it->second[a], v[a], 1e-5) << id;  // requantized
      for (int a = 3; a < 7; ++a) ASSERT_EQ(float(it->second[a]), float(v[a])) << id;
      ++checked;
    }
    EXPECT_EQ(checked, file.output_points);
  }
  for (const auto& entry : std::filesystem::directory_iterator(dir.path())) {
    EXPECT_NE(entry.path().filename().string().front(), '.') << entry.path();
  }
}

// Each point's normal by its id, from a file or octree that holds the normals as normals (not
// as scalars: what lighting reads).
std::map<std::uint32_t, Float3> normalsById(const std::filesystem::path& path) {
  std::map<std::uint32_t, Float3> out;
  PointStream stream(path, {});
  PointCloud batch;
  while (stream.next(batch, 1 << 20)) {
    const ScalarColumn* id = batch.findScalar("id");
    EXPECT_TRUE(id && batch.hasNormals()) << path;
    for (const char* name : {"nx", "NormalX", "normal_x"}) {
      EXPECT_EQ(batch.findScalar(name), nullptr) << path << ": " << name;
    }
    if (!id || !batch.hasNormals()) return out;
    for (std::size_t i = 0; i < batch.count; ++i) {
      EXPECT_TRUE(out.emplace(std::uint32_t(id->valueAsDouble(i)), batch.normals[i]).second);
    }
  }
  return out;
}

// The normals of a LAS input travel as normals: `process --normals` writes them as the extra
// bytes CloudCompare and PDAL read as normals (NormalX NormalY NormalZ, float), the LAS reader
// gives them back as normals, and the Potree and COPC octrees built from such a file hold them as
// normals; the values are those of the same points processed from PLY, bit for bit.
TEST(ProcessOutput, LasNormalsTravelAsNormalsIntoOctrees) {
  TempDir dir;
  const auto ply = writeCloud(dir, "in.ply", terrainWithNoise(2000, 4));
  const auto las = dir / "in.las";
  writeLas(readPointFile(ply), las);
  NormalsStep normals;
  normals.k = 8;
  run(ply, dir / "expected.ply", {normals});
  run(las, dir / "out.las", {normals});
  const LasHeader header = readLasHeader(dir / "out.las");
  ASSERT_EQ(header.extra_bytes.size(), 4u);  // the normals, then id
  for (int axis = 0; axis < 3; ++axis) {
    const LasExtraBytes& extra = header.extra_bytes[std::size_t(axis)];
    EXPECT_EQ(extra.name, kLasNormalExtraBytesNames[axis]);
    EXPECT_EQ(extra.data_type, 9);  // float
  }
  EXPECT_EQ(header.extra_bytes[3].name, "id");
  const auto expected = normalsById(dir / "expected.ply");
  ASSERT_EQ(expected.size(), 2000u);
  EXPECT_EQ(normalsById(dir / "out.las"), expected);
  // The octrees that process builds from its LAS result (lod's converters read it back).
  run(las, dir / "octree/", {normals});
  run(las, dir / "out.copc.laz", {normals});
  EXPECT_EQ(normalsById(dir / "octree"), expected);
  EXPECT_EQ(normalsById(dir / "out.copc.laz"), expected);
}

template <class Parse>
std::string messageOf(Parse&& parse) {
  try {
    parse();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(no error)";
}

// A progress sink that sets the cancel flag when the normals step reports its first tile, as
// the viewer's Cancel button would from its own thread.
class CancelAtFirstTile final : public Progress {
 public:
  explicit CancelAtFirstTile(std::atomic<bool>& cancel) : cancel_(cancel) {}
  void advance(std::uint64_t) override { cancel_ = true; }

 private:
  std::atomic<bool>& cancel_;
};

// The names of what `dir` holds, sorted: what a cancelled run left behind.
std::vector<std::string> namesIn(const std::filesystem::path& dir) {
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    names.push_back(entry.path().filename().string());
  }
  std::sort(names.begin(), names.end());
  return names;
}

TEST(ProcessSteps, CancelledBetweenTilesLeavesNoOutputAndNoWorkFiles) {
  TempDir dir;
  const auto in = writeCloud(dir, "in.ply", terrainWithNoise(20000, 4));
  NormalsStep normals;
  normals.k = 8;
  for (const char* name : {"out.ply", "out.xyz", "octree/"}) {
    SCOPED_TRACE(name);
    std::atomic<bool> cancel = false;
    std::vector<std::string> stages;
    // 1 MB: 4 096-point tiles, 5 of them
    ProcessOptions options = runOptions(in, dir / name, {normals}, 1);
    options.cancel = &cancel;
    options.progress = [&](const std::string& stage, std::uint64_t) -> std::unique_ptr<Progress> {
      stages.push_back(stage);
      if (stage.starts_with("--normals")) return std::make_unique<CancelAtFirstTile>(cancel);
      return nullptr;
    };
    EXPECT_THROW(runProcess(options), ProcessCancelled);
    EXPECT_TRUE(cancel);
    ASSERT_FALSE(stages.empty());
    EXPECT_TRUE(stages.back().starts_with("--normals"));  // stopped there: nothing written
    // Only the input is left: no output, no partial file, no work folder.
    EXPECT_EQ(namesIn(dir.path()), std::vector<std::string>{"in.ply"});
  }
  // Not cancelled: the same options run to the end.
  std::atomic<bool> never = false;
  ProcessOptions options = runOptions(in, dir / "out.ply", {normals}, 1);
  options.cancel = &never;
  EXPECT_EQ(runProcess(options).output_points, 20000u);
}

// The flag set when an octree builder's stage starts (its progress bar is made): the builder
// stops at its next batch, chunk or node, and nothing is left, neither the octree nor its
// temporary directory, the work folder or the processed point file.
TEST(ProcessSteps, CancelledInsideTheOctreeBuildLeavesNoOutputAndNoWorkFiles) {
  TempDir dir;
  const auto in = writeCloud(dir, "in.ply", terrainWithNoise(1000, 4));
  NormalsStep normals;
  normals.k = 8;
  const std::vector<std::string> potree_stages = {"scanning", "counting", "distributing",
                                                  "indexing"};
  for (const char* name : {"octree/", "out.copc.laz"}) {
    std::vector<std::string> cancel_at = potree_stages;
    if (std::string(name) == "out.copc.laz") cancel_at.push_back("writing COPC");
    for (const std::string& at : cancel_at) {
      SCOPED_TRACE(std::string(name) + " at " + at);
      std::atomic<bool> cancel = false;
      std::vector<std::string> stages;
      // 16 MB: the builder's buffers sized for 1 000 points, not 2 GB
      ProcessOptions options = runOptions(in, dir / name, {normals}, 16);
      options.cancel = &cancel;
      options.progress = [&](const std::string& stage, std::uint64_t) -> std::unique_ptr<Progress> {
        stages.push_back(stage);
        if (stage == at) cancel = true;
        return nullptr;
      };
      EXPECT_THROW(runProcess(options), ProcessCancelled);
      ASSERT_FALSE(stages.empty());
      EXPECT_EQ(stages.back(), at);  // no stage after it started
      EXPECT_EQ(namesIn(dir.path()), std::vector<std::string>{"in.ply"});
    }
  }
}

TEST(ProcessSteps, BadParametersAreErrorsNamingTheStep) {
  EXPECT_EQ(messageOf([] { parseNormalsK("2"); }),
            "--normals 2: K must be a whole number from 3 to 1000, got '2'");
  EXPECT_EQ(messageOf([] { parseNormalsK("16x"); }),
            "--normals 16x: K must be a whole number from 3 to 1000, got '16x'");
  EXPECT_EQ(messageOf([] { parseNormalsRadius("-1"); }),
            "--normals-radius -1: R must be a positive number, got '-1'");
  EXPECT_EQ(messageOf([] { parseOutliers("statistical:8"); }),
            "--outliers statistical:8: expected statistical:K,S (e.g. statistical:8,2)");
  EXPECT_EQ(messageOf([] { parseOutliers("statistical:8,zero"); }),
            "--outliers statistical:8,zero: S must be a positive number, got 'zero'");
  EXPECT_EQ(messageOf([] { parseOutliers("radius:0.5,0"); }),
            "--outliers radius:0.5,0: N must be a whole number from 1 to 100000, got '0'");
  EXPECT_EQ(messageOf([] { parseOutliers("median:3"); }),
            "--outliers median:3: expected statistical:K,S or radius:R,N, got 'median'");
  EXPECT_EQ(messageOf([] { parseSubsample("voxel:0"); }),
            "--subsample voxel:0: SIZE must be a positive number, got '0'");
  EXPECT_EQ(messageOf([] { parseSubsample("grid:1"); }),
            "--subsample grid:1: expected voxel:SIZE, spacing:D or random:N, got 'grid'");
  NormalsStep normals;
  EXPECT_EQ(messageOf([&] { parseOrientation("1,2", normals); }),
            "--orient 1,2: expected up, sensor, propagate or X,Y,Z");
  EXPECT_EQ(messageOf([&] { parseOrientation("1,b,3", normals); }),
            "--orient 1,b,3: coordinate 2 must be a number, got 'b'");
  DistanceStep distance;
  EXPECT_EQ(messageOf([&] { parseLocalModel("quadric", distance); }),
            "--local-model quadric: expected plane");
  parseOrientation("1.5,-2,3e2", normals);
  EXPECT_EQ(normals.orientation, NormalOrientation::kPoint);
  EXPECT_EQ(normals.toward[2], 300.0);
}

// One typed line a step (the viewer's Processing panel): describeStep's words read back, with
// the options that modify the step; anything else is an error naming the line.
TEST(ProcessSteps, ParsedFromOneLineAsDescribed) {
  for (const char* text : {"--normals 16", "--normals-radius 0.5", "--outliers statistical:8,2",
                           "--outliers radius:0.25,3", "--subsample voxel:0.1",
                           "--subsample spacing:2", "--subsample random:100",
                           "--distance-to ref.las", "--distance-to ref.las --local-model plane"}) {
    EXPECT_EQ(describeStep(parseProcessStep(text)), text);
  }
  const ProcessStep normals = parseProcessStep("normals 12 --curvature --orient 1,2,3");
  const auto& n = std::get<NormalsStep>(normals);
  EXPECT_EQ(n.k, 12u);
  EXPECT_TRUE(n.curvature);
  EXPECT_EQ(n.orientation, NormalOrientation::kPoint);
  EXPECT_EQ(n.toward[1], 2.0);
  EXPECT_TRUE(
      std::get<OutliersStep>(parseProcessStep("outliers statistical:8,2 --mark-outliers")).mark);
  EXPECT_EQ(std::get<DistanceStep>(parseProcessStep("distance-to b.ply --local-k 9")).k, 9u);
  for (const char* ground : {"smrf:cell=2", "pmf", "csf:rigidness=2"}) {
    const std::string described = describeStep(parseGround(ground)) + " --keep-classes";
    EXPECT_EQ(describeStep(parseProcessStep(described)), described);
    EXPECT_EQ(describeStep(parseProcessStep(std::string("ground ") + ground)),
              describeStep(parseGround(ground)));
  }
  EXPECT_EQ(std::get<GroundStep>(parseProcessStep("ground smrf:window=9")).smrf.window, 9.0);
  EXPECT_TRUE(
      std::holds_alternative<HeightAboveGroundStep>(parseProcessStep("--height-above-ground")));
  EXPECT_EQ(messageOf([] { parseProcessStep("height-above-ground 2"); }),
            "processing step 'height-above-ground 2': '2' does not modify a height-above-ground "
            "step (normals: --curvature, --orient X; outliers: --mark-outliers; distance-to: "
            "--local-model plane, --local-k K; ground: --keep-classes)");
  EXPECT_EQ(messageOf([] { parseProcessStep("normals 2"); }),
            "--normals 2: K must be a whole number from 3 to 1000, got '2'");
  EXPECT_EQ(messageOf([] { parseProcessStep("smooth 3"); }),
            "processing step 'smooth 3': unknown step 'smooth' (normals, normals-radius, outliers, "
            "subsample, distance-to, ground, height-above-ground)");
  EXPECT_EQ(messageOf([] {
              parseProcessStep("normals");
            }).rfind("processing step 'normals': expected a step and its argument", 0),
            0u);
  EXPECT_EQ(messageOf([] { parseProcessStep("subsample voxel:1 --curvature"); }),
            "processing step 'subsample voxel:1 --curvature': 'curvature' does not modify a "
            "subsample step (normals: --curvature, --orient X; outliers: --mark-outliers; "
            "distance-to: --local-model plane, --local-k K; ground: --keep-classes)");
}

TEST(ProcessSteps, UnavailableStepsAndOutputsFailBeforeAnyWork) {
  TempDir dir;
  const auto in = writeCloud(dir, "in.ply", terrainWithNoise(100, 11));
  NormalsStep normals;
  normals.k = 8;
  EXPECT_THROW(run(in, dir / "out.copc", {normals}), std::invalid_argument);
  EXPECT_FALSE(std::filesystem::exists(dir / "out.ply"));
  DistanceStep distance;
  distance.reference = dir / "missing.ply";
  EXPECT_THROW(run(in, dir / "out.ply", {distance}), InputError);
  // A point file in a folder that does not exist: an error before any work, and no folder made
  // (the work folder beside the output made it, and the run succeeded).
  try {
    run(in, dir / "missing" / "out.ply", {normals});
    ADD_FAILURE() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()), "-o " + (dir / "missing" / "out.ply").string() +
                                         ": the folder " + (dir / "missing").string() +
                                         " does not exist");
  }
  EXPECT_FALSE(std::filesystem::exists(dir / "missing"));
}

}  // namespace
}  // namespace parallax
