// `parallax convert --classes / --clip-box / --clip-mode` end to end: from a LAS file and from a
// Potree octree, to a Potree directory, a COPC file and a LAS file, the output read back holds
// exactly the input's points that the filter keeps (compared as sorted sets), and the octrees'
// counts and bounds describe the kept points. Malformed lists are clear errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>
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

// A point as compared: millimetres (the files' grid), classification, intensity.
using Key = std::tuple<long long, long long, long long, int, int>;

// 12 000 points at UTM-like coordinates on a 1 mm grid, classes 0-19 (19 outside ASPRS's named
// ones), in a 40 x 30 x 10 m box. Deterministic.
PointCloud makeClassifiedCloud() {
  const std::uint64_t count = 12000;
  PointCloud cloud;
  cloud.count = count;
  cloud.quantization.scale = {0.001, 0.001, 0.001};
  cloud.quantization.offset = {500000.0, 5000000.0, 0.0};
  cloud.positions = Column<Int3>(count);
  cloud.intensity = Column<float>(count);
  cloud.classification = Column<std::uint8_t>(count);
  cloud.source.intensity = ScalarType::UInt16;
  std::uint32_t state = 7;
  auto next = [&] {  // xorshift32
    state ^= state << 13;
    state ^= state >> 17;
    state ^= state << 5;
    return state;
  };
  for (std::uint64_t i = 0; i < count; ++i) {
    cloud.positions[i] = {std::int32_t(next() % 40000), std::int32_t(next() % 30000),
                          std::int32_t(100000 + next() % 10000)};
    cloud.intensity[i] = float(i % 4096);
    cloud.classification[i] = std::uint8_t(next() % 20);
  }
  cloud.computeBounds();
  return cloud;
}

