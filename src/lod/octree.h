// The level-of-detail octree as the renderer sees it, whatever stores it: a Potree 2.0 directory
// on disk (potree_reader.h) or an octree built in memory from a loaded file (octree_builder.h).
//
// Additive LOD, as Potree: every point is stored in exactly one node. The root holds a subsample
// of the whole cloud spaced by `spacing`, each child a subsample of what is left in its octant
// spaced by half its parent's spacing, and leaves the rest. Drawing a node and all its ancestors
// shows the cloud at that node's spacing inside the node's box.
//
// Node boxes are cubes in world coordinates; child i of a node covers the octant whose
// +x half is bit 4 of i, +y bit 2, +z bit 1 (Potree's numbering). Node names are Potree's:
// "r" for the root, then one digit 0-7 per level ("r07" is child 7 of child 0 of the root).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <stop_token>
#include <string>
#include <vector>

#include "core/attribute_selection.h"
#include "core/bounds.h"
#include "core/point_cloud.h"
#include "core/quantization.h"

namespace parallax {

// One node of the hierarchy. Nodes live in a flat array; indices are stable for the octree's
// life (expanding a proxy appends, it never moves or removes nodes).
struct OctreeNode {
  std::string name;      // "r", "r0", "r07", ...
  int level = 0;         // 0 for the root
  Bounds3 box;           // the node's cube, world coordinates
  double spacing = 0.0;  // root spacing / 2^level, world units
  std::uint32_t point_count = 0;
  std::uint8_t child_mask = 0;             // bit i: child i exists
  std::array<std::int32_t, 8> children{};  // index of child i in nodes(), -1 where none (yet)
  std::int32_t parent = -1;                // -1 for the root
  // True while the node's children are known to exist (child_mask) but are not in nodes() yet:
  // a Potree proxy whose hierarchy chunk has not been read. expandHierarchy() reads it.
  bool hierarchy_pending = false;
  // Where the node's points are in the store: bytes of octree.bin for a Potree directory, a
  // record range for an in-memory octree. Opaque to callers.
  std::uint64_t byte_offset = 0;
  std::uint64_t byte_size = 0;
};

struct OctreeInfo {
  std::uint64_t point_count = 0;        // all points of all nodes
  Bounds3 bounds;                       // tight bounds of the points, world coordinates
  Bounds3 cube;                         // the root node's box
  Quantization quantization;            // of the positions loadNode() returns
  double spacing = 0.0;                 // the root's spacing
  std::vector<std::string> attributes;  // names, as PointCloud::attributeNames() gives them
  bool has_colors = false, has_normals = false, has_intensity = false;
  bool has_classification = false;
  // Over all points, where the format records them (Potree metadata's "min" and "max" of
  // intensity and gps-time, a COPC file's info VLR for GPS time); the viewer's filter sliders
  // start from them. Empty: not recorded.
  std::optional<std::array<double, 2>> intensity_range, gps_time_range;
};

// Read access to an octree. nodes(), expandHierarchy() and hierarchyReady() belong to one thread
// (the frame loop); loadNode(), loadNodeCancellable(), fetchHierarchy() and prefetch() may be
// called from any number of threads at once, also while the frame loop expands the hierarchy
// (they take nodes by value).
//
// An octree behind a slow link (a URL) never makes the frame loop wait: hierarchyReady() says
// whether expandHierarchy() would wait, fetchHierarchy() (on a loader thread) brings what it
// needs, and prefetch() lets the store fetch what will be loaded next, together.
class Octree {
 public:
  virtual ~Octree() = default;

  virtual const OctreeInfo& info() const = 0;
  // Node 0 is the root. Only the part of the hierarchy read so far.
  virtual std::span<const OctreeNode> nodes() const = 0;
  // Reads the hierarchy below a node with hierarchy_pending set, appending its descendants to
  // nodes() and clearing the flag. Throws InputError for a malformed hierarchy.
  virtual void expandHierarchy(std::int32_t node) = 0;
  // The node's points (node.point_count of them) with `info().quantization`. Throws InputError
  // for data that lies (a byte range past the end of the file, a wrong size).
  virtual PointCloud loadNode(const OctreeNode& node) const = 0;
  // loadNode, given up when `cancel` is requested before the bytes arrive (ReadCancelled,
  // core/byte_source.h). Default: loadNode(node), never cancelled.
  virtual PointCloud loadNodeCancellable(const OctreeNode& node, std::stop_token cancel) const {
    (void)cancel;
    return loadNode(node);
  }

  // loadNode with every attribute the octree holds, whatever selectAttributes() asked: for
  // readers that report a point whole (picking, profiles) while the drawn nodes carry only what
  // the picture needs. Safe beside loader threads as loadNode is. Default: loadNode(node).
  virtual PointCloud loadNodeWhole(const OctreeNode& node) const { return loadNode(node); }

  // True when expandHierarchy(node) would not wait on a slow link (its hierarchy is local or
  // already fetched). Default: true.
  virtual bool hierarchyReady(std::int32_t node) const {
    (void)node;
    return true;
  }
  // Fetches what expandHierarchy() needs for `node` (hierarchy_pending set) into memory, so
  // that the call then does not wait. May wait on the network: for loader threads. Throws
  // InputError, or ReadCancelled when `cancel` is requested. Default: nothing to do.
  virtual void fetchHierarchy(const OctreeNode& node, std::stop_token cancel) const {
    (void)node, (void)cancel;
  }
  // Names the nodes whose points (`nodes`) and whose hierarchy (`hierarchy`: nodes with
  // hierarchy_pending) will be asked for soon, most urgent first; replaces the previous hint.
  // Never waits. Default: nothing.
  virtual void prefetch(std::span<const OctreeNode> nodes,
                        std::span<const OctreeNode> hierarchy) const {
    (void)nodes, (void)hierarchy;
  }
  // The attributes loadNode() need give from now on (positions always); info().attributes and
  // its has_* flags then describe those. Octrees whose nodes cost the same whatever is asked
  // ignore it (default); COPC never reads the LAZ layers of the others. Call it before loading
  // nodes (it does not synchronise with loader threads).
  virtual void selectAttributes(const AttributeSelection& attributes) { (void)attributes; }
};

}  // namespace parallax
