// Damaged COPC files: every lie of the hierarchy is an InputError that names the file, the page,
// the entry (index and key) and the byte offset; never a crash, a loop or wrong points.
#include <gtest/gtest.h>

#include <cstring>

#include "core/error.h"
#include "lod/copc_format.h"
#include "lod/copc_reader.h"
#include "lod/copc_test_files.h"
#include "lod/copc_writer.h"
#include "lod/in_memory_octree.h"
#include "lod/lod_test_clouds.h"
#include "lod/octree_node_batches.h"
#include "support/temp_dir.h"

namespace parallax {
namespace {

using test::errorOf;
using test::expectContains;
using test::loadAt;
using test::storeAt;

// A small COPC file written by Parallax with pages of two levels (child pages several deep).
struct CopcBytes {
  std::vector<std::byte> bytes;
  CopcInfo info;
  std::vector<CopcEntry> root;  // the root page's entries

  std::size_t find(std::int32_t point_count_sign) const {  // -1: a child page; 1: points
    for (std::size_t i = 0; i < root.size(); ++i) {
      if ((root[i].point_count == -1) == (point_count_sign < 0) && root[i].key.level > 0) return i;
    }
    ADD_FAILURE() << "no such entry in the root page";
    return 0;
  }
  std::size_t entryOffset(std::size_t i) const {
    return std::size_t(info.root_hierarchy_offset) + i * kCopcEntrySize;
  }
};

CopcBytes smallCopc() {
  static const std::vector<std::byte> bytes = [] {
    PointCloud cloud = test::makeSurfaceCloud(6000, 7);
    test::addDenseCluster(cloud);
    OctreeBuildOptions options;
    options.max_node_points = 300;
    auto octree = buildOctree(cloud, options);
    const test::TempDir dir;
    writeCopc(*octree, dir / "small.copc.laz", {.page_levels = 2});
    return test::readBytes(dir / "small.copc.laz");
  }();
  CopcBytes out;
  out.bytes = bytes;
  out.info = parseCopcInfo(std::span<const std::byte, kCopcInfoSize>(
      bytes.data() + kCopcInfoPayloadOffset, kCopcInfoSize));
  out.root = parseCopcPage(std::span(bytes).subspan(std::size_t(out.info.root_hierarchy_offset),
                                                    std::size_t(out.info.root_hierarchy_size)));
  return out;
}

// Opens, reads every page and loads every node: the first InputError's message.
std::string openAll(std::vector<std::byte> bytes) {
  return errorOf([&] {
    auto octree = openCopcFromMemory(std::move(bytes), "cloud.copc.laz");
    expandWholeOctree(*octree);
    for (const OctreeNode& node : octree->nodes()) octree->loadNode(node);
  });
}

TEST(CopcErrors, TheUndamagedFileReadsWhole) {
  const CopcBytes c = smallCopc();
  auto octree = openCopcFromMemory(c.bytes, "cloud.copc.laz");
  expandWholeOctree(*octree);
  std::uint64_t points = 0;
  for (const OctreeNode& node : octree->nodes()) points += octree->loadNode(node).count;
  EXPECT_EQ(points, 6000u);
  EXPECT_GT(copcDetails(*octree)->pages_read, 2u);
}

TEST(CopcErrors, RootPageOutsideTheFile) {
  CopcBytes c = smallCopc();
  storeAt<std::uint64_t>(c.bytes, kCopcInfoPayloadOffset + 40, c.bytes.size() - 16);
  expectContains(openAll(c.bytes),
                 {"cloud.copc.laz", "byte offset 469", "root hierarchy page", "inside the file"});
}

TEST(CopcErrors, ChildPageOutsideTheFile) {
  CopcBytes c = smallCopc();
  const std::size_t i = c.find(-1);
  storeAt<std::uint64_t>(c.bytes, c.entryOffset(i) + 16, c.bytes.size() + 64);
  expectContains(
      openAll(c.bytes),
      {"cloud.copc.laz", "byte offset " + std::to_string(c.entryOffset(i) + 16),
       "hierarchy page at byte " + std::to_string(c.info.root_hierarchy_offset) + " (of node r)",
       "entry " + std::to_string(i) + " (key " + c.root[i].key.text() + ")", "inside the file"});
}

TEST(CopcErrors, ChildPagePointingBackAtTheRootPageIsALoop) {
  CopcBytes c = smallCopc();
  const std::size_t i = c.find(-1);
  storeAt<std::uint64_t>(c.bytes, c.entryOffset(i) + 16, c.info.root_hierarchy_offset);
  storeAt<std::int32_t>(c.bytes, c.entryOffset(i) + 24, std::int32_t(c.info.root_hierarchy_size));
  expectContains(openAll(c.bytes), {"entry " + std::to_string(i), "a loop"});
}

TEST(CopcErrors, OverlappingPages) {
  CopcBytes c = smallCopc();
  const std::size_t i = c.find(-1);
  // Into the root page's second entry: neither the same page nor a separate one.
  storeAt<std::uint64_t>(c.bytes, c.entryOffset(i) + 16, c.info.root_hierarchy_offset + 32);
  expectContains(openAll(c.bytes), {"entry " + std::to_string(i), "overlapping the page"});
}

TEST(CopcErrors, PageNotOfWholeEntries) {
  CopcBytes c = smallCopc();
  const std::size_t i = c.find(-1);
  storeAt<std::int32_t>(c.bytes, c.entryOffset(i) + 24, c.root[i].byte_size - 5);
  expectContains(openAll(c.bytes), {"entry " + std::to_string(i), "whole 32-byte entries"});
}

TEST(CopcErrors, PageIntoThePointData) {
  CopcBytes c = smallCopc();
  const std::size_t i = c.find(-1);
  storeAt<std::uint64_t>(c.bytes, c.entryOffset(i) + 16, 4096);
  expectContains(openAll(c.bytes), {"entry " + std::to_string(i), "outside the point data"});
}

TEST(CopcErrors, EntriesThatContradictTheChunkTable) {
  CopcBytes c = smallCopc();
  const std::size_t i = c.find(1);
  {
    std::vector<std::byte> bytes = c.bytes;
    storeAt<std::int32_t>(bytes, c.entryOffset(i) + 24, c.root[i].byte_size + 1);
    expectContains(openAll(bytes), {"byte offset " + std::to_string(c.entryOffset(i) + 24),
                                    "entry " + std::to_string(i), "chunk table",
                                    std::to_string(c.root[i].byte_size + 1) + " bytes"});
  }
  {
    std::vector<std::byte> bytes = c.bytes;
    storeAt<std::int32_t>(bytes, c.entryOffset(i) + 28, c.root[i].point_count - 1);
    expectContains(openAll(bytes), {"entry " + std::to_string(i), "chunk table",
                                    std::to_string(c.root[i].point_count - 1) + " points"});
  }
  {
    std::vector<std::byte> bytes = c.bytes;
    storeAt<std::uint64_t>(bytes, c.entryOffset(i) + 16, c.root[i].offset + 1);
    expectContains(openAll(bytes), {"entry " + std::to_string(i), "where no chunk starts"});
  }
  {  // Two nodes claiming one chunk.
    std::vector<std::byte> bytes = c.bytes;
    const std::size_t root = 0;
    ASSERT_EQ(c.root[root].key, (CopcKey{0, 0, 0, 0}));
    for (int field : {16, 24, 28}) {
      std::memcpy(bytes.data() + c.entryOffset(i) + std::size_t(field),
                  bytes.data() + c.entryOffset(root) + std::size_t(field), field == 16 ? 8 : 4);
    }
    expectContains(openAll(bytes), {"entry " + std::to_string(i), "already another node's"});
  }
}

TEST(CopcErrors, KeysOutOfRangeOrOutOfPlace) {
  CopcBytes c = smallCopc();
  const std::size_t i = c.find(1);
  const CopcKey key = c.root[i].key;
  {
    std::vector<std::byte> bytes = c.bytes;
    storeAt<std::int32_t>(bytes, c.entryOffset(i) + 4, std::int32_t(1) << key.level);
    expectContains(openAll(bytes),
                   {"byte offset " + std::to_string(c.entryOffset(i)), "entry " + std::to_string(i),
                    "x, y and z in 0 .. 2^level - 1"});
  }
  {
    std::vector<std::byte> bytes = c.bytes;
    storeAt<std::int32_t>(bytes, c.entryOffset(i), -3);
    expectContains(openAll(bytes), {"entry " + std::to_string(i), "key -3-"});
  }
  {  // A key twice in the page.
    std::vector<std::byte> bytes = c.bytes;
    const std::size_t j = c.find(-1);
    std::memcpy(bytes.data() + c.entryOffset(j), bytes.data() + c.entryOffset(i), 16);
    expectContains(openAll(bytes), {"each key once in a page"});
  }
  {  // A node moved two levels down: it has no parent, nor have its children any more.
    std::vector<std::byte> bytes = c.bytes;
    const CopcKey orphan = key.child(0).child(0);
    storeAt<std::int32_t>(bytes, c.entryOffset(i), orphan.level);
    storeAt<std::int32_t>(bytes, c.entryOffset(i) + 4, orphan.x);
    storeAt<std::int32_t>(bytes, c.entryOffset(i) + 8, orphan.y);
    storeAt<std::int32_t>(bytes, c.entryOffset(i) + 12, orphan.z);
    expectContains(openAll(bytes),
                   {"hierarchy page at byte", "the parent's entry", "a node without a parent"});
  }
}

TEST(CopcErrors, AChildPageWithAKeyOutsideItsSubtree) {
  CopcBytes c = smallCopc();
  const std::size_t i = c.find(-1);
  const std::size_t page = std::size_t(c.root[i].offset);
  // The child page's first entry becomes the root's key.
  for (int field = 0; field < 4; ++field) storeAt<std::int32_t>(c.bytes, page + 4 * field, 0);
  auto octree = openCopcFromMemory(c.bytes, "cloud.copc.laz");
  std::int32_t pending = -1;
  for (std::size_t n = 0; n < octree->nodes().size(); ++n) {
    if (octree->nodes()[n].name == copcNodeName(c.root[i].key)) pending = std::int32_t(n);
  }
  ASSERT_GE(pending, 0);
  EXPECT_TRUE(octree->nodes()[std::size_t(pending)].hierarchy_pending);
  expectContains(errorOf([&] { octree->expandHierarchy(pending); }),
                 {"hierarchy page at byte " + std::to_string(page) + " (of node " +
                      copcNodeName(c.root[i].key) + ")",
                  "entry 0 (key 0-0-0-0)", "at or below the page's node"});
  // Its points cannot be loaded either while it is pending: its page does not hold its entry
  // any more... or does, elsewhere; either way never points of another node.
  const std::string load =
      errorOf([&] { octree->loadNode(octree->nodes()[std::size_t(pending)]); });
  expectContains(load, {"cloud.copc.laz"});
}

TEST(CopcErrors, NodeCountsThatDoNotAddUpToTheHeader) {
  CopcBytes c = smallCopc();
  const std::size_t i = c.find(1);
  // A node said to hold no points: its chunk is left over, the counts fall short.
  storeAt<std::int32_t>(c.bytes, c.entryOffset(i) + 24, 0);
  storeAt<std::int32_t>(c.bytes, c.entryOffset(i) + 28, 0);
  expectContains(openAll(c.bytes), {"COPC hierarchy", "nodes holding the header's 6000 points"});
}

TEST(CopcErrors, AChunkWhoseOwnCountDisagrees) {
  CopcBytes c = smallCopc();
  const std::size_t i = c.find(1);
  // A layered chunk: the first record raw (48 bytes here), then its point count.
  const std::size_t record = loadAt<std::uint16_t>(c.bytes, 105);
  const std::size_t at = std::size_t(c.root[i].offset) + record;
  storeAt<std::uint32_t>(c.bytes, at, loadAt<std::uint32_t>(c.bytes, at) + 1);
  expectContains(openAll(c.bytes),
                 {"cloud.copc.laz", "byte offset " + std::to_string(c.root[i].offset),
                  "node " + copcNodeName(c.root[i].key) + " (its LAZ chunk)", "does not decode"});
}

TEST(CopcErrors, NotACopcFileOrCutShort) {
  expectContains(errorOf([] { openCopc(test::copcData("ellipsoid.laz")); }),
                 {"ellipsoid.laz", "first VLR", "COPC info VLR"});
  const CopcBytes c = smallCopc();
  for (std::size_t size :
       {std::size_t(100), std::size_t(600), c.bytes.size() / 2, c.bytes.size() - 40}) {
    std::vector<std::byte> cut(c.bytes.begin(), c.bytes.begin() + std::ptrdiff_t(size));
    expectContains(openAll(cut), {"cloud.copc.laz"});
  }
}

}  // namespace
}  // namespace parallax