std::vector<Key> keysOf(const PointCloud& cloud) {
  std::vector<Key> keys;
  for (std::uint64_t i = 0; i < cloud.count; ++i) {
    keys.emplace_back(std::llround(cloud.worldX(i) * 1000.0),
                      std::llround(cloud.worldY(i) * 1000.0),
                      std::llround(cloud.worldZ(i) * 1000.0),
                      cloud.hasClassification() ? cloud.classification[i] : 0,
                      cloud.hasIntensity() ? int(cloud.intensity[i]) : 0);
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

// The filter written out by hand, in millimetres (no plane arithmetic shared with the product).
struct Expected {
  std::vector<int> classes;  // empty: all
  bool box = false, outside = false;
  long long min[3] = {0, 0, 0}, max[3] = {0, 0, 0};  // mm, inclusive

  bool keeps(const Key& k) const {
    if (!classes.empty() &&
        std::find(classes.begin(), classes.end(), std::get<3>(k)) == classes.end()) {
      return false;
    }
    if (!box) return true;
    const long long p[3] = {std::get<0>(k), std::get<1>(k), std::get<2>(k)};
    bool inside = true;
    for (int a = 0; a < 3; ++a) inside = inside && p[a] >= min[a] && p[a] <= max[a];
    return inside != outside;
  }
  std::vector<Key> of(const std::vector<Key>& all) const {
    std::vector<Key> kept;
    std::copy_if(all.begin(), all.end(), std::back_inserter(kept),
                 [&](const Key& k) { return keeps(k); });
    return kept;
  }
};

// The box 500010.0005-500025.0005 x 5000005.0005-5000020.0005 x 102.0005-108.0005: its faces lie
// half a millimetre from the grid, so no point is on them.
const char* const kBoxOption =
    "--clip-box 500010.0005,5000005.0005,102.0005,"
    "500025.0005,5000020.0005,108.0005";
Expected boxExpected(bool outside) {
  Expected e;
  e.box = true, e.outside = outside;
  const long long min[3] = {500010001, 5000005001, 102001},
                  max[3] = {500025000, 5000020000, 108000};
  for (int a = 0; a < 3; ++a) e.min[a] = min[a], e.max[a] = max[a];
  return e;
}

class ConvertFilters : public ::testing::Test {
 protected:
  void SetUp() override {
    las_ = dir_ / "in.las";
    writeLas(makeClassifiedCloud(), las_, {});
    all_ = keysOf(readPointFile(las_));
    ASSERT_EQ(all_.size(), 12000u);
  }
  // Converts with `options` and checks the exit status.
  void convert(const std::filesystem::path& in, const std::filesystem::path& out,
               const std::string& options) {
    const RunResult r = runParallax(dir_, "convert " + quoted(in.string()) + " -o " +
                                              quoted(out.string()) + " --quiet " + options);
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  // A Potree directory's metadata describes exactly `kept`: its count and its positions' range.
  void expectMetadataOf(const std::filesystem::path& potree, const std::vector<Key>& kept) {
    std::ifstream in(potree / "metadata.json");
    const nlohmann::json metadata = nlohmann::json::parse(in);
    EXPECT_EQ(metadata["points"].get<std::uint64_t>(), kept.size());
    long long lo[3] = {LLONG_MAX, LLONG_MAX, LLONG_MAX}, hi[3] = {LLONG_MIN, LLONG_MIN, LLONG_MIN};
    for (const Key& k : kept) {
      const long long p[3] = {std::get<0>(k), std::get<1>(k), std::get<2>(k)};
      for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], p[a]), hi[a] = std::max(hi[a], p[a]);
    }
    bool found = false;
    for (const auto& attribute : metadata["attributes"]) {
      if (attribute["name"] != "position") continue;
      found = true;
      for (int a = 0; a < 3; ++a) {
        EXPECT_EQ(std::llround(attribute["min"][a].get<double>() * 1000.0), lo[a]) << a;
        EXPECT_EQ(std::llround(attribute["max"][a].get<double>() * 1000.0), hi[a]) << a;
      }
    }
    EXPECT_TRUE(found) << "no position attribute in metadata.json";
  }
  TempDir dir_;
  std::filesystem::path las_;
  std::vector<Key> all_;
};

TEST_F(ConvertFilters, ClassesFromLasToPotreeKeepExactlyThoseClasses) {
  const Expected e{.classes = {2, 6, 9, 10, 11, 12}};
  const std::vector<Key> kept = e.of(all_);
  ASSERT_GT(kept.size(), 2000u);
  ASSERT_LT(kept.size(), all_.size());
  convert(las_, dir_ / "octree", "--classes 2,6,9-12");
  EXPECT_EQ(octreeKeys(*openPotree(dir_ / "octree")), kept);
  expectMetadataOf(dir_ / "octree", kept);
}

TEST_F(ConvertFilters, ClipBoxFromLasToPotreeAndCopcInsideAndOutside) {
  const std::vector<Key> inside = boxExpected(false).of(all_);
  const std::vector<Key> outside = boxExpected(true).of(all_);
  ASSERT_GT(inside.size(), 500u);
  ASSERT_EQ(inside.size() + outside.size(), all_.size());
  convert(las_, dir_ / "inside", kBoxOption);
  EXPECT_EQ(octreeKeys(*openPotree(dir_ / "inside")), inside);
  expectMetadataOf(dir_ / "inside", inside);
  convert(las_, dir_ / "outside.copc.laz", std::string(kBoxOption) + " --clip-mode outside");
  const auto copc = openCopc(dir_ / "outside.copc.laz");
  EXPECT_EQ(copc->info().point_count, outside.size());
  EXPECT_EQ(octreeKeys(*copc), outside);
  // A COPC header's bounds are those of the kept points.
  convert(las_, dir_ / "inside.copc.laz", kBoxOption);
  const Bounds3 bounds = openCopc(dir_ / "inside.copc.laz")->info().bounds;
  for (int a = 0; a < 3; ++a) {
    long long lo = LLONG_MAX, hi = LLONG_MIN;
    for (const Key& k : inside) {
      const long long v = a == 0 ? std::get<0>(k) : a == 1 ? std::get<1>(k) : std::get<2>(k);
      lo = std::min(lo, v), hi = std::max(hi, v);
    }
    EXPECT_EQ(std::llround(bounds.min[std::size_t(a)] * 1000.0), lo) << a;
    EXPECT_EQ(std::llround(bounds.max[std::size_t(a)] * 1000.0), hi) << a;
  }
}

TEST_F(ConvertFilters, LasToLasFileKeepsClassesAndBoxTogether) {
  Expected e = boxExpected(false);
  e.classes = {0, 1, 19};
  const std::vector<Key> kept = e.of(all_);
  ASSERT_GT(kept.size(), 50u);
  convert(las_, dir_ / "out.las", std::string(kBoxOption) + " --classes 0,1,19");
  EXPECT_EQ(keysOf(readPointFile(dir_ / "out.las")), kept);
}

TEST_F(ConvertFilters, FromAPotreeOctreeToEveryOutput) {
  convert(las_, dir_ / "all", "");
  ASSERT_EQ(octreeKeys(*openPotree(dir_ / "all")), all_);
  const Expected classes{.classes = {3, 4, 5, 17}};
  convert(dir_ / "all", dir_ / "classes", "--classes 3-5,17");
  EXPECT_EQ(octreeKeys(*openPotree(dir_ / "classes")), classes.of(all_));
  expectMetadataOf(dir_ / "classes", classes.of(all_));
  convert(dir_ / "all", dir_ / "box.las", kBoxOption);
  EXPECT_EQ(keysOf(readPointFile(dir_ / "box.las")), boxExpected(false).of(all_));
  convert(dir_ / "all", dir_ / "outside.copc.laz",
          std::string(kBoxOption) + " --clip-mode outside");
  EXPECT_EQ(octreeKeys(*openCopc(dir_ / "outside.copc.laz")), boxExpected(true).of(all_));
}

// A box of 24 x 12 m turned -25 degrees about its centre (500020.0005, 5000012.0005), its z from
// 101.0005 to 109.0005: the points kept are those the rotation puts inside, found here in double
// from the millimetre grid; each at least 0.01 mm from a face, else the test cannot tell.
std::vector<Key> turnedBoxExpected(const std::vector<Key>& all, bool outside) {
  const double radians = -25.0 * std::numbers::pi / 180.0;
  const double cs = std::cos(radians), sn = std::sin(radians);
  std::vector<Key> kept;
  for (const Key& k : all) {
    const double dx = double(std::get<0>(k) - 500000000) - 20000.5;
    const double dy = double(std::get<1>(k) - 5000000000) - 12000.5;
    const double u = cs * dx + sn * dy, v = -sn * dx + cs * dy;
    EXPECT_GT(std::min(std::abs(12000.0 - std::abs(u)), std::abs(6000.0 - std::abs(v))), 0.01);
    const bool inside = std::abs(u) <= 12000.0 && std::abs(v) <= 6000.0 &&
                        std::get<2>(k) >= 101001 && std::get<2>(k) <= 109000;
    if (inside != outside) kept.push_back(k);
  }
  return kept;
}
const char* const kTurnedBoxOption =
    "--clip-box 500008.0005,5000006.0005,101.0005,500032.0005,5000018.0005,109.0005,-25";

TEST_F(ConvertFilters, TurnedClipBoxFromLasAndFromAnOctree) {
  const std::vector<Key> inside = turnedBoxExpected(all_, false);
  ASSERT_GT(inside.size(), 1000u);
  ASSERT_LT(inside.size(), all_.size() / 2);
  convert(las_, dir_ / "turned", kTurnedBoxOption);
  EXPECT_EQ(octreeKeys(*openPotree(dir_ / "turned")), inside);
  expectMetadataOf(dir_ / "turned", inside);
  convert(las_, dir_ / "all", "");
  convert(dir_ / "all", dir_ / "outside.las",
          std::string(kTurnedBoxOption) + " --clip-mode outside");
  EXPECT_EQ(keysOf(readPointFile(dir_ / "outside.las")), turnedBoxExpected(all_, true));
}

TEST_F(ConvertFilters, FromACopcFileToPotree) {
  convert(las_, dir_ / "all.copc.laz", "");
  const Expected e{.classes = {7, 18}};
  convert(dir_ / "all.copc.laz", dir_ / "noise", "--classes 7,18");
  EXPECT_EQ(octreeKeys(*openPotree(dir_ / "noise")), e.of(all_));
}

// The distributed build, task by task as a driver runs them (`convert --plan`, then each stage's
// `convert-task` over every range or group), with the same filter options as a local `convert`:
// the same octree, byte for byte. From LAZ, from a text file and from a Potree octree (inputs read
// whole by one task each: their readers cannot skip; many ranges and groups are
// test_distributed_convert.cpp's). The filter travels in plan.json, as the tasks read it.
class DistributedConvertFilters : public ConvertFilters {
 protected:
  std::string readAll(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  }
  void task(const std::string& stage, const std::filesystem::path& plan, std::size_t part) {
    const RunResult r = runParallax(dir_, "convert-task " + stage + " " + quoted(plan.string()) +
                                              " --part " + std::to_string(part));
    ASSERT_EQ(r.exit_code, 0) << stage << " " << part << ": " << r.err;
  }
  // `convert in -o local/NAME OPTIONS` and the same through the tasks, to tasks/NAME: the same
  // metadata.json, hierarchy.bin and octree.bin.
  void expectTasksBuildTheLocalOctree(const std::filesystem::path& in, const std::string& name,
                                      const std::string& options) {
    const auto local = dir_ / "local" / name, tasks = dir_ / "tasks" / name;
    const auto work = dir_ / (name + "_work");
    ASSERT_NO_FATAL_FAILURE(convert(in, local, options));
    ASSERT_NO_FATAL_FAILURE(convert(
        in, tasks,
        "--plan --tasks 3 --build-tasks 3 --work-dir " + quoted(work.string()) + " " + options));
    const auto plan = work / "plan.json";
    const std::size_t ranges = nlohmann::json::parse(readAll(plan)).at("ranges").size();
    for (const std::string stage : {"scan", "cube", "count", "chunks", "distribute"}) {
      const bool per_range = stage != "cube" && stage != "chunks";
      for (std::size_t part = 0; part < (per_range ? ranges : 1); ++part) {
        ASSERT_NO_FATAL_FAILURE(task(stage, plan, part));
      }
    }
    const std::size_t groups =
        nlohmann::json::parse(readAll(work / "chunks.json")).at("groups").size();
    for (const std::string stage : {"build", "place"}) {
      for (std::size_t part = 0; part < groups; ++part) {
        ASSERT_NO_FATAL_FAILURE(task(stage, plan, part));
      }
    }
    ASSERT_NO_FATAL_FAILURE(task("finish", plan, 0));
    for (const char* file : {"metadata.json", "hierarchy.bin", "octree.bin"}) {
      const std::string a = readAll(local / file), b = readAll(tasks / file);
      EXPECT_FALSE(a.empty()) << file;
      EXPECT_TRUE(a == b) << name << ": " << file << " differs (" << a.size() << " and " << b.size()
                          << " bytes)";
    }
  }
};

TEST_F(DistributedConvertFilters, FromLazWithClassesAndAClipBox) {
  convert(las_, dir_ / "in.laz", "");
  expectTasksBuildTheLocalOctree(dir_ / "in.laz", "classes", "--classes 2,6,9-12");
  expectTasksBuildTheLocalOctree(dir_ / "in.laz", "box", kBoxOption);
}

TEST_F(DistributedConvertFilters, FromATextFileWithAClipBoxOutside) {
  std::ofstream text(dir_ / "in.txt");
  text.precision(10);
  const PointCloud cloud = readPointFile(las_);
  for (std::uint64_t i = 0; i < cloud.count; ++i) {
    text << cloud.worldX(i) << ' ' << cloud.worldY(i) << ' ' << cloud.worldZ(i) << ' '
         << int(cloud.classification[i]) << '\n';
  }
  text.close();
  expectTasksBuildTheLocalOctree(
      dir_ / "in.txt", "text",
      "--columns x,y,z,classification " + std::string(kBoxOption) + " --clip-mode outside");
}

TEST_F(DistributedConvertFilters, FromAPotreeOctreeWithClasses) {
  convert(las_, dir_ / "all", "");
  expectTasksBuildTheLocalOctree(dir_ / "all", "octree", "--classes 3-5,17");
}

TEST_F(ConvertFilters, AFilterThatKeepsNothingIsAClearError) {
  const RunResult r = runParallax(dir_, "convert " + quoted(las_.string()) + " -o " +
                                            quoted((dir_ / "none").string()) + " --classes 200");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find(
                "at least one point that the filters (classes, returns, ranges, clip region) keep"),
            std::string::npos)
      << r.err;
}

