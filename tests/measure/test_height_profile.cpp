// The height profile of a synthetic slope: which points are in the corridor, their stations and
// heights, the same from an octree, and the CSV and LAS exports read back.
#include "measure/height_profile.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>

#include "io/las_reader.h"
#include "lod/in_memory_octree.h"

namespace parallax {
namespace {

constexpr double kProfileEast = 500000.0, kProfileNorth = 5000000.0;
// A power-of-two scale: every grid coordinate below is exact in the quantized cloud.
constexpr double kScale = 1.0 / 1024.0;

// A plane rising 0.1 per unit of x, sampled every 0.25 over x 0..20, y -5..5, at UTM coordinates.
PointCloud slope() {
  std::vector<Int3> positions;
  for (int i = 0; i <= 80; ++i) {
    for (int j = -20; j <= 20; ++j) {
      const double x = 0.25 * i, y = 0.25 * j, z = 100.0 + 0.1 * x;
      positions.push_back({std::int32_t(std::lround(x / kScale)),
                           std::int32_t(std::lround(y / kScale)),
                           std::int32_t(std::lround(z / kScale))});
    }
  }
  PointCloud cloud;
  cloud.count = positions.size();
  cloud.quantization.scale = {kScale, kScale, kScale};
  cloud.quantization.offset = {kProfileEast, kProfileNorth, 0.0};
  cloud.positions = Column<Int3>(positions.size());
  std::copy(positions.begin(), positions.end(), cloud.positions.begin());
  cloud.intensity = Column<float>(positions.size());
  for (std::size_t i = 0; i < positions.size(); ++i) cloud.intensity[i] = float(i % 1000);
  cloud.computeBounds();
  return cloud;
}

std::filesystem::path profileDir() {
  const std::filesystem::path dir = std::filesystem::path(PARALLAX_TEST_TMP) / "profile";
  std::filesystem::create_directories(dir);
  return dir;
}

TEST(HeightProfile, StraightLineOverASlope) {
  const PointCloud cloud = slope();
  // From x 2 to 12 along y 0; 1.1 wide: the rows y -0.5 .. 0.5 (five of them), every column
  // from x 2 to x 12 inclusive (41): 205 points.
  const std::vector<glm::dvec3> line{{kProfileEast + 2, kProfileNorth, 0},
                                     {kProfileEast + 12, kProfileNorth, 50}};
  const HeightProfile profile = extractProfile(cloud, line, 1.1);
  ASSERT_EQ(profile.samples.size(), 205u);
  ASSERT_EQ(profile.points.count, 205u);
  double previous = -1;
  for (std::size_t i = 0; i < profile.samples.size(); ++i) {
    const ProfileSample& s = profile.samples[i];
    const double x = s.position.x - kProfileEast, y = s.position.y - kProfileNorth;
    EXPECT_EQ(s.station, x - 2.0);
    EXPECT_EQ(s.offset, y);
    EXPECT_LE(std::abs(y), 0.5);
    // The height is the point's z (0.1 x above 100 to the quantization's precision).
    EXPECT_NEAR(s.position.z, 100.0 + 0.1 * x, kScale);
    EXPECT_GE(s.station, previous);
    previous = s.station;
    // The LAS-bound points are the same points, in the same order.
    EXPECT_EQ(profile.points.worldX(i), s.position.x);
    EXPECT_EQ(profile.points.worldZ(i), s.position.z);
  }
  EXPECT_EQ(profile.samples.front().station, 0.0);
  EXPECT_EQ(profile.samples.back().station, 10.0);
}

TEST(HeightProfile, BendGivesEachPointToTheNearerSegmentOnce) {
  const PointCloud cloud = slope();
  // An L: east 10 units, then north 4 units. Width 2.
  const std::vector<glm::dvec3> line{{kProfileEast + 5, kProfileNorth - 2, 0},
                                     {kProfileEast + 15, kProfileNorth - 2, 0},
                                     {kProfileEast + 15, kProfileNorth + 2, 0}};
  const HeightProfile profile = extractProfile(cloud, line, 2.0);
  std::vector<glm::dvec3> seen;
  for (const ProfileSample& s : profile.samples) seen.push_back(s.position);
  std::sort(seen.begin(), seen.end(), [](const glm::dvec3& a, const glm::dvec3& b) {
    return std::tie(a.x, a.y) < std::tie(b.x, b.y);
  });
  EXPECT_EQ(std::adjacent_find(seen.begin(), seen.end()), seen.end()) << "a point listed twice";
  // (14.5, -1.5) is 0.5 from the first segment and 0.5 from the second: one of them, once.
  // (14.75, -1.25) is 0.75 from the first, 0.25 from the second: the second's station, 10 + 0.75.
  bool found = false;
  for (const ProfileSample& s : profile.samples) {
    if (s.position.x == kProfileEast + 14.75 && s.position.y == kProfileNorth - 1.25) {
      found = true;
      EXPECT_EQ(s.station, 10.75);
      EXPECT_EQ(s.offset, 0.25);  // left of the northward segment is west: 15 - 14.75
    }
  }
  EXPECT_TRUE(found);
  // Every point within 1 of the L is there: count them by brute force.
  std::size_t expected = 0;
  for (std::size_t i = 0; i < cloud.count; ++i) {
    const double x = cloud.worldX(i) - kProfileEast, y = cloud.worldY(i) - kProfileNorth;
    const bool first = x >= 5 && x <= 15 && std::abs(y + 2) <= 1;
    const bool second = y >= -2 && y <= 2 && std::abs(x - 15) <= 1;
    expected += first || second;
  }
  EXPECT_EQ(profile.samples.size(), expected);
}

TEST(HeightProfile, OctreeGivesTheSamePointsAtFullDetail) {
  const PointCloud cloud = slope();
  auto octree = buildOctree(cloud);
  const std::vector<glm::dvec3> line{{kProfileEast + 1, kProfileNorth - 3, 0},
                                     {kProfileEast + 19, kProfileNorth + 4, 0}};
  const HeightProfile direct = extractProfile(cloud, line, 1.5);
  const HeightProfile streamed = extractProfile(*octree, line, 1.5);
  ASSERT_GT(direct.samples.size(), 50u);
  ASSERT_EQ(streamed.samples.size(), direct.samples.size());
  ASSERT_EQ(streamed.points.count, direct.points.count);
  auto key = [](const ProfileSample& s) { return std::tuple(s.station, s.position.y); };
  std::vector<std::tuple<double, double>> a, b;
  for (const auto& s : direct.samples) a.push_back(key(s));
  for (const auto& s : streamed.samples) b.push_back(key(s));
  std::sort(a.begin(), a.end());
  std::sort(b.begin(), b.end());
  EXPECT_EQ(a, b);
  EXPECT_TRUE(streamed.points.hasIntensity());
}

// A line drawn between two points of the cloud (as the viewer's profile tool draws it) holds
// both: the end vertex is at the very end of the corridor, never a rounding past it. Every
// diagonal from one grid point to a spread of others.
TEST(HeightProfile, BothEndPointsOfTheLineAreInIt) {
  const PointCloud cloud = slope();
  const auto gridPoint = [&](std::size_t k) {
    return glm::dvec3(cloud.worldX(k), cloud.worldY(k), cloud.worldZ(k));
  };
  const glm::dvec3 start = gridPoint(5 * 41 + 3);
  std::size_t lines = 0;
  for (std::size_t k = 7 * 41; k < cloud.count; k += 5 * 41 + 3) {
    const glm::dvec3 end = gridPoint(k);
    const HeightProfile profile = extractProfile(cloud, {start, end}, 0.1);
    for (const glm::dvec3& vertex : {start, end}) {
      EXPECT_TRUE(std::any_of(profile.samples.begin(), profile.samples.end(),
                              [&](const ProfileSample& s) { return s.position == vertex; }))
          << "from " << start.x - kProfileEast << "," << start.y - kProfileNorth << " to "
          << end.x - kProfileEast << "," << end.y - kProfileNorth << ": " << vertex.x - kProfileEast
          << "," << vertex.y - kProfileNorth << " left out";
    }
    ++lines;
  }
  EXPECT_GT(lines, 10u);
}

TEST(HeightProfile, DegenerateLinesGiveNothing) {
  const PointCloud cloud = slope();
  EXPECT_TRUE(extractProfile(cloud, {{kProfileEast + 1, kProfileNorth, 0}}, 1.0).samples.empty());
  // The same XY twice (a vertical line) has no direction on the ground.
  EXPECT_TRUE(
      extractProfile(
          cloud, {{kProfileEast + 1, kProfileNorth, 0}, {kProfileEast + 1, kProfileNorth, 9}}, 1.0)
          .samples.empty());
  EXPECT_TRUE(
      extractProfile(cloud,
                     {{kProfileEast, kProfileNorth, 0}, {kProfileEast + 5, kProfileNorth, 0}}, 0.0)
          .samples.empty());
}

TEST(HeightProfile, CsvAndLasExportsReadBack) {
  const PointCloud cloud = slope();
  const std::vector<glm::dvec3> line{{kProfileEast + 2, kProfileNorth, 0},
                                     {kProfileEast + 12, kProfileNorth, 0}};
  const HeightProfile profile = extractProfile(cloud, line, 1.1);
  const auto dir = profileDir();

  writeProfileCsv(profile, dir / "profile.csv");
  EXPECT_FALSE(std::filesystem::exists(dir / "profile.csv.partial"));
  std::ifstream csv(dir / "profile.csv");
  std::string header;
  std::getline(csv, header);
  EXPECT_EQ(header, "station,height,offset,x,y,z");
  std::size_t rows = 0;
  for (std::string row; std::getline(csv, row); ++rows) {
    double values[6];
    ASSERT_EQ(std::sscanf(row.c_str(), "%lf,%lf,%lf,%lf,%lf,%lf", &values[0], &values[1],
                          &values[2], &values[3], &values[4], &values[5]),
              6)
        << row;
    const ProfileSample& s = profile.samples[rows];
    EXPECT_EQ(values[0], s.station);  // 17 digits: exactly the doubles
    EXPECT_EQ(values[1], s.position.z);
    EXPECT_EQ(values[3], s.position.x);
    EXPECT_EQ(values[4], s.position.y);
  }
  EXPECT_EQ(rows, profile.samples.size());

  writeProfileLas(profile, dir / "profile.las");
  const PointCloud las = readLas(dir / "profile.las");
  ASSERT_EQ(las.count, profile.samples.size());
  for (std::size_t i = 0; i < las.count; ++i) {
    EXPECT_EQ(las.worldX(i), profile.samples[i].position.x);
    EXPECT_EQ(las.worldY(i), profile.samples[i].position.y);
    EXPECT_EQ(las.worldZ(i), profile.samples[i].position.z);
  }
}

}  // namespace
}  // namespace parallax
