// The octree builder keeps only the attributes asked for (ConvertInput::attributes, `convert
// --properties`), and a LAZ of point formats 6-10 then decodes only their layers: the octree is
// the one the LAS twin gives with the same attributes, its points are the full conversion's
// positions and colours, and damage in a layer not asked for changes nothing.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <sstream>
#include <tuple>

#include "core/error.h"
#include "io/point_file.h"
#include "lod/convert_stages.h"
#include "lod/octree_node_batches.h"
#include "lod/potree_converter.h"
#include "lod/potree_reader.h"
#include "lod_test_clouds.h"
#include "support/file_bytes.h"
#include "support/temp_dir.h"

namespace parallax::test {
namespace {

using test::smallChunks;

ConvertInput input(const std::filesystem::path& path, const AttributeSelection& attributes,
                   const PointFilter& filter = {}) {
  return {.path = path, .text_columns = {}, .filter = filter, .attributes = attributes};
}

// Every point of an octree as (x, y, z, red, green, blue), sorted: each point is stored once.
std::vector<std::tuple<std::int32_t, std::int32_t, std::int32_t, int, int, int>> pointsOf(
    const std::filesystem::path& dir) {
  std::unique_ptr<Octree> octree = openPotree(dir);
  expandWholeOctree(*octree);
  std::vector<std::tuple<std::int32_t, std::int32_t, std::int32_t, int, int, int>> points;
  for (const OctreeNode& node : octree->nodes()) {
    const PointCloud cloud = octree->loadNode(node);
    EXPECT_TRUE(cloud.hasColors());
    if (!cloud.hasColors()) return points;
    for (std::uint64_t i = 0; i < cloud.count; ++i) {
      const Int3 p = cloud.positions[i];
      const Rgba8 c = cloud.colors[i];
      points.emplace_back(p.x, p.y, p.z, c.r, c.g, c.b);
    }
  }
  std::sort(points.begin(), points.end());
  return points;
}

const AttributeSelection kColour = AttributeSelection::only({"red", "green", "blue"});

TEST(ConvertSelective, KeepsOnlyTheAttributesAskedAsTheLasTwinDoes) {
  TempDir dir;
  const PointCloud cloud = makeLasLikeCloud(30'000, 7);
  writePointFile(cloud, dir / "in.las", {.las_point_format = 7});
  writePointFile(cloud, dir / "in.laz", {.las_point_format = 7});
  convertToPotree({input(dir / "in.las", kColour)}, dir / "las_rgb", smallChunks());
  convertToPotree({input(dir / "in.laz", kColour)}, dir / "laz_rgb", smallChunks());
  convertToPotree({input(dir / "in.laz", {})}, dir / "laz_all", smallChunks());
  // The LAS reader fills every column and the stream drops the others; the LAZ reader decodes
  // the colour layers only: the same octree.
  expectSameOctree(dir / "las_rgb", dir / "laz_rgb");
  EXPECT_EQ(openPotree(dir / "laz_rgb")->info().attributes,
            (std::vector<std::string>{"x", "y", "z", "red", "green", "blue"}));
  const std::vector<std::string> all = openPotree(dir / "laz_all")->info().attributes;
  EXPECT_NE(std::find(all.begin(), all.end(), "gps_time"), all.end());
  EXPECT_NE(std::find(all.begin(), all.end(), "intensity"), all.end());
  // The points and their colours are the full conversion's.
  const auto selective = pointsOf(dir / "laz_rgb");
  EXPECT_EQ(selective.size(), 30'000u);
  EXPECT_TRUE(selective == pointsOf(dir / "laz_all"));
}

TEST(ConvertSelective, TheFilterReadsItsAttributesAndTheOutputDropsThem) {
  TempDir dir;
  const PointCloud cloud = makeLasLikeCloud(20'000, 7);
  writePointFile(cloud, dir / "in.las", {.las_point_format = 7});
  writePointFile(cloud, dir / "in.laz", {.las_point_format = 7});
  PointFilter filter;
  filter.keepOnlyClasses({2, 5});
  filter.gps_time = ValueRange{1000.0, 5000.0};
  const auto las =
      convertToPotree({input(dir / "in.las", kColour, filter)}, dir / "las", smallChunks());
  const auto laz =
      convertToPotree({input(dir / "in.laz", kColour, filter)}, dir / "laz", smallChunks());
  expectSameOctree(dir / "las", dir / "laz");
  EXPECT_EQ(openPotree(dir / "laz")->info().attributes,
            (std::vector<std::string>{"x", "y", "z", "red", "green", "blue"}));
  // Classes 2 and 5 of the first 16 001 points (GPS time up to 5000).
  std::uint64_t expected = 0;
  for (std::uint64_t i = 0; i <= 16'000; ++i) expected += (i % 7 == 2 || i % 7 == 5);
  EXPECT_EQ(las.points, expected);
  EXPECT_EQ(laz.points, expected);
}

// The byte offset and size of layer `layer` (0-8 POINT14's, 9 RGB14's) of the first chunk of a
// format-7 LAZ that Parallax wrote (the chunk table's offset first, then the chunk: the first
// record raw, the point count, ten layer sizes, the layers).
std::pair<std::size_t, std::size_t> firstChunkLayer(const std::string& bytes, int layer) {
  std::uint32_t point_data = 0;
  std::memcpy(&point_data, bytes.data() + 96, 4);
  const std::size_t sizes = point_data + 8 + 36 + 4;
  std::size_t at = sizes + 10 * 4;
  std::uint32_t size = 0;
  for (int k = 0; k <= layer; ++k) {
    std::memcpy(&size, bytes.data() + sizes + 4 * std::size_t(k), 4);
    if (k < layer) at += size;
  }
  return {at, size};
}

TEST(ConvertSelective, DamageInALayerNotAskedForChangesNothing) {
  TempDir dir;
  const PointCloud cloud = makeLasLikeCloud(20'000, 7);
  writePointFile(cloud, dir / "in.laz", {.las_point_format = 7});
  std::string bytes = fileBytes(dir / "in.laz");
  const auto [at, size] = firstChunkLayer(bytes, 8);  // GPS time
  ASSERT_GT(size, 100u);
  ASSERT_LT(at + size, bytes.size());
  for (std::size_t i = at; i < at + size; ++i) bytes[i] = char(~bytes[i]);
  std::ofstream(dir / "damaged.laz", std::ios::binary) << bytes;

  // Read whole, the damage is an error naming the layer (so a conversion that decoded that layer
  // would fail).
  try {
    readPointFile(dir / "damaged.laz");
    ADD_FAILURE() << "the damaged GPS time layer went unnoticed";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("GPS time layer"), std::string::npos) << e.what();
  }
  // Positions and colour: that layer is never read.
  convertToPotree({input(dir / "in.laz", kColour)}, dir / "intact", smallChunks());
  convertToPotree({input(dir / "damaged.laz", kColour)}, dir / "damaged", smallChunks());
  expectSameOctree(dir / "intact", dir / "damaged");
}

}  // namespace
}  // namespace parallax::test
