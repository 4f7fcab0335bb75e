// parallax.open_octree: a Potree 2.0 directory or a COPC file, local or over http(s), as a Python
// object with its bounds and hierarchy and region queries returning PointClouds. The octree is
// the library's (lod/octree_open.h, through core's byte sources and net's HTTP cache); a query is
// lod/octree_export.h's queryOctree, which reads only the nodes the region and level can meet.
#include <pybind11/stl.h>

#include <algorithm>
#include <memory>
#include <mutex>

#include "core/progress.h"
#include "lod/copc_reader.h"
#include "lod/octree_export.h"
#include "lod/octree_open.h"
#include "net/network_counters.h"
#include "python_module.h"

namespace py = pybind11;

namespace parallax::python {

namespace {

py::tuple boundsTuple(const Bounds3& bounds) {
  return py::make_tuple(triple(bounds.min), triple(bounds.max));
}

// One node of the hierarchy as Python sees it (a copy: the octree's array may grow).
struct NodeInfo {
  std::string name;
  int level = 0;
  Bounds3 box;
  double spacing = 0.0;
  std::uint32_t point_count = 0;
  std::uint8_t child_mask = 0;
};

// An open octree. The Octree's hierarchy belongs to one thread at a time (lod/octree.h): every
// call that may expand it or read nodes holds `mutex`, taken with the GIL released so that a
// query on one thread never blocks the interpreter's others.
class OctreeHandle {
 public:
  explicit OctreeHandle(const std::string& input) : input_(input) {
    py::gil_scoped_release release;
    octree_ = openOctree(input);
    copc_ = copcDetails(*octree_).has_value();
  }

  const OctreeInfo& info() const { return octree_->info(); }
  const std::string& input() const { return input_; }
  bool copc() const { return copc_; }

  // Every node, the whole hierarchy read first (over HTTP: its chunks or pages, few requests).
  std::vector<NodeInfo> nodes() {
    py::gil_scoped_release release;
    const std::lock_guard lock(mutex_);
    expandWholeHierarchy(*octree_);
    std::vector<NodeInfo> nodes;
    nodes.reserve(octree_->nodes().size());
    for (const OctreeNode& node : octree_->nodes()) {
      nodes.push_back(
          {node.name, node.level, node.box, node.spacing, node.point_count, node.child_mask});
    }
    return nodes;
  }

  // Points per level, root first: the number of levels is its length.
  std::vector<std::uint64_t> levelPointCounts() {
    std::vector<std::uint64_t> counts;
    for (const NodeInfo& node : nodes()) {
      if (std::size_t(node.level) >= counts.size()) counts.resize(std::size_t(node.level) + 1);
      counts[std::size_t(node.level)] += node.point_count;
    }
    return counts;
  }

  // The octree and the lock that gives it to one thread (taken with the GIL released).
  Octree& octree() { return *octree_; }
  std::mutex& mutex() { return mutex_; }

  int levelOfSpacing(double spacing) {
    py::gil_scoped_release release;
    const std::lock_guard lock(mutex_);
    return parallax::levelOfSpacing(*octree_, spacing);
  }

 private:
  std::string input_;
  std::unique_ptr<Octree> octree_;
  bool copc_ = false;
  std::mutex mutex_;
};

// The Progress behind a query's callback: counts to the points of the nodes read, which is known
// only once the nodes are chosen; calls the callable with the GIL taken, at most 200 times.
class QueryProgress final : public Progress {
 public:
  explicit QueryProgress(py::object callback) : callback_(std::move(callback)) {}
  void setTotal(std::uint64_t total) {
    total_ = total;
    step_ = std::max<std::uint64_t>(1, total / 200);
  }
  void advance(std::uint64_t amount) override {
    done_ += amount;
    if (done_ < next_ && done_ < total_) return;
    next_ = done_ + step_;
    if (error_) return;
    py::gil_scoped_acquire gil;
    try {
      callback_(done_, total_);
    } catch (py::error_already_set& error) {
      error_ = std::make_unique<py::error_already_set>(std::move(error));
    }
  }
  // Raises what the callable raised (needs the GIL).
  void finish() {
    if (error_) throw std::move(*error_);
  }

