// The COPC writer: an octree written as COPC reads back as the same tree (nodes, boxes, counts,
// each node's points in order), a plain LAZ reader reads it front to back, and COPC and Potree
// re-encode into each other node by node without changing the tree.
#include "lod/copc_writer.h"

#include <gtest/gtest.h>

#include <cstring>
#include <map>

#include "io/las_header.h"
#include "io/laz_reader.h"
#include "lod/copc_reader.h"
#include "lod/copc_test_files.h"
#include "lod/in_memory_octree.h"
#include "lod/lod_test_clouds.h"
#include "lod/octree_node_batches.h"
#include "lod/potree_octree_writer.h"
#include "lod/potree_reader.h"
#include "support/temp_dir.h"

namespace parallax {
namespace {

using test::pointMultiset;

// A deep tree: small nodes and a dense cluster (several hierarchy pages at 2 levels a page).
std::unique_ptr<InMemoryOctree> deepOctree() {
  PointCloud cloud = test::makeSurfaceCloud(20000, 3);
  test::addDenseCluster(cloud);
  OctreeBuildOptions options;
  options.max_node_points = 400;
  return buildOctree(cloud, options);
}

// Same nodes (names, levels, counts, masks, boxes, spacing) and same points node by node.
void expectSameTree(Octree& expected, Octree& actual) {
  expandWholeOctree(expected);
  expandWholeOctree(actual);
  ASSERT_EQ(expected.nodes().size(), actual.nodes().size());
  EXPECT_EQ(expected.info().point_count, actual.info().point_count);
  // COPC stores the cube as center +- halfsize: the corners come back to within rounding.
  for (int axis = 0; axis < 3; ++axis) {
    EXPECT_NEAR(expected.info().cube.min[axis], actual.info().cube.min[axis], 1e-9);
    EXPECT_NEAR(expected.info().cube.max[axis], actual.info().cube.max[axis], 1e-9);
  }
  EXPECT_EQ(expected.info().spacing, actual.info().spacing);
  std::map<std::string, const OctreeNode*> by_name;
  for (const OctreeNode& node : actual.nodes()) by_name[node.name] = &node;
  for (const OctreeNode& e : expected.nodes()) {
    ASSERT_TRUE(by_name.count(e.name)) << e.name;
    const OctreeNode& a = *by_name[e.name];
    EXPECT_EQ(a.level, e.level) << e.name;
    EXPECT_EQ(a.point_count, e.point_count) << e.name;
    EXPECT_EQ(a.child_mask, e.child_mask) << e.name;
    EXPECT_EQ(a.spacing, e.spacing) << e.name;
    for (int axis = 0; axis < 3; ++axis) {
      EXPECT_NEAR(a.box.min[axis], e.box.min[axis], 1e-9) << e.name;
      EXPECT_NEAR(a.box.max[axis], e.box.max[axis], 1e-9) << e.name;
    }
    const PointCloud pe = expected.loadNode(e);
    const PointCloud pa = actual.loadNode(a);
    ASSERT_EQ(pa.count, pe.count) << e.name;
    for (std::size_t i = 0; i < pe.count; ++i) {
      ASSERT_EQ(pa.worldX(i), pe.worldX(i)) << e.name << " point " << i;
      ASSERT_EQ(pa.worldY(i), pe.worldY(i)) << e.name << " point " << i;
      ASSERT_EQ(pa.worldZ(i), pe.worldZ(i)) << e.name << " point " << i;
      ASSERT_EQ(pa.colors[i], pe.colors[i]) << e.name << " point " << i;
      ASSERT_EQ(pa.intensity[i], pe.intensity[i]) << e.name << " point " << i;
    }
    const ScalarColumn* qe = pe.findScalar("quality");
    const ScalarColumn* qa = pa.findScalar("quality");
    ASSERT_TRUE(qe && qa) << e.name;
    if (pe.count > 0) {  // (an empty node's columns have no storage: memcmp of null)
      EXPECT_EQ(std::memcmp(qe->data.data(), qa->data.data(), pe.count * 4), 0) << e.name;
    }
  }
}

TEST(CopcWriter, AnOctreeReadsBackNodeByNode) {
  const test::TempDir dir;
  auto source = deepOctree();
  CopcWriteOptions options;
  options.page_levels = 2;
  options.batch_points = 3000;  // several batches
  const CopcWriteResult result = writeCopc(*source, dir / "deep.copc.laz", options);
  EXPECT_EQ(result.points, 20000u);
  EXPECT_EQ(result.nodes, source->nodes().size());
  EXPECT_EQ(result.point_format, 7);  // colour
  EXPECT_GT(result.pages, 3u);
  ASSERT_TRUE(isCopcFile(dir / "deep.copc.laz"));
  auto copc = openCopc(dir / "deep.copc.laz");
  // Only the root page is read at first: deeper nodes wait, as Potree's proxies do.
  std::size_t pending = 0;
  for (const OctreeNode& node : copc->nodes()) pending += node.hierarchy_pending ? 1 : 0;
  EXPECT_GT(pending, 0u);
  expectSameTree(*source, *copc);
  EXPECT_EQ(copcDetails(*copc)->pages_read, result.pages);
}

TEST(CopcWriter, APlainLazReaderReadsTheFileFrontToBack) {
  const test::TempDir dir;
  auto source = deepOctree();
  writeCopc(*source, dir / "deep.copc.laz", {.page_levels = 2});
  const LasHeader header = readLasHeader(dir / "deep.copc.laz");
  EXPECT_EQ(header.versionString(), "1.4");
  EXPECT_EQ(header.point_format, 7);
  EXPECT_EQ(header.point_count, 20000u);
  EXPECT_EQ(header.global_encoding & 16, 16);  // WKT, as COPC requires
  ASSERT_TRUE(header.laszip);
  EXPECT_EQ(header.laszip->compressor, 3);
  EXPECT_EQ(header.laszip->chunk_size, laz::kVariableChunkSize);
  const LazSummary laz = summarizeLaz(dir / "deep.copc.laz");
  std::size_t with_points = 0;
  for (const OctreeNode& node : source->nodes()) with_points += node.point_count > 0 ? 1 : 0;
  EXPECT_EQ(laz.chunks, with_points);  // one chunk per node with points
  EXPECT_TRUE(laz.table_note.empty()) << laz.table_note;
  const PointCloud all = readLaz(dir / "deep.copc.laz");
  PointCloud expected = source->points().clone();
  ASSERT_EQ(all.count, expected.count);
  // Same points (positions, colours, intensity, quality); normals are extra bytes in LAS.
  expected.normals = {};
  PointCloud read = all.clone();
  read.normals = {};
  auto keep = [](PointCloud& cloud) {
    std::erase_if(cloud.scalars, [](const ScalarColumn& c) { return c.name != "quality"; });
    cloud.classification = {};
  };
  keep(expected);
  keep(read);
  EXPECT_EQ(pointMultiset(read), pointMultiset(expected));
  // The header's bounds are the points' own.
  EXPECT_EQ(header.bounds.min, all.bounds.min);
  EXPECT_EQ(header.bounds.max, all.bounds.max);
}

TEST(CopcWriter, CopcAndPotreeReencodeIntoEachOtherWithoutChangingTheTree) {
  const test::TempDir dir;
  auto source = deepOctree();
  writeCopc(*source, dir / "a.copc.laz", {.page_levels = 2});
  auto copc = openCopc(dir / "a.copc.laz");
  const PotreeWriteResult potree = writePotree(*copc, dir / "potree");
  EXPECT_EQ(potree.points, 20000u);
  auto from_copc = openPotree(dir / "potree");
  expectSameTree(*source, *from_copc);
  // And back: the same COPC file, byte for byte, but for the creation date and the cube's center
  // and halfsize, which may move by a rounding step (center +- halfsize -> corners -> back).
  writeCopc(*from_copc, dir / "b.copc.laz", {.page_levels = 2});
  auto bytes = [&](const char* name) {
    std::vector<std::byte> b = test::readBytes(dir / name);
    std::fill_n(b.begin() + 90, 4, std::byte{0});
    std::fill_n(b.begin() + kCopcInfoPayloadOffset, 32, std::byte{0});
    return b;
  };
  EXPECT_EQ(bytes("a.copc.laz"), bytes("b.copc.laz"));
}

TEST(CopcWriter, AnEmptyOctreeIsARootWithoutPoints) {
  const test::TempDir dir;
  PointCloud empty;
  empty.quantization.scale = {0.01, 0.01, 0.01};
  auto source = buildOctree(empty);
  ASSERT_FALSE(copcLayoutProblem(source->info()));
  const CopcWriteResult result = writeCopc(*source, dir / "empty.copc.laz");
  EXPECT_EQ(result.points, 0u);
  auto copc = openCopc(dir / "empty.copc.laz");
  EXPECT_EQ(copc->info().point_count, 0u);
  EXPECT_EQ(copc->loadNode(copc->nodes()[0]).count, 0u);
}

TEST(CopcWriter, RefusesARootBoxThatIsNoCube) {
  OctreeInfo info;
  info.cube.min = {0, 0, 0};
  info.cube.max = {2, 1, 1};
  info.spacing = 0.1;
  ASSERT_TRUE(copcLayoutProblem(info));
  EXPECT_NE(copcLayoutProblem(info)->find("not a cube"), std::string::npos);
  info.cube.max = {1, 1, 1};
  EXPECT_FALSE(copcLayoutProblem(info));
  info.spacing = 0.0;
  EXPECT_TRUE(copcLayoutProblem(info));
}

}  // namespace
}  // namespace parallax
