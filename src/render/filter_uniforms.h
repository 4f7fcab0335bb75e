// The point filter (core/point_filter.h) as the uniforms of keepPoint() (point_pass_glsl.cpp),
// set the same way by both rasterizers: the frame-wide part once per program, the part relative
// to a chunk (its origin, its GPS time base) per chunk. Only uniforms: changing a filter uploads
// no point.
//
// How the GPU's tests agree with the CPU's (filterPoints, in double on the file's values):
//   - classes and returns: the same 256-bit tables, indexed by the bytes the buffers hold.
//   - intensity: the buffers hold unorm16 over the draw set's range (ChunkLayout); the bounds are
//     converted with the same function. Where every intensity is a whole number (LAS, Potree,
//     COPC) the bounds are first rounded inwards to whole numbers, and the test is exact while
//     the range spans at most 65 536 values; otherwise it is good to a 65 535th of the range.
//     An octree's range is its root node's (NodeLoader): a bound outside it is only that good.
//   - elevation, clip planes, polygon: chunk-relative floats with the origin taken off in double,
//     exact but within a float's step (~1e-7 of the chunk's size) of a bound or edge.
//   - GPS time: (hi, lo) float pairs relative to the chunk's base (PointChunk::gps_offset), the
//     bounds split the same way with the low part rounded inwards: exact (see splitGpsTime).
#pragma once

#include <epoxy/gl.h>

#include <array>
#include <cstdint>
#include <string>

#include "core/point_filter.h"
#include "render/draw_set.h"
#include "render/shader_program.h"

namespace parallax {

// The parts of keepPoint() a frame needs, each compiled in only when used (FILTER_* defines):
// llvmpipe runs both sides of a branch on a uniform under a mask, so a GPS test or a polygon
// loop left in for every filter would cost every point its work (measured: a classes-only
// filter at 3 M points, 165 ms of CPU a frame with its test alone, 228 ms with every test
// compiled in and switched off by uniforms).
enum FilterPart : unsigned {
  kFilterClasses = 1,
  kFilterReturns = 2,
  kFilterIntensity = 4,  // also "keep nothing" (filterIntensityBounds)
  kFilterElevation = 8,
  kFilterGps = 16,
  kFilterPlanes = 32,
  kFilterPolygon = 64,
  kFilterHighlight = 128,  // the region tints (inClipRegion()) instead of dropping
};
// 0 when the filter keeps everything.
unsigned filterParts(const PointFilter& filter, const DrawSet& draw_set);
// "#define FILTER 1\n#define FILTER_CLASSES 1\n..." for the shaders (every FILTER_* defined).
std::string filterDefines(unsigned parts);

// Inclusive bounds of the unorm16 intensity the shaders compare; {1, 0} keeps nothing.
std::array<std::uint32_t, 2> filterIntensityBounds(const PointFilter& filter,
                                                   const DrawSet& draw_set);

// The GPS bounds relative to a chunk's base: (min hi, min lo, max hi, max lo).
std::array<float, 4> filterGpsBounds(const ValueRange& range, double base);

class FilterUniforms {
 public:
  // Looks the uniforms up in `program` (current) and sets the frame-wide ones.
  FilterUniforms(const ShaderProgram& program, const PointFilter& filter, const DrawSet& draw_set);
  // Sets the chunk-relative ones for `chunk`.
  void setChunk(const PointChunk& chunk) const;
  // Whether keepPoint() reads GPS times (the draw set has them and a range is set).
  bool readsGpsTime() const { return gps_on_; }
  unsigned parts() const { return parts_; }

 private:
  const PointFilter& filter_;
  unsigned parts_ = 0;
  bool gps_on_ = false;
  GLint planes_ = -1, elevation_ = -1, gps_ = -1, polygon_ = -1;
};

}  // namespace parallax
