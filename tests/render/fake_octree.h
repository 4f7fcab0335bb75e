// A hand-built Octree for the level-of-detail tests: nodes with known boxes and point counts,
// points made up on demand, and hooks to hold a load back (a gate), make a load fail, and hide a
// subtree behind a proxy until expandHierarchy(); and SlowLinkOctree, the same behind a slow link.
#pragma once

#include <atomic>
#include <condition_variable>
#include <mutex>
#include <set>
#include <string>
#include <vector>

#include "core/byte_source.h"
#include "core/error.h"
#include "lod/octree.h"

namespace parallax::test {

class FakeOctree : public Octree {
 public:
  // A root node over `cube` with `points` points and spacing `spacing`.
  FakeOctree(const Bounds3& cube, std::uint32_t points, double spacing) {
    info_.cube = cube;
    info_.bounds = cube;
    info_.spacing = spacing;
    info_.quantization.scale = {1.0 / 1024, 1.0 / 1024, 1.0 / 1024};
    info_.has_colors = true;
    info_.has_intensity = true;
    OctreeNode root;
    root.name = "r";
    root.box = cube;
    root.spacing = spacing;
    root.point_count = points;
    root.children.fill(-1);
    nodes_.push_back(root);
    info_.point_count = points;
  }

  // Adds child `octant` (bit 4 +x, 2 +y, 1 +z) of `parent`; returns its index.
  std::int32_t addChild(std::int32_t parent, int octant, std::uint32_t points) {
    OctreeNode child;
    const OctreeNode& p = nodes_[std::size_t(parent)];
    child.name = p.name + char('0' + octant);
    child.level = p.level + 1;
    child.spacing = p.spacing / 2;
    child.point_count = points;
    child.parent = parent;
    child.children.fill(-1);
    const auto center = p.box.center();
    const int bits[3] = {4, 2, 1};
    for (int a = 0; a < 3; ++a) {
      const bool high = (octant & bits[a]) != 0;
      child.box.min[std::size_t(a)] = high ? center[std::size_t(a)] : p.box.min[std::size_t(a)];
      child.box.max[std::size_t(a)] = high ? p.box.max[std::size_t(a)] : center[std::size_t(a)];
    }
    const auto index = std::int32_t(nodes_.size());
    nodes_[std::size_t(parent)].child_mask |= std::uint8_t(1u << octant);
    nodes_[std::size_t(parent)].children[std::size_t(octant)] = index;
    nodes_.push_back(child);
    info_.point_count += points;
    return index;
  }

  // A full octree below the root: every node down to `depth` levels has all 8 children, each
  // with `points` points.
  void addFullLevels(int depth, std::uint32_t points) {
    std::vector<std::int32_t> level{0};
    for (int d = 0; d < depth; ++d) {
      std::vector<std::int32_t> next;
      for (std::int32_t node : level) {
        for (int octant = 0; octant < 8; ++octant) next.push_back(addChild(node, octant, points));
      }
      level = next;
    }
  }

  // Turns `node` into a proxy: its children (and their subtrees) leave nodes() until
  // expandHierarchy(node) puts them back (appended, with new indices, as a reader would).
  void makeProxy(std::int32_t node) {
    std::lock_guard lock(mutex_);
    hidden_.push_back(node);
    nodes_[std::size_t(node)].hierarchy_pending = true;
  }

  // Loads of these nodes throw InputError.
  void failLoads(std::int32_t node) {
    std::lock_guard lock(mutex_);
    failing_.insert(node);
  }

  // With the gate closed, loadNode() waits until it opens.
  void closeGate() {
    std::lock_guard lock(mutex_);
    gate_open_ = false;
  }
  void openGate() {
    {
      std::lock_guard lock(mutex_);
      gate_open_ = true;
    }
    changed_.notify_all();
  }
  // Waits until `count` loads have started (inside loadNode).
  void waitForLoadsStarted(std::size_t count) {
    std::unique_lock lock(mutex_);
    changed_.wait(lock, [&] { return load_log_.size() >= count; });
  }
  // Names of the nodes whose points were read, in the order the reads started.
  std::vector<std::string> loadLog() const {
    std::lock_guard lock(mutex_);
    return load_log_;
  }
  int expansions() const { return expansions_; }

  const OctreeInfo& info() const override { return info_; }
  std::span<const OctreeNode> nodes() const override { return visible_nodes(); }

  void expandHierarchy(std::int32_t node) override {
    ++expansions_;
    nodes_[std::size_t(node)].hierarchy_pending = false;
    std::erase(hidden_, node);
    rebuildVisible();
  }

  PointCloud loadNode(const OctreeNode& node) const override {
    std::unique_lock lock(mutex_);
    load_log_.push_back(node.name);
    changed_.notify_all();
    changed_.wait(lock, [&] { return gate_open_; });
    for (std::int32_t failing : failing_) {
      if (nodes_[std::size_t(failing)].name == node.name) {
        throw InputError({.file = "octree.bin",
                          .byte_offset = node.byte_offset,
                          .element = "node " + node.name,
                          .expected = "bytes inside the file",
                          .found = "a range past its end"});
      }
    }
    lock.unlock();
    return makePoints(node);
  }