 private:
  py::object callback_;
  std::uint64_t total_ = 0, step_ = 1, done_ = 0, next_ = 0;
  std::unique_ptr<py::error_already_set> error_;
};

CloudPtr query(OctreeHandle& octree, const FilterArguments& filter_arguments,
               const py::object& level, const py::object& spacing, const py::object& progress,
               py::dict* report) {
  OctreeQuery query{.filter = pointFilterFrom(filter_arguments)};  // before any I/O
  if (!level.is_none() && !spacing.is_none()) {
    throw py::value_error("level, spacing: give one of them (a level has its spacing)");
  }
  if (!level.is_none()) {
    query.max_level = level.cast<int>();
    if (query.max_level < 0) {
      throw py::value_error("level: expected 0 (the root) or deeper, found " +
                            std::to_string(query.max_level));
    }
  }
  if (!spacing.is_none()) {
    const double value = spacing.cast<double>();
    if (!(value > 0.0)) {
      throw py::value_error("spacing: expected a positive distance in world units, found " +
                            std::string(py::str(py::repr(spacing))));
    }
    query.max_level = octree.levelOfSpacing(value);
  }
  std::unique_ptr<QueryProgress> bar;
  if (!progress.is_none()) bar = std::make_unique<QueryProgress>(progress);
  OctreePoints points;
  {
    py::gil_scoped_release release;
    const std::lock_guard lock(octree.mutex());
    // queryOctree asks for the progress once it has chosen the nodes, with their points' total.
    points =
        queryOctree(octree.octree(), query, octree.input(), [&](std::uint64_t total) -> Progress* {
          if (bar) bar->setTotal(total);
          return bar.get();
        });
  }
  if (bar) bar->finish();
  if (report) {
    (*report)["nodes_read"] = points.nodes_read;
    (*report)["nodes_total"] = points.nodes_total;
    (*report)["node_bytes"] = points.node_bytes;
    (*report)["level"] = query.max_level;
  }
  auto handle = std::make_shared<CloudHandle>();
  handle->cloud = std::move(points.cloud);
  handle->metadata.path = octree.input();
  handle->metadata.format = octree.copc() ? "copc" : "potree";
  return handle;
}

}  // namespace

void bindOctree(py::module_& m) {
  py::class_<NodeInfo>(m, "OctreeNode", "One node of an octree's hierarchy")
      .def_readonly("name", &NodeInfo::name, "Potree's name: 'r', then a digit 0-7 a level")
      .def_readonly("level", &NodeInfo::level, "0 for the root")
      .def_property_readonly(
          "bounds", [](const NodeInfo& node) { return boundsTuple(node.box); },
          "The node's cube, ((xmin, ymin, zmin), (xmax, ymax, zmax)), world coordinates")
      .def_readonly("spacing", &NodeInfo::spacing, "The root's spacing / 2^level")
      .def_readonly("point_count", &NodeInfo::point_count)
      .def_readonly("child_mask", &NodeInfo::child_mask,
                    "Bit i: child i exists (+x is bit 4, +y bit 2, +z bit 1)")
      .def("__repr__", [](const NodeInfo& node) {
        return "<parallax.OctreeNode " + node.name + ": " + std::to_string(node.point_count) +
               " points>";
      });

  py::class_<OctreeHandle>(m, "Octree", R"doc(
A level-of-detail octree: a Potree 2.0 directory or a COPC file, local or over http(s).

Every point is in one node (additive LOD): levels 0..L together are the cloud at level L's
spacing. ``query`` reads only the nodes its region and level can meet (over HTTP: their byte
ranges, through the on-disk range cache), with the GIL released.
)doc")
      .def_property_readonly("path", &OctreeHandle::input)
      .def_property_readonly("format",
                             [](const OctreeHandle& o) { return o.copc() ? "copc" : "potree"; })
      .def_property_readonly("point_count",
                             [](const OctreeHandle& o) { return o.info().point_count; })
      .def("__len__", [](const OctreeHandle& o) { return o.info().point_count; })
      .def_property_readonly(
          "bounds", [](const OctreeHandle& o) { return boundsTuple(o.info().bounds); },
          "Tight bounds of the points, ((xmin, ymin, zmin), (xmax, ymax, zmax))")
      .def_property_readonly(
          "cube", [](const OctreeHandle& o) { return boundsTuple(o.info().cube); },
          "The root node's cube")
      .def_property_readonly(
          "spacing", [](const OctreeHandle& o) { return o.info().spacing; },
          "The root's point spacing, world units")
      .def_property_readonly(
          "scale", [](const OctreeHandle& o) { return triple(o.info().quantization.scale); })
      .def_property_readonly(
          "offset", [](const OctreeHandle& o) { return triple(o.info().quantization.offset); })
      .def_property_readonly(
          "attributes", [](const OctreeHandle& o) { return o.info().attributes; },
          "The attributes its nodes hold")
      .def("nodes", &OctreeHandle::nodes,
           "Every node of the hierarchy (read whole first), as OctreeNode objects")
      .def_property_readonly("level_point_counts", &OctreeHandle::levelPointCounts,
                             "Points per level, root first (its length is the number of levels)")
      .def_property_readonly(
          "levels", [](OctreeHandle& o) { return o.levelPointCounts().size(); },
          "The number of levels (the root's is 0)")
      .def(
          "query",
          [](OctreeHandle& octree, const py::object& box, const py::object& polygon,
             const py::object& level, const py::object& spacing, const py::object& classes,
             const py::object& returns, const py::object& intensity, const py::object& elevation,
             const py::object& gps_time, const std::string& clip_mode, const py::object& progress,
             const py::object& report) {
            py::dict stats;
            CloudPtr cloud = query(
                octree, {classes, returns, intensity, elevation, gps_time, box, polygon, clip_mode},
                level, spacing, progress, &stats);
            if (!report.is_none()) report.attr("update")(stats);
            return cloud;
          },
          py::kw_only(), py::arg("box") = py::none(), py::arg("polygon") = py::none(),
          py::arg("level") = py::none(), py::arg("spacing") = py::none(),
          py::arg("classes") = py::none(), py::arg("returns") = py::none(),
          py::arg("intensity") = py::none(), py::arg("elevation") = py::none(),
          py::arg("gps_time") = py::none(), py::arg("clip_mode") = "inside",
          py::arg("progress") = py::none(), py::arg("report") = py::none(),
          R"doc(The points of the octree a region, a level and the filters keep, as a PointCloud.

box: (xmin, ymin, zmin, xmax, ymax, zmax[, yaw_degrees]), world coordinates, closed.
polygon: [(x, y), ...] extruded along z (with a box: their intersection).
level: the deepest level read (0: the root alone); spacing: a resolution in world units (the
first level whose spacing is at most it). Neither: every level, the whole cloud.
classes, returns, intensity, elevation, gps_time, clip_mode: as parallax.read.
progress: callable(done, total) over the points of the nodes read.
report: a dict filled with nodes_read, nodes_total, node_bytes and level.)doc")
      .def("__repr__", [](const OctreeHandle& o) {
        return "<parallax.Octree " + std::string(o.copc() ? "COPC" : "Potree 2.0") + " '" +
               o.input() + "': " + std::to_string(o.info().point_count) + " points>";
      });

  m.def(
      "open_octree", [](const std::string& path) { return std::make_unique<OctreeHandle>(path); },
      py::arg("path"),
      "Opens a Potree 2.0 directory or a COPC file (told by content), or its http(s) URL. "
      "Raises parallax.InputError for anything else.");

  m.def(
      "network_stats",
      [] {
        const NetworkStats stats = networkStats();
        py::dict result;
        result["requests"] = stats.requests;
        result["bytes_received"] = stats.bytes_received;
        result["cache_hits"] = stats.cache_hits;
        result["cache_bytes"] = stats.cache_bytes;
        result["retries"] = stats.retries;
        return result;
      },
      "The process's HTTP counters since it started: requests, bytes_received, cache_hits, "
      "cache_bytes, retries");
}

}  // namespace parallax::python
