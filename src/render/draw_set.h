// What one frame draws: a list of GPU point chunks, whoever owns them. A GpuPointCloud (a whole
// cloud uploaded at once) gives all its chunks; the level-of-detail node cache gives the nodes
// the node selection chose, in priority order. The renderer draws the list once per view.
#pragma once

#include <cstdint>
#include <vector>

#include "core/bounds.h"
#include "render/point_buffers.h"

namespace parallax {

struct DrawItem {
  const PointChunk* chunk = nullptr;  // owned by the GpuPointCloud or the node cache
  // Level-of-detail nodes: the node's spacing (world units) and level, for adaptive point size.
  // 0 spacing: the chunk carries its own per-point spacing (a GpuPointCloud).
  float node_spacing = 0.0f;
  int node_level = 0;
  // Level-of-detail nodes: the node's index in Octree::nodes(), whose loadNode() the chunk was
  // staged from (picking reads points back from it); -1 for a whole uploaded cloud.
  std::int32_t node = -1;
};

struct DrawSet {
  std::vector<DrawItem> items;  // drawn in this order
  Bounds3 bounds;               // of everything that may be drawn (clip planes come from it)
  bool has_colors = false, has_normals = false, has_intensity = false;
  bool has_classification = false;
  bool has_gps_time = false;  // chunks have a GPS time section (PointChunk::gps_offset)
  // The intensity quantization of every chunk (ChunkLayout), and whether every intensity is a
  // whole number (LAS, Potree and COPC): what the filter's bounds are converted with.
  float intensity_min = 0.0f, intensity_max = 1.0f;
  bool intensity_integral = true;
  double typical_spacing = 0.0;  // world units, for the default adaptive and attenuated sizes
};

}  // namespace parallax