// Each malformed option names the option, the item and what was expected.
TEST_F(ConvertFilters, MalformedListsAreClearErrors) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"--classes ''", "--classes: expected a list, found an empty value"},
      {"--classes 2,x", "--classes: item 'x' is not a class: expected a class number 0-255"},
      {"--classes 2,,3", "--classes: item '' is not a class"},
      {"--classes 256", "--classes: item '256' is not a class"},
      {"--classes=-3", "--classes: item '-3' is not a class"},
      {"--classes 9-x", "--classes: item '9-x' is not a range"},
      {"--classes 12-9", "--classes: range '12-9' runs backwards: expected N-M with N <= M"},
      {"--clip-box 1,2,3",
       "--clip-box: expected six numbers XMIN,YMIN,ZMIN,XMAX,YMAX,ZMAX, "
       "and optionally a seventh, YAW, found 3 items"},
      {"--clip-box 0,0,a,1,1,1", "--clip-box: ZMIN 'a' is not a number"},
      {"--clip-box 0,5,0,1,2,1", "--clip-box: YMIN '5' is greater than YMAX '2'"},
      {"--clip-box 0,0,0,1,1,1,inf", "--clip-box: YAW 'inf' is not a number: expected degrees"},
      {"--clip-box 0,0,0,1,1,1 --clip-mode sideways",
       "--clip-mode: unknown mode 'sideways' (use inside|outside)"},
  };
  for (const auto& [options, message] : cases) {
    const RunResult r = runParallax(dir_, "convert " + quoted(las_.string()) + " -o " +
                                              quoted((dir_ / "bad.las").string()) + " " + options);
    EXPECT_NE(r.exit_code, 0) << options;
    EXPECT_NE(r.err.find(message), std::string::npos) << options << "\n" << r.err;
    EXPECT_FALSE(std::filesystem::exists(dir_ / "bad.las")) << options;
  }
}

}  // namespace
}  // namespace parallax::test
