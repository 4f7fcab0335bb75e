#include "render/node_loader.h"

#include <algorithm>
#include <cassert>
#include <exception>

namespace parallax {

NodeLoader::NodeLoader(const Octree& octree, int threads) : octree_(octree) {
  const OctreeInfo& info = octree.info();
  layout_.colors = info.has_colors;
  layout_.normals = info.has_normals;
  if (!octree.nodes().empty()) root_ = octree.nodes()[0];
  threads_.reserve(std::size_t(std::max(threads, 1)));
  for (int i = 0; i < std::max(threads, 1); ++i) {
    threads_.emplace_back([this](std::stop_token stop) { work(stop); });
  }
}

NodeLoader::~NodeLoader() {
  {
    std::lock_guard lock(mutex_);
    queue_.clear();
  }
  for (std::jthread& thread : threads_) thread.request_stop();
  // condition_variable_any wakes on request_stop by itself; the joins wait for loads in flight.
  threads_.clear();
}

void NodeLoader::request(std::span<const OctreeNode> nodes, std::span<const std::int32_t> wanted) {
  std::deque<Request> queue;
  {
    std::lock_guard lock(mutex_);
    std::unordered_set<std::int32_t> busy(in_flight_);
    for (const LoadedNode& loaded : done_) busy.insert(loaded.node);
    for (std::int32_t index : wanted) {
      assert(index >= 0 && std::size_t(index) < nodes.size() &&
             "NodeLoader: node index out of range");
      if (busy.insert(index).second) queue.push_back({index, nodes[std::size_t(index)]});
    }
    queue_.swap(queue);
  }
  wake_.notify_all();
  delivered_.notify_all();  // an emptied queue may end a waitForLoaded()
}

std::vector<LoadedNode> NodeLoader::takeLoaded() {
  std::lock_guard lock(mutex_);
  return std::exchange(done_, {});
}

void NodeLoader::waitForLoaded(std::chrono::milliseconds timeout) {
  std::unique_lock lock(mutex_);
  delivered_.wait_for(lock, timeout,
                      [&] { return !done_.empty() || (queue_.empty() && in_flight_.empty()); });
}

std::size_t NodeLoader::queued() const {
  std::lock_guard lock(mutex_);
  return queue_.size();
}

std::size_t NodeLoader::inFlight() const {
  std::lock_guard lock(mutex_);
  return in_flight_.size();
}

std::size_t NodeLoader::pending() const {
  std::lock_guard lock(mutex_);
  return queue_.size() + in_flight_.size() + done_.size();
}

std::uint64_t NodeLoader::loadsStarted() const {
  std::lock_guard lock(mutex_);
  return loads_started_;
}

void NodeLoader::work(std::stop_token stop) {
  while (true) {
    Request request;
    {
      std::unique_lock lock(mutex_);
      if (!wake_.wait(lock, stop, [&] { return !queue_.empty(); })) return;
      request = std::move(queue_.front());
      queue_.pop_front();
      in_flight_.insert(request.index);
      ++loads_started_;
    }
    LoadedNode loaded = load(request);
    {
      std::lock_guard lock(mutex_);
      in_flight_.erase(request.index);
      done_.push_back(std::move(loaded));
    }
    delivered_.notify_all();
  }
}

LoadedNode NodeLoader::load(const Request& request) {
  LoadedNode loaded;
  loaded.node = request.index;
  try {
    if (octree_.info().has_intensity) {
      std::call_once(intensity_once_, [&] {
        const PointCloud root = octree_.loadNode(root_);
        if (root.hasIntensity() && root.count > 0) {
          const auto [lo, hi] = std::minmax_element(root.intensity.begin(), root.intensity.end());
          layout_.intensity_min = *lo;
          layout_.intensity_max = *hi > *lo ? *hi : *lo + 1.0f;
        }
      });
    }
    const PointCloud cloud = octree_.loadNode(request.node);
    ChunkLayout layout = layout_;
    layout.uniform_spacing = float(request.node.spacing);
    loaded.staged = stagePointChunk(cloud, mortonOrder(cloud), layout);
  } catch (const std::exception& error) {
    // InputError's message names the file and the byte range; std::bad_alloc and the like are
    // reported the same way, so one bad node never takes the viewer down.
    loaded.staged = {};
    loaded.error = error.what();
  }
  return loaded;
}

}  // namespace parallax
