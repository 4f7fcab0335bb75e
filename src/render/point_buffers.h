// A point cloud in GPU buffers: chunks of at most `max_chunk_points` points, each one immutable
// buffer holding its attributes as consecutive sections (structure of arrays), positions as floats
// relative to the chunk's own origin.
//
// Why chunks: one buffer per point is absurd and one buffer for a billion points is past every
// driver's limits (llvmpipe binds at most 128 MiB to a shader); a chunk of 1 M points is 12 MB of
// positions. Why chunk-relative floats: a float holds 24 bits, 6 cm at a UTM easting of 500 km,
// but a chunk is small, and the world-to-chunk offset is applied in double on the CPU
// (see PointPass), so the GPU never sees a large coordinate.
//
// Points are sorted in Morton (Z) order before they are cut into chunks, so each chunk is a
// compact box (tight culling, good origins) and points that follow each other in a draw call are
// neighbours on screen, which is what makes llvmpipe's rasterizer fast (tiles stay in cache).
#pragma once

#include <epoxy/gl.h>

#include <array>
#include <cstdint>
#include <glm/glm.hpp>
#include <memory>
#include <span>
#include <vector>

#include "core/point_cloud.h"

namespace parallax {

struct DrawSet;  // render/draw_set.h

// Points per batch: the compute rasterizer's unit of work and of culling (one workgroup each).
// Consecutive points in the chunk's (Morton) order, so a batch is a compact box.
inline constexpr std::uint32_t kBatchPoints = 4096;

struct PointUploadOptions {
  // 256 K: a chunk is the smallest part progressive refinement draws of a point file, and one
  // of 1 M points alone took 60-110 ms of llvmpipe's time, past the viewer's 66.7 ms moving
  // frame; 8 draws of 256 K cost a whole frame what 2 of 1 M do (render/NOTES.md).
  std::uint32_t max_chunk_points = 1u << 18;
  bool morton_order = true;  // false keeps file order (benchmarks compare both)
};

// The per-point attribute sections of a chunk's buffer; absent attributes have no section.
struct PointChunk {
  GLuint buffer = 0;
  std::uint32_t count = 0;
  glm::dvec3 origin{0.0};  // world coordinates that chunk-relative position (0, 0, 0) stands for
  Bounds3 bounds;          // world coordinates
  // Byte offsets in `buffer` of: vec3 float positions, rgba8 colours, int 2_10_10_10 normals,
  // 8-byte extras (uint16 unorm intensity, uint8 classification, uint8 returns: return number in
  // the low 4 bits, number of returns in the high 4, each clamped to 15; float spacing), and,
  // when the layout has GPS time, vec2 GPS times (below).
  std::size_t positions_offset = 0;
  std::size_t colors_offset = 0;
  std::size_t normals_offset = 0;
  std::size_t extras_offset = 0;
  // GPS time t of each point as two floats (hi, lo): hi = float(t - gps_base), lo = float(t -
  // gps_base - hi), with gps_base the chunk's smallest GPS time, in double. A float alone is
  // good to 64 s at t ~ 1e9; the pair holds t - gps_base exactly where it has at most 48
  // significant bits (a chunk spanning up to a year of GPS time at 1e9 s and its 0.12 us steps),
  // and compared as a pair (hi first) against a bound split the same way (render/filter_uniforms.h)
  // the GPU's test is the CPU's double test. Points without GPS time hold 0 with gps_base 0.
  std::size_t gps_offset = 0;
  double gps_base = 0.0;
  // Batches of kBatchPoints consecutive points (the last may be shorter): their boxes, as two
  // RGBA32F texels each (min xyz, max xyz; w unused) in chunk-relative coordinates, at
  // `batches_offset`. Only the compute rasterizer reads them (render/compute_rasterizer.h).
  std::size_t batches_offset = 0;
  std::uint32_t batch_count = 0;
  // The batches' box centres, chunk-relative, on the CPU: the compute rasterizer orders batches
  // by their depth each frame. Shared by the copies of the chunk; may be null (no order).
  std::shared_ptr<const std::vector<glm::vec3>> batch_centers;
  // The largest per-point spacing in the chunk (world units): bounds the adaptive point size of
  // its points, so that a rasterizer can tell ahead whether they stay small on screen.
  float max_spacing = 0.0f;
  // source_indices[i]: the index, in the PointCloud it was staged from, of the chunk's point i.
  // The GPU holds Morton-reordered chunk-relative floats, neither the file's order nor its
  // precision; picking (render/point_picker.h) reads the picked point back from the source
  // through this. 4 bytes a point on the CPU, shared by the copies of the chunk.
  std::shared_ptr<const std::vector<std::uint32_t>> source_indices;
};

// How a chunk's buffer is laid out and filled; the same for every chunk of one cloud or octree,
// so that one shader variant draws them all.
struct ChunkLayout {
  // Sections present. A section the cloud has no column for is filled with a default (white,
  // a zero normal), so a node that lacks an attribute the octree declares still draws.
  bool colors = false, normals = false;
  // Intensity is stored as unorm16 over [intensity_min, intensity_max] (clamped), so the range
  // must be the cloud's (or the octree's), never a single chunk's.
  float intensity_min = 0.0f, intensity_max = 1.0f;
  // A GPS time section (PointChunk::gps_offset), 8 bytes a point, when the cloud or octree has
  // GPS time: always there, so that a GPS time filter toggled in the viewer uploads nothing.
  bool gps_time = false;
  // > 0: every point gets this spacing (world units), e.g. an octree node's; 0: the local spacing
  // of the chunk's points in their draw order (localSpacing()).
  float uniform_spacing = 0.0f;
};

// A chunk built on the CPU and not uploaded yet: `chunk` is complete but for `buffer` (0), and
// `bytes` is the buffer's content. Building one needs no GL context, so any thread may do it.
struct StagedChunk {
  PointChunk chunk;
  std::vector<std::byte> bytes;
};

// The unorm16 value the buffers hold for intensity `value` (clamped to the layout's range).
std::uint16_t quantizeIntensity(float value, const ChunkLayout& layout);

// The (hi, lo) pair of PointChunk::gps_offset for GPS time `t` in a chunk based at `base`.
std::array<float, 2> splitGpsTime(double t, double base);

// Bytes given to the GL by uploadStagedChunk in this process, every thread and cloud together:
// tests assert that a filter change uploads nothing (it is uniforms only).
std::uint64_t uploadedPointBytes();

// Builds the chunk of cloud points `indices` (in that draw order). Thread-safe; uses TBB inside.
StagedChunk stagePointChunk(const PointCloud& cloud, std::span<const std::uint32_t> indices,
                            const ChunkLayout& layout);
// Creates the chunk's GL buffer from the staged bytes (needs a current context), frees the bytes
// and returns the chunk, now owning a buffer the caller deletes with glDeleteBuffers.
PointChunk uploadStagedChunk(StagedChunk& staged);

// Owns the GL buffers of one cloud; needs a current context for its whole life.
class GpuPointCloud {
 public:
  GpuPointCloud() = default;
  GpuPointCloud(const PointCloud& cloud, const PointUploadOptions& options = {});
  ~GpuPointCloud();
  GpuPointCloud(GpuPointCloud&& other) noexcept;
  GpuPointCloud& operator=(GpuPointCloud&& other) noexcept;
  GpuPointCloud(const GpuPointCloud&) = delete;
  GpuPointCloud& operator=(const GpuPointCloud&) = delete;

