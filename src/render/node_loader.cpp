#include "render/node_loader.h"

#include <sys/resource.h>
#include <unistd.h>

#include <tbb/task_arena.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <exception>
#include <unordered_set>

#include "core/byte_source.h"
#include "core/point_filter.h"

namespace parallax {

NodeLoader::NodeLoader(const Octree& octree, int threads) : octree_(octree) {
  const OctreeInfo& info = octree.info();
  layout_.colors = info.has_colors;
  layout_.normals = info.has_normals;
  layout_.gps_time = std::find(info.attributes.begin(), info.attributes.end(),
                               filter_names::kGpsTime) != info.attributes.end();
  if (!octree.nodes().empty()) root_ = octree.nodes()[0];
  threads_.reserve(std::size_t(std::max(threads, 1)));
  for (int i = 0; i < std::max(threads, 1); ++i) {
    threads_.emplace_back([this](std::stop_token stop) { work(stop); });
  }
}

NodeLoader::~NodeLoader() {
  stop();
}

void NodeLoader::stop() {
  {
    std::lock_guard lock(mutex_);
    queue_.clear();
  }
  for (std::jthread& thread : threads_) thread.request_stop();
  // condition_variable_any wakes on request_stop by itself; the joins wait for loads in flight.
  threads_.clear();
  std::lock_guard lock(mutex_);
  done_.clear();
}

void NodeLoader::request(std::span<const OctreeNode> nodes, std::span<const std::int32_t> wanted,
                         std::span<const std::int32_t> hierarchy) {
  std::deque<Request> queue;
  std::vector<OctreeNode> hint_nodes, hint_hierarchy;
  {
    std::lock_guard lock(mutex_);
    std::unordered_set<std::int64_t> busy;
    for (const auto& [key, stop] : in_flight_) busy.insert(key);
    for (const LoadedNode& loaded : done_) busy.insert(keyOf(loaded.node, loaded.hierarchy));
    std::unordered_set<std::int64_t> named;
    auto enqueue = [&](std::int32_t index, bool is_hierarchy) {
      assert(index >= 0 && std::size_t(index) < nodes.size() &&
             "NodeLoader: node index out of range");
      const std::int64_t key = keyOf(index, is_hierarchy);
      named.insert(key);
      if (busy.insert(key).second) {
        queue.push_back({index, is_hierarchy, nodes[std::size_t(index)]});
      }
    };
    for (std::int32_t index : hierarchy) enqueue(index, true);
    for (std::int32_t index : wanted) enqueue(index, false);
    queue_.swap(queue);
    // Work in flight that nothing names any more: given up where the octree can.
    for (auto& [key, stop] : in_flight_) {
      if (!named.count(key)) stop.request_stop();
    }
    // The queue only: a load in flight has its bytes or is waiting for them (and a fetched
    // range that a hint no longer names is kept a while by the source, for a load that took
    // its node from the queue just before). Naming loads in flight would fetch again the nodes
    // already read, as long as they are being staged.
    std::uint64_t hinted_bytes = 0;
    for (const Request& r : queue_) {
      if (r.hierarchy) {
        hint_hierarchy.push_back(r.node);
      } else if (hint_nodes.size() < kPrefetchNodes && hinted_bytes < kPrefetchBytes) {
        hint_nodes.push_back(r.node);
        hinted_bytes += r.node.byte_size;
      }
    }
    // Under the lock: a worker that took a node from the old queue and read it must not see
    // the hint name it again afterwards (the source would fetch it a second time).
    octree_.prefetch(hint_nodes, hint_hierarchy);
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

std::uint64_t NodeLoader::loadsCancelled() const {
  std::lock_guard lock(mutex_);
  return loads_cancelled_;
}

void NodeLoader::work(std::stop_token stop) {
  // Loading yields to the frame: on a machine with few cores the loader's decoding (LAZ above
  // all) would otherwise take the cores the frame loop and a software rasterizer need, and the
  // first picture would wait for nodes it does not draw yet. A higher nice value for this thread
  // (Linux: per thread) costs nothing when the frame loop is idle. Failure (another OS) is
  // harmless: loading then competes as before.
  setpriority(PRIO_PROCESS, static_cast<id_t>(gettid()), kNice);
  // The parallel loops of decoding and staging run on this thread only: TBB's workers are
  // shared with the rest of the process and keep its priority, so work handed to them would
  // escape the nice value. Nodes load in parallel across the loader's threads instead.
  tbb::task_arena serial(1);
  serial.execute([&] { serve(stop); });
}

void NodeLoader::serve(std::stop_token stop) {
  while (true) {
    Request request;
    std::stop_token cancel;
    {
      std::unique_lock lock(mutex_);
      if (!wake_.wait(lock, stop, [&] { return !queue_.empty(); })) return;
      request = std::move(queue_.front());
      queue_.pop_front();
      std::stop_source& source = in_flight_[keyOf(request.index, request.hierarchy)];
      source = std::stop_source();
      cancel = source.get_token();
      if (!request.hierarchy) ++loads_started_;
    }
    LoadedNode loaded = load(request, cancel);
    {
      std::lock_guard lock(mutex_);
      in_flight_.erase(keyOf(request.index, request.hierarchy));
      if (loaded.node >= 0) {
        done_.push_back(std::move(loaded));
      } else {
        ++loads_cancelled_;
      }
    }
    delivered_.notify_all();
  }
}

std::optional<NodeLoader::IntensityLayout> NodeLoader::intensityLayout() const {
  if (!intensity_ready_.load(std::memory_order_acquire)) return std::nullopt;
  return IntensityLayout{layout_.intensity_min, layout_.intensity_max, intensity_integral_};
}

LoadedNode NodeLoader::load(const Request& request, std::stop_token cancel) {
  LoadedNode loaded;
  loaded.node = request.index;
  loaded.hierarchy = request.hierarchy;
  try {
    if (request.hierarchy) {
      octree_.fetchHierarchy(request.node, cancel);
      return loaded;
    }
    if (octree_.info().has_intensity) {
      std::call_once(intensity_once_, [&] {
        const PointCloud root = octree_.loadNode(root_);
        if (root.hasIntensity() && root.count > 0) {
          const auto [lo, hi] = std::minmax_element(root.intensity.begin(), root.intensity.end());
          layout_.intensity_min = *lo;
          layout_.intensity_max = *hi > *lo ? *hi : *lo + 1.0f;
          intensity_integral_ = std::all_of(root.intensity.begin(), root.intensity.end(),
                                            [](float v) { return v == std::floor(v); });
        }
        intensity_ready_.store(true, std::memory_order_release);
      });
    } else {
      intensity_ready_.store(true, std::memory_order_release);
    }
    const PointCloud cloud = octree_.loadNodeCancellable(request.node, cancel);
    ChunkLayout layout = layout_;
    layout.uniform_spacing = float(request.node.spacing);
    loaded.staged = stagePointChunk(cloud, mortonOrder(cloud), layout);
  } catch (const ReadCancelled&) {
    loaded.node = -1;  // no longer wanted: nothing to deliver
  } catch (const std::exception& error) {
    // InputError's message names the file and the byte range; std::bad_alloc and the like are
    // reported the same way, so one bad node never takes the viewer down.
    loaded.staged = {};
    loaded.error = error.what();
  }
  return loaded;
}

}  // namespace parallax
