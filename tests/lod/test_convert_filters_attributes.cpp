// `parallax convert --returns / --intensity / --elevation / --gps-time / --clip-polygon` end to
// end: from a LAS file, a Potree octree and a COPC file, to a Potree directory, a COPC file and a
// LAS file, the output read back holds exactly the input's points that the filter keeps, with
// their exact values (millimetres, returns, intensity, GPS time to the bit), compared as sorted
// sets with the input filtered by hand in integers. Bad polygon files are clear errors, and the
// converter (on the CPU) takes polygons beyond the shaders' vertex limit.
#include <gtest/gtest.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <functional>
#include <iomanip>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "io/las_writer.h"
#include "io/point_file.h"
#include "lod/copc_reader.h"
#include "lod/octree_node_batches.h"
#include "lod/potree_reader.h"
#include "support/run_parallax.h"
#include "support/temp_dir.h"

namespace parallax::test {
namespace {

// x, y, z in millimetres, return number, number of returns, intensity, GPS time.
using Key = std::tuple<long long, long long, long long, int, int, int, double>;
constexpr double kGpsBase = 400000000.0;

// 12 000 points on a 1 mm grid in a 40 x 30 x 10 m box at UTM-like coordinates, 1-5 returns,
// intensities 0-4095, GPS times at whole microseconds over 100 s. Deterministic.
PointCloud makeCloud() {
  const std::uint64_t count = 12000;
  PointCloud cloud;
  cloud.count = count;
  cloud.quantization.scale = {0.001, 0.001, 0.001};
  cloud.quantization.offset = {500000.0, 5000000.0, 0.0};
  cloud.positions = Column<Int3>(count);
  cloud.intensity = Column<float>(count);
  cloud.source.intensity = ScalarType::UInt16;
  ScalarColumn r{.name = "return_number", .type = ScalarType::UInt8, .data = ByteBuffer(count)};
  ScalarColumn n{.name = "number_of_returns", .type = ScalarType::UInt8, .data = ByteBuffer(count)};
  ScalarColumn gps{.name = "gps_time", .type = ScalarType::Float64, .data = ByteBuffer(count * 8)};
  std::uint32_t state = 11;
  auto next = [&] {  // xorshift32
    state ^= state << 13;
    state ^= state >> 17;
    state ^= state << 5;
    return state;
  };
  for (std::uint64_t i = 0; i < count; ++i) {
    cloud.positions[i] = {std::int32_t(next() % 40000), std::int32_t(next() % 30000),
                          std::int32_t(100000 + next() % 10000)};
    cloud.intensity[i] = float(next() % 4096);
    const std::uint32_t returns = 1 + next() % 5;
    n.as<std::uint8_t>()[i] = std::uint8_t(returns);
    r.as<std::uint8_t>()[i] = std::uint8_t(1 + next() % returns);
    gps.as<double>()[i] = kGpsBase + double(next() % 100000001u) * 1e-6;
  }
  cloud.scalars.push_back(std::move(r));
  cloud.scalars.push_back(std::move(n));
  cloud.scalars.push_back(std::move(gps));
  cloud.computeBounds();
  return cloud;
}

std::vector<Key> keysOf(const PointCloud& cloud) {
  const ScalarColumn* r = cloud.findScalar("return_number");
  const ScalarColumn* n = cloud.findScalar("number_of_returns");
  const ScalarColumn* gps = cloud.findScalar("gps_time");
  EXPECT_TRUE(r && n && gps) << "returns or GPS time lost";
  std::vector<Key> keys;
  for (std::uint64_t i = 0; i < cloud.count; ++i) {
    keys.emplace_back(std::llround(cloud.worldX(i) * 1000.0),
                      std::llround(cloud.worldY(i) * 1000.0),
                      std::llround(cloud.worldZ(i) * 1000.0), r ? int(r->valueAsDouble(i)) : -1,
                      n ? int(n->valueAsDouble(i)) : -1, int(cloud.intensity[i]),
                      gps ? gps->valueAsDouble(i) : -1.0);
  }
  std::sort(keys.begin(), keys.end());
  return keys;
}

std::vector<Key> octreeKeys(Octree& octree) {
  expandWholeOctree(octree);
  std::vector<Key> keys;
  for (const OctreeNode& node : octree.nodes()) {
    const std::vector<Key> part = keysOf(octree.loadNode(node));
    keys.insert(keys.end(), part.begin(), part.end());
  }
  std::sort(keys.begin(), keys.end());
  return keys;
}

std::vector<Key> keep(const std::vector<Key>& all, const std::function<bool(const Key&)>& test) {
  std::vector<Key> kept;
  std::copy_if(all.begin(), all.end(), std::back_inserter(kept), test);
  return kept;
}

int ret(const Key& k) {
  return std::get<3>(k);
}
int returns(const Key& k) {
  return std::get<4>(k);
}
int intensity(const Key& k) {
  return std::get<5>(k);
}
// Whole microseconds past kGpsBase (the values were made so; exact at this magnitude).
long long gpsMicroseconds(const Key& k) {
  return std::llround((std::get<6>(k) - kGpsBase) * 1e6);
}

// A polygon with vertices on odd half millimetres (world = half_mm / 2000 m): the hand test is
// the crossing number in exact integers; no point of the grid lies on an edge's vertex.
struct HandPolygon {
  std::vector<std::array<long long, 2>> half_mm;