  const std::vector<PointChunk>& chunks() const { return chunks_; }
  std::uint64_t pointCount() const { return point_count_; }
  std::uint64_t gpuBytes() const { return gpu_bytes_; }
  const Bounds3& bounds() const { return bounds_; }
  bool hasColors() const { return has_colors_; }
  bool hasNormals() const { return has_normals_; }
  bool hasIntensity() const { return has_intensity_; }
  bool hasClassification() const { return has_classification_; }
  bool hasGpsTime() const { return layout_.gps_time; }
  // Median over the cloud of the local point spacing (world units), 0 for fewer than 2 points.
  double typicalSpacing() const { return typical_spacing_; }
  // Every chunk, in upload order, with the cloud's bounds and attributes (include
  // render/draw_set.h to use it). Points into this cloud: valid while it lives and is not moved.
  DrawSet drawSet() const;

 private:
  void release();

  std::vector<PointChunk> chunks_;
  std::uint64_t point_count_ = 0;
  std::uint64_t gpu_bytes_ = 0;
  Bounds3 bounds_;
  bool has_colors_ = false, has_normals_ = false, has_intensity_ = false;
  bool has_classification_ = false;
  bool intensity_integral_ =
      true;  // every intensity a whole number (filter bounds: filter_uniforms.h)
  ChunkLayout layout_;
  double typical_spacing_ = 0.0;
};

// The permutation that sorts the cloud's points in Morton order of their quantized positions
// (21 bits per axis, the coarsest bits of the cloud's extent). Exposed for tests and benchmarks.
std::vector<std::uint32_t> mortonOrder(const PointCloud& cloud);

// Local spacing of points already in a spatially coherent order: for each block of 32
// consecutive points, the median distance between neighbours in that order (world units).
std::vector<float> localSpacing(const std::vector<glm::dvec3>& ordered_positions);

}  // namespace parallax