  // The node's made-up points: a deterministic scatter inside its box, exactly on the grid.
  PointCloud makePoints(const OctreeNode& node) const {
    PointCloud cloud;
    cloud.count = node.point_count;
    cloud.quantization = info_.quantization;
    cloud.positions = Column<Int3>(node.point_count);
    cloud.colors = Column<Rgba8>(node.point_count);
    cloud.intensity = Column<float>(node.point_count);
    std::uint32_t state = 12345u + std::uint32_t(node.name.size()) * 7919u;
    auto next = [&] {
      state = state * 1664525u + 1013904223u;
      return double(state >> 8) / double(1u << 24);
    };
    for (std::uint32_t i = 0; i < node.point_count; ++i) {
      std::int32_t q[3];
      for (int a = 0; a < 3; ++a) {
        const double lo = node.box.min[std::size_t(a)], hi = node.box.max[std::size_t(a)];
        q[a] = cloud.quantization.toQuantized(a, lo + (hi - lo) * next());
      }
      cloud.positions[i] = {q[0], q[1], q[2]};
      cloud.colors[i] = {std::uint8_t(i), std::uint8_t(node.level * 40), 200, 255};
      cloud.intensity[i] = float(100 * node.level + i % 100);
    }
    cloud.computeBounds();
    return cloud;
  }

 private:
  // nodes() without the subtrees of unexpanded proxies. The visible list is rebuilt when a proxy
  // is expanded; indices of nodes seen before never change because hidden subtrees are added
  // only at the end (a test makes proxies of nodes whose subtrees were added last).
  std::span<const OctreeNode> visible_nodes() const {
    if (!visible_built_) const_cast<FakeOctree*>(this)->rebuildVisible();
    return visible_;
  }
  void rebuildVisible() {
    std::vector<std::uint8_t> hide(nodes_.size(), 0);
    for (std::size_t i = 0; i < nodes_.size(); ++i) {
      const std::int32_t parent = nodes_[i].parent;
      if (parent >= 0 &&
          (hide[std::size_t(parent)] || nodes_[std::size_t(parent)].hierarchy_pending)) {
        hide[i] = 1;
      }
    }
    visible_.clear();
    for (std::size_t i = 0; i < nodes_.size(); ++i) {
      if (hide[i]) continue;
      OctreeNode node = nodes_[i];
      if (node.hierarchy_pending) node.children.fill(-1);
      visible_.push_back(node);
    }
    visible_built_ = true;
  }

  OctreeInfo info_;
  std::vector<OctreeNode> nodes_;
  std::vector<OctreeNode> visible_;
  bool visible_built_ = false;
  std::vector<std::int32_t> hidden_;
  std::set<std::int32_t> failing_;
  mutable std::mutex mutex_;
  mutable std::condition_variable changed_;
  mutable std::vector<std::string> load_log_;
  bool gate_open_ = true;
  std::atomic<int> expansions_ = 0;
};

// A FakeOctree behind a slow link, as an octree read over HTTP looks to the renderer: loads wait
// at a gate of their own and give up when cancelled (ReadCancelled); hierarchyReady() is false
// for a proxy until fetchHierarchy() has run for it; prefetch hints are recorded.
class SlowLinkOctree : public FakeOctree {
 public:
  using FakeOctree::FakeOctree;

  void closeLink() {
    std::lock_guard lock(link_mutex_);
    link_open_ = false;
  }
  void openLink() {
    {
      std::lock_guard lock(link_mutex_);
      link_open_ = true;
    }
    link_changed_.notify_all();
  }
  // Waits until `count` cancellable loads have started.
  void waitForLinkLoads(std::size_t count) {
    std::unique_lock lock(link_mutex_);
    link_changed_.wait(lock, [&] { return link_loads_.size() >= count; });
  }
  std::vector<std::string> linkLoads() const {
    std::lock_guard lock(link_mutex_);
    return link_loads_;
  }
  int cancelledLoads() const { return cancelled_; }
  // Events in order: "fetch r7" (fetchHierarchy), "expand r7" (expandHierarchy).
  std::vector<std::string> hierarchyLog() const {
    std::lock_guard lock(link_mutex_);
    return hierarchy_log_;
  }
  // The last prefetch hint: the nodes' names, then the hierarchy nodes' names after a "|".
  std::vector<std::string> lastHint() const {
    std::lock_guard lock(link_mutex_);
    return last_hint_;
  }

  PointCloud loadNodeCancellable(const OctreeNode& node, std::stop_token cancel) const override {
    {
      std::unique_lock lock(link_mutex_);
      link_loads_.push_back(node.name);
      link_changed_.notify_all();
      if (!link_changed_.wait(lock, cancel, [&] { return link_open_; })) {
        ++cancelled_;
        throw ReadCancelled();
      }
    }
    return loadNode(node);
  }
  bool hierarchyReady(std::int32_t node) const override {
    std::lock_guard lock(link_mutex_);
    return fetched_.count(nodes()[std::size_t(node)].name) > 0;
  }
  void fetchHierarchy(const OctreeNode& node, std::stop_token) const override {
    std::lock_guard lock(link_mutex_);
    hierarchy_log_.push_back("fetch " + node.name);
    fetched_.insert(node.name);
  }
  void expandHierarchy(std::int32_t node) override {
    {
      std::lock_guard lock(link_mutex_);
      hierarchy_log_.push_back("expand " + nodes()[std::size_t(node)].name);
    }
    FakeOctree::expandHierarchy(node);
  }
  void prefetch(std::span<const OctreeNode> nodes,
                std::span<const OctreeNode> hierarchy) const override {
    std::lock_guard lock(link_mutex_);
    last_hint_.clear();
    for (const OctreeNode& n : nodes) last_hint_.push_back(n.name);
    last_hint_.push_back("|");
    for (const OctreeNode& n : hierarchy) last_hint_.push_back(n.name);
  }

 private:
  mutable std::mutex link_mutex_;
  mutable std::condition_variable_any link_changed_;
  bool link_open_ = true;
  mutable std::vector<std::string> link_loads_, hierarchy_log_, last_hint_;
  mutable std::set<std::string> fetched_;
  mutable std::atomic<int> cancelled_ = 0;
};

}  // namespace parallax::test
