// The COPC reader on the two real COPC files of PARALLAX_TEST_DATA/laz (written by PDAL / untwine and
// copc.js's authors, not by Parallax): every node read, keys and boxes, and every point of every
// node equal to what the plain LAZ reader gives for the same point of the file.
#include "lod/copc_reader.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <iterator>
#include <map>

#include "core/error.h"
#include "io/laz_reader.h"
#include "lod/copc_format.h"
#include "lod/copc_test_files.h"
#include "lod/octree_export.h"

namespace parallax {
namespace {

using test::copcData;
using test::errorOf;
using test::expectContains;
using test::readBytes;

void expandAll(Octree& octree) {
  for (std::size_t i = 0; i < octree.nodes().size(); ++i) {
    if (octree.nodes()[i].hierarchy_pending) octree.expandHierarchy(std::int32_t(i));
  }
}

// Every node's points against the plain LAZ reader's points of the same chunk: the chunks lie in
// the file in offset order, so a node's first point in the file is the sum of the points of the
// nodes whose chunks come before it.
void expectNodesEqualPlainReader(const std::filesystem::path& path, std::size_t expected_nodes,
                                 std::uint64_t expected_points) {
  auto octree = openCopc(path);
  expandAll(*octree);
  const auto nodes = octree->nodes();
  ASSERT_EQ(nodes.size(), expected_nodes);
  EXPECT_EQ(octree->info().point_count, expected_points);
  const PointCloud all = readLaz(path);
  ASSERT_EQ(all.count, expected_points);

  std::map<std::uint64_t, std::size_t> by_offset;
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    if (nodes[i].point_count > 0) by_offset[nodes[i].byte_offset] = i;
  }
  std::uint64_t first = 0, total = 0;
  for (const auto& [offset, index] : by_offset) {
    const OctreeNode& node = nodes[index];
    const PointCloud points = octree->loadNode(node);
    ASSERT_EQ(points.count, node.point_count) << node.name;
    EXPECT_EQ(points.quantization.scale, all.quantization.scale);
    EXPECT_EQ(points.quantization.offset, all.quantization.offset);
    for (std::size_t i = 0; i < points.count; ++i) {
      const std::size_t j = std::size_t(first + i);
      ASSERT_EQ(points.positions[i], all.positions[j]) << node.name << " point " << i;
      ASSERT_EQ(points.colors[i], all.colors[j]) << node.name << " point " << i;
      ASSERT_EQ(points.intensity[i], all.intensity[j]) << node.name << " point " << i;
      ASSERT_EQ(points.classification[i], all.classification[j]) << node.name << " point " << i;
      // Inside its node's cube (the writer's promise; a wrong key mapping breaks it).
      for (int axis = 0; axis < 3; ++axis) {
        const double v = points.quantization.toWorld(axis, (&points.positions[i].x)[axis]);
        ASSERT_GE(v, node.box.min[axis] - 0.01) << node.name;
        ASSERT_LE(v, node.box.max[axis] + 0.01) << node.name;
      }
    }
    ASSERT_EQ(points.scalars.size(), all.scalars.size());
    for (std::size_t s = 0; s < points.scalars.size(); ++s) {
      const std::size_t size = scalarSize(points.scalars[s].type);
      EXPECT_EQ(std::memcmp(points.scalars[s].data.data(),
                            all.scalars[s].data.data() + first * size, points.count * size),
                0)
          << node.name << " " << points.scalars[s].name;
    }
    first += node.point_count;
    total += points.count;
  }
  EXPECT_EQ(total, expected_points);
}

TEST(CopcReader, DetectsCopcByContent) {
  EXPECT_TRUE(isCopcFile(copcData("simple.copc.laz")));
  EXPECT_TRUE(isCopcFile(copcData("ellipsoid.copc.laz")));
  EXPECT_FALSE(isCopcFile(copcData("ellipsoid.laz")));
  EXPECT_FALSE(isCopcFile(copcData("point10.las")));
  EXPECT_FALSE(isCopcFile(copcData("simple.copc.laz").parent_path() / "no such file.copc.laz"));
  EXPECT_FALSE(isCopcFile(copcData("simple.copc.laz").parent_path()));
}

TEST(CopcReader, SimpleFileEveryNodeEqualsThePlainLazReader) {
  expectNodesEqualPlainReader(copcData("simple.copc.laz"), 65, 1065);
}

TEST(CopcReader, EllipsoidFileEveryNodeEqualsThePlainLazReader) {
  expectNodesEqualPlainReader(copcData("ellipsoid.copc.laz"), 5, 100000);
}

// A query of the whole octree (what `convert URL -o FILE.las` and Python's query() read) is the
// file's points in file order, the colours as stored included: simple.copc.laz keeps 8-bit
// values in its 16-bit fields, which a LAS output must write back as they are.
TEST(CopcReader, AWholeQueryKeepsTheStoredColours) {
  const PointCloud all = readLaz(copcData("simple.copc.laz"));
  const OctreePoints read = readOctreePoints(copcData("simple.copc.laz").string(), {});
  ASSERT_EQ(read.cloud.count, all.count);
  ASSERT_EQ(all.stored_colors.size(), all.count);
  ASSERT_EQ(read.cloud.stored_colors.size(), all.count);
  for (std::size_t i = 0; i < all.count; ++i) {
    ASSERT_EQ(read.cloud.positions[i], all.positions[i]) << "point " << i;
    ASSERT_EQ(read.cloud.stored_colors[i], all.stored_colors[i]) << "point " << i;
  }
  EXPECT_EQ(all.stored_colors[0], (Rgb16{100, 94, 122}));
}

TEST(CopcReader, KeysBecomePotreeNamesAndCubes) {
  auto octree = openCopc(copcData("ellipsoid.copc.laz"));
  const OctreeInfo& info = octree->info();
  // The info VLR: center (-8242596, 4966656, 100), halfsize 150, spacing 2.34375.
  EXPECT_EQ(info.cube.min, (std::array<double, 3>{-8242746.0, 4966506.0, -50.0}));
  EXPECT_EQ(info.cube.max, (std::array<double, 3>{-8242446.0, 4966806.0, 250.0}));
  EXPECT_EQ(info.spacing, 2.34375);
  EXPECT_EQ(info.bounds.min, (std::array<double, 3>{-8242746.0, 4966506.0, -50.0}));
  EXPECT_EQ(info.bounds.max, (std::array<double, 3>{-8242446.0, 4966706.0, 50.0}));
  const auto nodes = octree->nodes();
  ASSERT_EQ(nodes.size(), 5u);
  // Keys 1-0-0-0, 1-1-0-0, 1-0-1-0, 1-1-1-0: child digits 0, 4 (+x), 2 (+y), 6.
  EXPECT_EQ(nodes[0].name, "r");
  EXPECT_EQ(nodes[0].point_count, 66272u);
  EXPECT_EQ(nodes[0].child_mask, (1 << 0) | (1 << 4) | (1 << 2) | (1 << 6));
  const OctreeNode& plus_x = nodes[std::size_t(nodes[0].children[4])];
  EXPECT_EQ(plus_x.name, "r4");
  EXPECT_EQ(plus_x.level, 1);
  EXPECT_EQ(plus_x.point_count, 12347u);
  EXPECT_EQ(plus_x.spacing, 2.34375 / 2);
  EXPECT_EQ(plus_x.box.min, (std::array<double, 3>{-8242596.0, 4966506.0, -50.0}));
  EXPECT_EQ(plus_x.box.max, (std::array<double, 3>{-8242446.0, 4966656.0, 100.0}));
  EXPECT_EQ(nodes[std::size_t(nodes[0].children[6])].point_count, 4689u);
  EXPECT_EQ(octree->info().attributes.front(), "x");
  EXPECT_TRUE(octree->info().has_colors);
  const auto details = copcDetails(*octree);
  ASSERT_TRUE(details);
  EXPECT_EQ(details->chunks, 5u);
  EXPECT_EQ(details->pages_read, 1u);
  EXPECT_EQ(details->info.gps_time_min, 42.0);
  EXPECT_EQ(details->info.root_hierarchy_offset, 630580u);
}

TEST(CopcFormat, KeysAndNamesBothWays) {
  const CopcKey key{3, 5, 2, 7};  // x 101, y 010, z 111: digits 4+0+1, 0+2+1, 4+0+1
  EXPECT_EQ(copcNodeName(key), "r535");
  EXPECT_EQ(copcKeyOfName("r535"), key);
  EXPECT_EQ(copcKeyOfName("r"), (CopcKey{0, 0, 0, 0}));
  EXPECT_FALSE(copcKeyOfName("r8"));
  EXPECT_FALSE(copcKeyOfName("x1"));
  EXPECT_TRUE(key.valid());
  EXPECT_FALSE((CopcKey{3, 8, 0, 0}).valid());
  EXPECT_FALSE((CopcKey{-1, 0, 0, 0}).valid());
  EXPECT_FALSE((CopcKey{31, 0, 0, 0}).valid());
  EXPECT_TRUE(key.within(CopcKey{1, 1, 0, 1}));
  EXPECT_FALSE(key.within(CopcKey{1, 0, 0, 1}));
  EXPECT_EQ(key.parent(), (CopcKey{2, 2, 1, 3}));
  EXPECT_EQ(key.parent().child(key.digit()), key);
}

}  // namespace
}  // namespace parallax
