// The GPU node cache: stays under its byte budget, evicts the least recently used node first
// (the deepest among equals), never a node used in the current frame.
#include "render/gpu_node_cache.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>

#include "render_test_support.h"

namespace parallax {
namespace {

void ensureContext() {
  test::headlessContext();
}

// A staged chunk of `count` points on a line: positions (12 bytes a point) and extras (8),
// each section rounded up to 256 bytes. 16 points: 256 + 256 = 512 bytes.
StagedChunk stagedPoints(std::uint32_t count) {
  PointCloud cloud;
  cloud.count = count;
  cloud.positions = Column<Int3>(count);
  for (std::uint32_t i = 0; i < count; ++i) cloud.positions[i] = {std::int32_t(i), 0, 0};
  std::vector<std::uint32_t> order(count);
  std::iota(order.begin(), order.end(), 0u);
  ChunkLayout layout;
  layout.uniform_spacing = 1.0f;
  return stagePointChunk(cloud, order, layout);
}

std::vector<std::int32_t> sorted(std::vector<std::int32_t> nodes) {
  std::sort(nodes.begin(), nodes.end());
  return nodes;
}

TEST(GpuNodeCache, UploadsAndFindsNodes) {
  ensureContext();
  GpuNodeCache cache(4096);
  StagedChunk staged = stagedPoints(16);
  // Positions, colours, extras and one batch box, each section rounded up to 256 bytes.
  ASSERT_EQ(staged.bytes.size(), 768u);
  ASSERT_TRUE(cache.insert(7, 1, staged, 1));
  EXPECT_TRUE(staged.bytes.empty());  // handed to the GPU
  const PointChunk* chunk = cache.find(7);
  ASSERT_NE(chunk, nullptr);
  EXPECT_NE(chunk->buffer, 0u);
  EXPECT_EQ(chunk->count, 16u);
  GLint64 size = 0;
  glGetNamedBufferParameteri64v(chunk->buffer, GL_BUFFER_SIZE, &size);
  EXPECT_EQ(size, 768);
  EXPECT_EQ(cache.bytes(), 768u);
  EXPECT_EQ(cache.find(8), nullptr);
}

TEST(GpuNodeCache, EvictsLeastRecentlyUsedUnderItsBudget) {
  ensureContext();
  GpuNodeCache cache(3072);  // four nodes of 768 bytes
  for (std::int32_t node = 1; node <= 4; ++node) {
    StagedChunk staged = stagedPoints(16);
    ASSERT_TRUE(cache.insert(node, 1, staged, std::uint64_t(node)));
  }
  EXPECT_EQ(cache.bytes(), 3072u);
  // Frame 5: a fifth node pushes out node 1, used longest ago.
  StagedChunk fifth = stagedPoints(16);
  ASSERT_TRUE(cache.insert(5, 1, fifth, 5));
  EXPECT_EQ(sorted(cache.residentNodes()), (std::vector<std::int32_t>{2, 3, 4, 5}));
  // Frame 6 uses node 2 again, so node 3 is now the oldest.
  cache.touch(2, 6);
  StagedChunk sixth = stagedPoints(16);
  ASSERT_TRUE(cache.insert(6, 1, sixth, 6));
  EXPECT_EQ(sorted(cache.residentNodes()), (std::vector<std::int32_t>{2, 4, 5, 6}));
  EXPECT_EQ(cache.bytes(), 3072u);
  EXPECT_EQ(cache.evictions(), 2u);
  // Frame 6 uses nodes 2, 5 and 6: only node 4 may go, and 2304 + 1536 bytes still exceed the
  // budget, so the insert fails and the staged bytes stay for a later try.
  StagedChunk big = stagedPoints(64);  // 768 + 256 + 256 + 256 = 1536 bytes
  ASSERT_EQ(big.bytes.size(), 1536u);
  cache.touch(5, 6);
  ASSERT_FALSE(cache.insert(9, 1, big, 6));
  EXPECT_FALSE(big.bytes.empty());  // left for a later try
  EXPECT_FALSE(cache.contains(9));
  EXPECT_LE(cache.bytes(), cache.budget());
  EXPECT_TRUE(cache.contains(2) && cache.contains(5) && cache.contains(6));
}

TEST(GpuNodeCache, EvictsTheDeepestAmongEquallyOldNodes) {
  ensureContext();
  GpuNodeCache cache(2304);  // three nodes of 768 bytes
  StagedChunk parent = stagedPoints(16), child = stagedPoints(16), grandchild = stagedPoints(16);
  ASSERT_TRUE(cache.insert(1, 0, parent, 3));
  ASSERT_TRUE(cache.insert(3, 2, grandchild, 3));
  ASSERT_TRUE(cache.insert(2, 1, child, 3));
  StagedChunk other = stagedPoints(16);
  ASSERT_TRUE(cache.insert(4, 1, other, 4));
  EXPECT_EQ(sorted(cache.residentNodes()), (std::vector<std::int32_t>{1, 2, 4}));
  StagedChunk another = stagedPoints(16);
  ASSERT_TRUE(cache.insert(5, 1, another, 5));
  EXPECT_EQ(sorted(cache.residentNodes()), (std::vector<std::int32_t>{1, 4, 5}));
}

TEST(GpuNodeCache, TrimsToALoweredBudget) {
  ensureContext();
  GpuNodeCache cache(6144);
  for (std::int32_t node = 0; node < 6; ++node) {
    StagedChunk staged = stagedPoints(16);
    ASSERT_TRUE(cache.insert(node, 1, staged, std::uint64_t(node + 1)));
  }
  EXPECT_EQ(cache.bytes(), 4608u);
  cache.setBudget(1536);
  cache.trim(6);  // node 5 was used in frame 6 and stays; 0-3 go first, then 4
  EXPECT_EQ(sorted(cache.residentNodes()), (std::vector<std::int32_t>{4, 5}));
  EXPECT_EQ(cache.bytes(), 1536u);
}

}  // namespace
}  // namespace parallax