  bool inside(const Key& k) const {
    const long long x = 2 * std::get<0>(k), y = 2 * std::get<1>(k);
    bool in = false;
    for (std::size_t i = 0, j = half_mm.size() - 1; i < half_mm.size(); j = i++) {
      const auto& a = half_mm[i];
      const auto& b = half_mm[j];
      if ((a[1] > y) == (b[1] > y)) continue;
      // Relative to a: the products (below 1e10) stay well inside 64 bits.
      const long long lhs = (x - a[0]) * (b[1] - a[1]);
      const long long rhs = (b[0] - a[0]) * (y - a[1]);
      if (b[1] > a[1] ? lhs < rhs : lhs > rhs) in = !in;
    }
    return in;
  }

  // The smallest distance (mm) of a point to an edge: the double test of the product may only
  // disagree with the exact one within rounding of an edge.
  double distanceToEdges(const Key& k) const {
    double best = INFINITY;
    for (std::size_t i = 0, j = half_mm.size() - 1; i < half_mm.size(); j = i++) {
      const double x = double(2 * std::get<0>(k) - half_mm[i][0]);
      const double y = double(2 * std::get<1>(k) - half_mm[i][1]);
      const double dx = double(half_mm[j][0] - half_mm[i][0]);
      const double dy = double(half_mm[j][1] - half_mm[i][1]);
      const double t = std::clamp((x * dx + y * dy) / (dx * dx + dy * dy), 0.0, 1.0);
      best = std::min(best, std::hypot(x - t * dx, y - t * dy));
    }
    return best / 2.0;
  }

  static std::string coordinate(long long half_mm) {
    const long long tenths = half_mm * 5;  // tenths of a millimetre
    std::ostringstream text;
    text << tenths / 10000 << '.' << std::setw(4) << std::setfill('0') << tenths % 10000;
    return text.str();
  }

  std::string geoJson() const {
    std::string json = R"({"type":"Feature","geometry":{"type":"Polygon","coordinates":[[)";
    for (std::size_t i = 0; i <= half_mm.size(); ++i) {
      const auto& v = half_mm[i % half_mm.size()];
      json += (i ? ",[" : "[") + coordinate(v[0]) + "," + coordinate(v[1]) + "]";
    }
    return json + "]]}}";
  }

