// The background node loader: every requested node arrives, staged; requests dropped from the
// queue are never read; a new request list re-orders the queue; a failed load is reported.
#include "render/node_loader.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstring>
#include <fstream>
#include <memory>
#include <string>
#include <thread>

#include "fake_octree.h"

namespace parallax {
namespace {

using test::FakeOctree;
using namespace std::chrono_literals;

Bounds3 cube16() {
  Bounds3 box;
  box.extend(0, 0, 0);
  box.extend(16, 16, 16);
  return box;
}

// Takes loaded nodes until `count` have arrived.
std::vector<LoadedNode> takeAll(NodeLoader& loader, std::size_t count) {
  std::vector<LoadedNode> all;
  while (all.size() < count) {
    loader.waitForLoaded(1000ms);
    for (LoadedNode& node : loader.takeLoaded()) all.push_back(std::move(node));
  }
  return all;
}

TEST(NodeLoader, DeliversEveryRequestedNodeStaged) {
  FakeOctree octree(cube16(), 50, 2.0);
  octree.addFullLevels(1, 30);
  NodeLoader loader(octree, 2);
  const std::vector<std::int32_t> wanted{0, 3, 5, 8};
  loader.request(octree.nodes(), wanted);
  std::vector<LoadedNode> loaded = takeAll(loader, 4);
  std::sort(loaded.begin(), loaded.end(), [](auto& a, auto& b) { return a.node < b.node; });
  ASSERT_EQ(loaded.size(), 4u);
  for (std::size_t i = 0; i < 4; ++i) {
    const OctreeNode& node = octree.nodes()[std::size_t(wanted[i])];
    EXPECT_EQ(loaded[i].node, wanted[i]);
    EXPECT_TRUE(loaded[i].error.empty());
    EXPECT_EQ(loaded[i].staged.chunk.count, node.point_count);
    EXPECT_EQ(loaded[i].staged.chunk.buffer, 0u);
    // Positions, colours, extras and batch boxes (one batch), each rounded up to 256 bytes.
    EXPECT_EQ(loaded[i].staged.bytes.size(),
              node.point_count == 50 ? 768u + 256u + 512u + 256u : 512u + 256u + 256u + 256u);
    // Every point lies in the node's box, and carries the node's spacing.
    const Bounds3& bounds = loaded[i].staged.chunk.bounds;
    for (int a = 0; a < 3; ++a) {
      EXPECT_GE(bounds.min[std::size_t(a)], node.box.min[std::size_t(a)]);
      EXPECT_LE(bounds.max[std::size_t(a)], node.box.max[std::size_t(a)]);
    }
    float spacing = 0;
    std::memcpy(&spacing, loaded[i].staged.bytes.data() + loaded[i].staged.chunk.extras_offset + 4,
                4);
    EXPECT_EQ(spacing, float(node.spacing));
  }
  EXPECT_EQ(loader.queued(), 0u);
  EXPECT_EQ(loader.inFlight(), 0u);
}

TEST(NodeLoader, DropsCancelledRequestsAndFollowsTheNewOrder) {
  FakeOctree octree(cube16(), 10, 2.0);
  octree.addFullLevels(1, 10);
  // The intensity range is read from the root before the first node: let that happen first.
  NodeLoader loader(octree, 1);
  const std::vector<std::int32_t> root{0};
  loader.request(octree.nodes(), root);
  takeAll(loader, 1);
  const std::size_t before = octree.loadLog().size();  // root twice: range, then the node

  octree.closeGate();
  const std::vector<std::int32_t> first{1, 2, 3, 4};
  loader.request(octree.nodes(), first);
  octree.waitForLoadsStarted(before + 1);  // node 1 is in flight, held at the gate
  // The camera moved: 2 and 4 are no longer wanted, 7 is, and most urgently.
  const std::vector<std::int32_t> second{7, 1, 3};
  loader.request(octree.nodes(), second);
  EXPECT_EQ(loader.queued(), 2u);  // 7 and 3; 1 is in flight already
  EXPECT_EQ(loader.inFlight(), 1u);
  octree.openGate();
  std::vector<LoadedNode> loaded = takeAll(loader, 3);

  const std::vector<std::string> log = octree.loadLog();
  EXPECT_EQ(std::vector<std::string>(log.begin() + std::ptrdiff_t(before), log.end()),
            (std::vector<std::string>{"r0", "r6", "r2"}));
  std::vector<std::int32_t> delivered;
  for (const LoadedNode& node : loaded) delivered.push_back(node.node);
  EXPECT_EQ(delivered, (std::vector<std::int32_t>{1, 7, 3}));
  EXPECT_EQ(loader.loadsStarted(), 4u);
}

TEST(NodeLoader, ReportsAFailedLoad) {
  FakeOctree octree(cube16(), 10, 2.0);
  octree.addFullLevels(1, 10);
  octree.failLoads(2);
  NodeLoader loader(octree, 2);
  const std::vector<std::int32_t> wanted{2};
  loader.request(octree.nodes(), wanted);
  const std::vector<LoadedNode> loaded = takeAll(loader, 1);
  EXPECT_EQ(loaded[0].node, 2);
  EXPECT_NE(loaded[0].error.find("octree.bin"), std::string::npos) << loaded[0].error;
  EXPECT_NE(loaded[0].error.find("node r1"), std::string::npos) << loaded[0].error;
  EXPECT_TRUE(loaded[0].staged.bytes.empty());
}

// The scheduler state of thread `tid` of this process, from /proc (Linux): 'S' while it sleeps.
char threadState(pid_t tid) {
  std::ifstream in("/proc/self/task/" + std::to_string(tid) + "/stat");
  std::string stat;
  std::getline(in, stat);
  const auto name_end = stat.rfind(')');  // "tid (name) S ...": the name may hold anything
  return name_end != std::string::npos && name_end + 2 < stat.size() ? stat[name_end + 2] : '?';
}

TEST(NodeLoader, StopsWithWorkQueued) {
  FakeOctree octree(cube16(), 10, 2.0);
  octree.addFullLevels(1, 10);
  auto loader = std::make_unique<NodeLoader>(octree, 1);
  const std::vector<std::int32_t> root{0};
  loader->request(octree.nodes(), root);  // the intensity range is read before any other load
  takeAll(*loader, 1);
  const std::size_t before = octree.loadLog().size();

  octree.closeGate();
  const std::vector<std::int32_t> wanted{1, 2, 3, 4, 5, 6, 7, 8};
  loader->request(octree.nodes(), wanted);
  octree.waitForLoadsStarted(before + 1);  // node 1 in flight, held at the gate
  EXPECT_EQ(loader->queued(), 7u);
  // The gate opens once this thread sleeps in the destructor's join, which comes after the
  // destructor dropped the queue: then the loader may finish node 1 and must load nothing else.
  const pid_t this_thread = gettid();
  std::atomic<bool> destroying = false;
  std::thread opener([&] {
    while (!destroying) std::this_thread::yield();
    while (threadState(this_thread) != 'S') std::this_thread::sleep_for(1ms);
    octree.openGate();
  });
  destroying = true;
  loader.reset();  // returns: nothing hangs
  opener.join();
  const std::vector<std::string> log = octree.loadLog();
  ASSERT_EQ(log.size(), before + 1) << "the destructor let queued loads start";
  EXPECT_EQ(log.back(), "r0");
}

TEST(NodeLoader, CancelsLoadsInFlightThatAreNoLongerWanted) {
  test::SlowLinkOctree octree(cube16(), 10, 2.0);
  octree.addFullLevels(1, 10);
  NodeLoader loader(octree, 1);
  octree.closeLink();
  const std::vector<std::int32_t> first{1};
  loader.request(octree.nodes(), first);
  octree.waitForLinkLoads(1);  // node 1 waits on the link
  // The camera turned away: node 2 is wanted instead; node 1's read is given up.
  const std::vector<std::int32_t> second{2};
  loader.request(octree.nodes(), second);
  octree.waitForLinkLoads(2);  // the thread is free again: it took node 2
  EXPECT_EQ(octree.cancelledLoads(), 1);
  EXPECT_EQ(loader.loadsCancelled(), 1u);
  octree.openLink();
  const std::vector<LoadedNode> loaded = takeAll(loader, 1);
  ASSERT_EQ(loaded.size(), 1u);
  EXPECT_EQ(loaded[0].node, 2) << "the cancelled node is never delivered";
  EXPECT_TRUE(loaded[0].error.empty()) << loaded[0].error;
  loader.waitForLoaded(50ms);
  EXPECT_TRUE(loader.takeLoaded().empty());
  EXPECT_EQ(loader.pending(), 0u);
  EXPECT_EQ(octree.linkLoads(), (std::vector<std::string>{"r0", "r1"}));
}

TEST(NodeLoader, FetchesHierarchyFirstAndHintsTheQueue) {
  test::SlowLinkOctree octree(cube16(), 10, 2.0);
  octree.addFullLevels(1, 10);
  octree.makeProxy(8);  // r7: a proxy with no children listed, as FakeOctree keeps it
  NodeLoader loader(octree, 1);
  octree.closeLink();
  const std::vector<std::int32_t> wanted{3, 1, 2};
  const std::vector<std::int32_t> hierarchy{8};
  loader.request(octree.nodes(), wanted, hierarchy);
  // The hint names the queue in order, the hierarchy fetch apart.
  EXPECT_EQ(octree.lastHint(), (std::vector<std::string>{"r2", "r0", "r1", "|", "r7"}));
  // The hierarchy fetch comes first (it does not wait on the node gate).
  std::vector<LoadedNode> loaded = takeAll(loader, 1);
  ASSERT_EQ(loaded.size(), 1u);
  EXPECT_TRUE(loaded[0].hierarchy);
  EXPECT_EQ(loaded[0].node, 8);
  EXPECT_TRUE(loaded[0].error.empty());
  EXPECT_TRUE(loaded[0].staged.bytes.empty());
  EXPECT_TRUE(octree.hierarchyReady(8));
  EXPECT_EQ(octree.hierarchyLog(), (std::vector<std::string>{"fetch r7"}));
  octree.openLink();
  loaded = takeAll(loader, 3);
  std::vector<std::int32_t> order;
  for (const LoadedNode& node : loaded) order.push_back(node.node);
  EXPECT_EQ(order, (std::vector<std::int32_t>{3, 1, 2}));
}

}  // namespace
}  // namespace parallax
