// The in-memory octree build (lod/in_memory_octree.h, the same core as the conversion): every
// point exactly once, a consistent hierarchy, and the sampling property of each inner node.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <set>
#include <sstream>

#include "io/point_file.h"
#include "lod/in_memory_octree.h"
#include "lod/potree_converter.h"
#include "lod/sampler.h"
#include "lod_test_clouds.h"
#include "support/file_bytes.h"
#include "support/temp_dir.h"

namespace parallax::test {
namespace {

OctreeBuildOptions smallNodes(SamplingMethod sampling) {
  OctreeBuildOptions options;
  options.sampling = sampling;
  options.max_node_points = 500;
  return options;
}

double distance(const PointCloud& cloud, std::size_t a, std::size_t b) {
  const double dx = cloud.worldX(a) - cloud.worldX(b), dy = cloud.worldY(a) - cloud.worldY(b),
               dz = cloud.worldZ(a) - cloud.worldZ(b);
  return std::sqrt(dx * dx + dy * dy + dz * dz);
}

class OctreeBuilder : public ::testing::TestWithParam<SamplingMethod> {};

TEST_P(OctreeBuilder, KeepsEveryPointExactlyOnce) {
  const PointCloud cloud = makeSurfaceCloud(20'000);
  const auto octree = buildOctree(cloud, smallNodes(GetParam()));
  EXPECT_EQ(octree->info().point_count, 20'000u);
  EXPECT_EQ(octree->points().count, 20'000u);
  EXPECT_EQ(pointMultiset(octree->points()), pointMultiset(cloud));
  std::uint64_t sum = 0;
  for (const OctreeNode& node : octree->nodes()) sum += node.point_count;
  EXPECT_EQ(sum, 20'000u);
  // loadNode gives the node's own points.
  PointCloud root = octree->loadNode(octree->nodes()[0]);
  EXPECT_EQ(root.count, octree->nodes()[0].point_count);
}

TEST_P(OctreeBuilder, HierarchyIsConsistent) {
  const PointCloud cloud = makeSurfaceCloud(20'000);
  const auto octree = buildOctree(cloud, smallNodes(GetParam()));
  const auto nodes = octree->nodes();
  ASSERT_GT(nodes.size(), 8u);
  EXPECT_EQ(nodes[0].name, "r");
  EXPECT_EQ(nodes[0].parent, -1);
  std::uint64_t next_record = 0;
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    const OctreeNode& node = nodes[i];
    EXPECT_EQ(node.byte_offset, next_record) << node.name;  // contiguous, in node order
    EXPECT_EQ(node.byte_size, node.point_count) << node.name;
    next_record += node.byte_size;
    EXPECT_DOUBLE_EQ(node.spacing, octree->info().spacing / double(1 << node.level));
    EXPECT_EQ(int(node.name.size()) - 1, node.level);
    for (int c = 0; c < 8; ++c) {
      const bool has = node.child_mask & (1 << c);
      EXPECT_EQ(has, node.children[std::size_t(c)] >= 0) << node.name << " child " << c;
      if (!has) continue;
      const OctreeNode& child = nodes[std::size_t(node.children[std::size_t(c)])];
      EXPECT_EQ(child.name, node.name + char('0' + c));
      EXPECT_EQ(child.parent, std::int32_t(i));
    }
    // A node without children holds points: empty leaves are removed.
    // Leaves hold at most max_node_points (no point here is duplicated).
    if (node.child_mask == 0) {
      EXPECT_GT(node.point_count, 0u) << node.name;
      EXPECT_LE(node.point_count, 500u) << node.name;
    }
    // Every point lies in its node's box.
    const PointCloud points = octree->loadNode(node);
    for (std::uint64_t p = 0; p < points.count; ++p) {
      const double world[3] = {points.worldX(p), points.worldY(p), points.worldZ(p)};
      for (int axis = 0; axis < 3; ++axis) {
        EXPECT_GE(world[axis], node.box.min[axis] - 1e-9) << node.name;
        EXPECT_LE(world[axis], node.box.max[axis] + 1e-9) << node.name;
      }
    }
  }
  EXPECT_EQ(next_record, 20'000u);
}

INSTANTIATE_TEST_SUITE_P(Samplers, OctreeBuilder,
                         ::testing::Values(SamplingMethod::Poisson, SamplingMethod::Random),
                         [](const auto& param_info) {
                           return std::string(samplingMethodName(param_info.param));
                         });

TEST(OctreeBuilderPoisson, InnerNodesKeepTheirSpacing) {
  const PointCloud cloud = makeSurfaceCloud(20'000);
  const auto octree = buildOctree(cloud, smallNodes(SamplingMethod::Poisson));
  int inner = 0;
  for (const OctreeNode& node : octree->nodes()) {
    if (node.child_mask == 0) continue;
    ++inner;
    const PointCloud points = octree->loadNode(node);
    for (std::size_t a = 0; a < points.count; ++a) {
      for (std::size_t b = a + 1; b < points.count; ++b) {
        ASSERT_GE(distance(points, a, b), node.spacing) << node.name;
      }
    }
  }
  EXPECT_GT(inner, 1);
}

TEST(OctreeBuilderRandom, InnerNodesHoldOnePointPerSpacingCell) {
  const PointCloud cloud = makeSurfaceCloud(20'000);
  const auto octree = buildOctree(cloud, smallNodes(SamplingMethod::Random));
  int inner = 0;
  for (const OctreeNode& node : octree->nodes()) {
    if (node.child_mask == 0) continue;
    ++inner;
    const PointCloud points = octree->loadNode(node);
    EXPECT_GT(points.count, 0u) << node.name << ": an inner node holds a sample";
    std::set<std::tuple<int, int, int>> cells;
    for (std::size_t p = 0; p < points.count; ++p) {
      // Cells of the node's edge / 128 (= its spacing), computed as the sampler does.
      auto cell = [&](int axis, double world) {
        const double edge = node.box.max[axis] - node.box.min[axis];
        return std::clamp(int((world - node.box.min[axis]) * (128.0 / edge)), 0, 127);
      };
      EXPECT_TRUE(cells
                      .insert({cell(0, points.worldX(p)), cell(1, points.worldY(p)),
                               cell(2, points.worldZ(p))})
                      .second)
          << node.name;
    }
  }
  EXPECT_GT(inner, 1);  // the root and more: the property above was checked somewhere
}

TEST(OctreeBuilderEdges, CoincidentPointsEndInOneDeepLeaf) {
  PointCloud cloud = makeSurfaceCloud(3000);
  for (std::uint64_t i = 0; i < 2000; ++i) cloud.positions[i] = cloud.positions[0];
  cloud.computeBounds();
  const auto octree = buildOctree(cloud, smallNodes(SamplingMethod::Poisson));
  EXPECT_EQ(pointMultiset(octree->points()), pointMultiset(cloud));
}

TEST(OctreeBuilderEdges, EmptyAndSinglePointClouds) {
  const auto empty = buildOctree(PointCloud{}, {});
  ASSERT_EQ(empty->nodes().size(), 1u);
  EXPECT_EQ(empty->nodes()[0].point_count, 0u);
  const PointCloud one = makeSurfaceCloud(1);
  const auto single = buildOctree(one, {});
  ASSERT_EQ(single->nodes().size(), 1u);
  EXPECT_EQ(single->nodes()[0].point_count, 1u);
  EXPECT_EQ(single->info().cube.max[0] - single->info().cube.min[0], 1.0);
}

// The conversion builds several chunks at once and writes them in chunk order: the files must
// not depend on how many threads ran, nor on how many chunks the budget let run together.
class ConvertDeterminism : public ::testing::TestWithParam<SamplingMethod> {};

TEST_P(ConvertDeterminism, SameBytesWhateverTheThreadsAndChunksInFlight) {
  TempDir dir;
  PointCloud cloud = makeSurfaceCloud(30'000);
  addDenseCluster(cloud);
  writePointFile(cloud, dir / "in.ply");
  struct Run {
    const char* name;
    int threads;
    std::uint64_t memory_bytes;  // 1 MB: one or two chunks in flight; 2 GB: all of them
  };
  const Run runs[] = {{"one_thread", 1, 2048ull << 20},
                      {"four_threads", 4, 2048ull << 20},
                      {"four_threads_small_budget", 4, 1u << 20},
                      {"default_threads", 0, 2048ull << 20}};
  std::string reference_octree, reference_hierarchy;
  for (const Run& run : runs) {
    PotreeConvertOptions options;
    options.build.sampling = GetParam();
    options.build.max_node_points = 300;
    options.build.max_chunk_points = 1500;
    options.build.threads = run.threads;
    options.build.memory_bytes = run.memory_bytes;
    const auto out = dir / run.name;
    const PotreeConvertResult result = convertToPotree({{dir / "in.ply", {}}}, out, options);
    EXPECT_EQ(result.points, 30'000u);
    EXPECT_GT(result.chunks, 8u) << run.name;
    const std::string octree = fileBytes(out / "octree.bin");
    const std::string hierarchy = fileBytes(out / "hierarchy.bin");
    EXPECT_EQ(octree.size(), 30'000u * PotreeLayout::fromCloud(cloud).recordSize());
    if (reference_octree.empty()) {
      reference_octree = octree;
      reference_hierarchy = hierarchy;
      continue;
    }
    EXPECT_TRUE(octree == reference_octree) << run.name;
    EXPECT_TRUE(hierarchy == reference_hierarchy) << run.name;
  }
}

INSTANTIATE_TEST_SUITE_P(Samplers, ConvertDeterminism,
                         ::testing::Values(SamplingMethod::Poisson, SamplingMethod::Random),
                         [](const auto& param_info) {
                           return param_info.param == SamplingMethod::Poisson ? "poisson"
                                                                              : "random";
                         });

}  // namespace
}  // namespace parallax::test