  std::string text() const {
    std::string lines = "# x y\n";
    for (const auto& v : half_mm) lines += coordinate(v[0]) + " " + coordinate(v[1]) + "\n";
    return lines;
  }
};

// A concave hexagon over part of the cloud (x 500000-500040, y 5000000-5000030 m).
HandPolygon concave() {
  const long long x0 = 2 * 500000000, y0 = 2 * 5000000000;
  return {{{x0 + 10001, y0 + 8001},
           {x0 + 70001, y0 + 4001},
           {x0 + 60001, y0 + 50001},
           {x0 + 36001, y0 + 24001},
           {x0 + 30001, y0 + 56001},
           {x0 + 4001, y0 + 40001}}};
}

// 1 000 vertices around a circle of 12 m: beyond the shaders' 256, which convert does not have.
HandPolygon circle() {
  HandPolygon p;
  for (int i = 0; i < 1000; ++i) {
    const double a = 2 * M_PI * i / 1000;
    p.half_mm.push_back({2 * (500020000 + std::llround(12000 * std::cos(a))) + 1,
                         2 * (5000015000 + std::llround(12000 * std::sin(a))) + 1});
  }
  return p;
}

class ConvertAttributeFilters : public ::testing::Test {
 protected:
  void SetUp() override {
    las_ = dir_ / "in.las";
    writeLas(makeCloud(), las_, {});
    all_ = keysOf(readPointFile(las_));
    ASSERT_EQ(all_.size(), 12000u);
  }
  void convert(const std::filesystem::path& in, const std::filesystem::path& out,
               const std::string& options) {
    const RunResult r = runParallax(dir_, "convert " + quoted(in.string()) + " -o " +
                                              quoted(out.string()) + " --quiet " + options);
    ASSERT_EQ(r.exit_code, 0) << options << "\n" << r.err;
  }
  // Checks that `kept` is a real selection (not all, not nothing).
  static void expectSelective(const std::vector<Key>& kept, std::size_t all) {
    ASSERT_GT(kept.size(), 100u);
    ASSERT_LT(kept.size(), all);
  }
  TempDir dir_;
  std::filesystem::path las_;
  std::vector<Key> all_;
};

TEST_F(ConvertAttributeFilters, ReturnsAndIntensityFromLasToPotree) {
  const auto kept = keep(all_, [](const Key& k) {
    return (ret(k) == 1 || ret(k) == returns(k)) && intensity(k) >= 1000 && intensity(k) <= 3000;
  });
  expectSelective(kept, all_.size());
  convert(las_, dir_ / "octree", "--returns first,last --intensity 1000,3000");
  EXPECT_EQ(octreeKeys(*openPotree(dir_ / "octree")), kept);
}

TEST_F(ConvertAttributeFilters, GpsTimeAndElevationFromLasToLasToTheMicrosecond) {
  const auto kept = keep(all_, [](const Key& k) {
    return gpsMicroseconds(k) >= 25000001 && gpsMicroseconds(k) <= 75000000 &&
           std::get<2>(k) >= 102500 && std::get<2>(k) <= 107250;
  });
  expectSelective(kept, all_.size());
  convert(las_, dir_ / "out.las",
          "--gps-time 400000025.0000005,400000075.0000005 --elevation 102.4995,107.2505");
  EXPECT_EQ(keysOf(readPointFile(dir_ / "out.las")), kept);
}

TEST_F(ConvertAttributeFilters, PolygonFromAPotreeOctreeToCopcInsideAndOutside) {
  const HandPolygon polygon = concave();
  for (const Key& k : all_) ASSERT_GT(polygon.distanceToEdges(k), 0.001);
  const auto file = dir_.write("area.geojson", polygon.geoJson());
  const auto inside = keep(all_, [&](const Key& k) { return polygon.inside(k); });
  expectSelective(inside, all_.size());
  convert(las_, dir_ / "all", "");
  ASSERT_EQ(octreeKeys(*openPotree(dir_ / "all")), all_);
  convert(dir_ / "all", dir_ / "inside.copc.laz", "--clip-polygon " + quoted(file.string()));
  EXPECT_EQ(octreeKeys(*openCopc(dir_ / "inside.copc.laz")), inside);
  const auto outside_last = keep(all_, [&](const Key& k) {
    return !polygon.inside(k) && (ret(k) == returns(k) || ret(k) == 2);
  });
  convert(dir_ / "all", dir_ / "outside",
          "--clip-polygon " + quoted(file.string()) + " --clip-mode outside --returns last,2");
  EXPECT_EQ(octreeKeys(*openPotree(dir_ / "outside")), outside_last);
}

TEST_F(ConvertAttributeFilters, PolygonTextFileFromCopcToLasWithoutAVertexLimit) {
  const HandPolygon polygon = circle();
  for (const Key& k : all_) ASSERT_GT(polygon.distanceToEdges(k), 0.001);
  const auto file = dir_.write("circle.txt", polygon.text());
  const auto kept = keep(all_, [&](const Key& k) { return polygon.inside(k) && returns(k) == 1; });
  expectSelective(kept, all_.size());
  convert(las_, dir_ / "all.copc.laz", "");
  convert(dir_ / "all.copc.laz", dir_ / "circle.las",
          "--clip-polygon " + quoted(file.string()) + " --returns single");
  EXPECT_EQ(keysOf(readPointFile(dir_ / "circle.las")), kept);
}

// The octrees record the kept points' intensity and GPS time ranges where their formats can
// (Potree metadata's min and max, COPC's info VLR for GPS time): the viewer's sliders start there.
TEST_F(ConvertAttributeFilters, OctreesRecordTheKeptPointsRanges) {
  const auto kept = keep(all_, [](const Key& k) { return ret(k) == 1; });
  double gps[2] = {INFINITY, -INFINITY};
  int intensities[2] = {INT_MAX, INT_MIN};
  for (const Key& k : kept) {
    gps[0] = std::min(gps[0], std::get<6>(k)), gps[1] = std::max(gps[1], std::get<6>(k));
    intensities[0] = std::min(intensities[0], intensity(k));
    intensities[1] = std::max(intensities[1], intensity(k));
  }
  convert(las_, dir_ / "first", "--returns first");
  const auto potree = openPotree(dir_ / "first");
  ASSERT_TRUE(potree->info().gps_time_range.has_value());
  EXPECT_EQ((*potree->info().gps_time_range)[0], gps[0]);
  EXPECT_EQ((*potree->info().gps_time_range)[1], gps[1]);
  ASSERT_TRUE(potree->info().intensity_range.has_value());
  EXPECT_EQ((*potree->info().intensity_range)[0], intensities[0]);
  EXPECT_EQ((*potree->info().intensity_range)[1], intensities[1]);
  convert(las_, dir_ / "first.copc.laz", "--returns first");
  const auto copc = openCopc(dir_ / "first.copc.laz");
  ASSERT_TRUE(copc->info().gps_time_range.has_value());
  EXPECT_EQ((*copc->info().gps_time_range)[0], gps[0]);
  EXPECT_EQ((*copc->info().gps_time_range)[1], gps[1]);
}

TEST_F(ConvertAttributeFilters, BadValuesAndPolygonFilesAreClearErrors) {
  const auto holes = dir_.write(
      "holes.geojson",
      R"({"type":"Polygon","coordinates":[[[0,0],[9,0],[9,9],[0,0]],[[1,1],[2,1],[2,2],[1,1]]]})");
  const auto two = dir_.write("two.txt", "500000 5000000\n500010 5000000\n");
  struct Case {
    std::string options, message;
    int exit_code;
  };
  for (const auto& [options, message, exit_code] : std::vector<Case>{
           {"--returns firstt", "--returns: item 'firstt' is not a return", 1},
           {"--intensity 3000,1000", "--intensity: MIN '3000' is greater than MAX '1000'", 1},
           {"--gps-time ,5", "--gps-time: MIN '' is not a number", 1},
           {"--clip-polygon " + quoted(holes.string()),
            "element '$.coordinates': expected one ring (a polygon without holes), found 2 rings",
            2},
           {"--clip-polygon " + quoted(two.string()),
            "expected at least 3 distinct vertices, found 2", 2},
           {"--gps-time 1,2", "at least one point that the filters", 2},
           {"--clip-polygon " + quoted(two.string()) + " --clip-mode highlight",
            "--clip-mode: highlight tints the region in a picture and keeps every point: use it "
            "with render or view",
            1}}) {
    const RunResult r = runParallax(dir_, "convert " + quoted(las_.string()) + " -o " +
                                              quoted((dir_ / "bad.las").string()) + " " + options);
    EXPECT_EQ(r.exit_code, exit_code) << options << "\n" << r.err;
    EXPECT_NE(r.err.find(message), std::string::npos) << options << "\n" << r.err;
    EXPECT_FALSE(std::filesystem::exists(dir_ / "bad.las")) << options;
  }
}

}  // namespace
}  // namespace parallax::test
