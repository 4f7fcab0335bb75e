#include "render/point_buffers.h"

#include "core/morton.h"
#include "core/point_filter.h"
#include "render/draw_set.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstring>
#include <utility>

namespace parallax {

namespace {

std::uint32_t packNormal(const Float3& n) {
  auto component = [](float v) {
    const float clamped = std::isfinite(v) ? std::clamp(v, -1.0f, 1.0f) : 0.0f;
    return std::uint32_t(std::int32_t(std::lround(clamped * 511.0f))) & 0x3ffu;
  };
  return component(n.x) | component(n.y) << 10 | component(n.z) << 20;
}

constexpr std::size_t kExtraBytes = 8;
constexpr std::size_t kSpacingBlock = 32;

std::size_t alignUp(std::size_t v) {
  return (v + 255) & ~std::size_t(255);
}

// LSD radix sort on the 63-bit key, 11 bits a pass, stable (equal keys keep file order). Three
// to four times faster than a comparison sort of the pairs here, and passes whose digit is the
// same for every key (the high bits of a small cloud) are skipped.
void radixSort(std::vector<std::pair<std::uint64_t, std::uint32_t>>& items) {
  constexpr int kBits = 11, kBuckets = 1 << kBits;
  std::vector<std::pair<std::uint64_t, std::uint32_t>> scratch(items.size());
  std::vector<std::size_t> count(kBuckets);
  for (int shift = 0; shift < 63; shift += kBits) {
    std::fill(count.begin(), count.end(), 0);
    for (const auto& item : items) ++count[(item.first >> shift) & (kBuckets - 1)];
    if (std::find(count.begin(), count.end(), items.size()) != count.end()) continue;
    std::size_t sum = 0;
    for (std::size_t& c : count) sum += std::exchange(c, sum);
    for (const auto& item : items) scratch[count[(item.first >> shift) & (kBuckets - 1)]++] = item;
    items.swap(scratch);
  }
}

}  // namespace

std::uint16_t quantizeIntensity(float value, const ChunkLayout& layout) {
  const float span = layout.intensity_max > layout.intensity_min
                         ? layout.intensity_max - layout.intensity_min
                         : 1.0f;
  const float t = (value - layout.intensity_min) * (65535.0f / span);
  // NaN (a float intensity may be one) gives 0: converting it to an integer is undefined.
  return std::uint16_t((t >= 0.0f ? std::min(t, 65535.0f) : 0.0f) + 0.5f);
}

std::array<float, 2> splitGpsTime(double t, double base) {
  // Kept within a float's range (a double beyond it has no float); NaN stays NaN, which every
  // comparison fails, as the CPU's range test does.
  const double d = std::isnan(t - base) ? t - base : std::clamp(t - base, -1e30, 1e30);
  const float hi = float(d);
  return {hi, float(d - double(hi))};
}

namespace {
std::atomic<std::uint64_t> uploaded_bytes{0};
}  // namespace

std::uint64_t uploadedPointBytes() {
  return uploaded_bytes.load();
}

std::vector<std::uint32_t> mortonOrder(const PointCloud& cloud) {
  const std::size_t n = cloud.positions.size();
  std::int64_t lo[3] = {INT64_MAX, INT64_MAX, INT64_MAX}, hi[3] = {INT64_MIN, INT64_MIN, INT64_MIN};
  for (std::size_t i = 0; i < n; ++i) {
    const Int3 p = cloud.positions[i];
    lo[0] = std::min<std::int64_t>(lo[0], p.x), hi[0] = std::max<std::int64_t>(hi[0], p.x);
    lo[1] = std::min<std::int64_t>(lo[1], p.y), hi[1] = std::max<std::int64_t>(hi[1], p.y);
    lo[2] = std::min<std::int64_t>(lo[2], p.z), hi[2] = std::max<std::int64_t>(hi[2], p.z);
  }
  // One shift for all axes keeps the cells cubic in quantized units.
  std::uint64_t extent = 0;
  for (int a = 0; a < 3; ++a) extent = std::max<std::uint64_t>(extent, n ? hi[a] - lo[a] : 0);
  const int shift = std::max(0, int(std::bit_width(extent)) - 21);

  std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed(n);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n), [&](const auto& range) {
    for (std::size_t i = range.begin(); i < range.end(); ++i) {
      const Int3 p = cloud.positions[i];
      const std::uint64_t x = std::uint64_t(p.x - lo[0]) >> shift;
      const std::uint64_t y = std::uint64_t(p.y - lo[1]) >> shift;
      const std::uint64_t z = std::uint64_t(p.z - lo[2]) >> shift;
      keyed[i] = {spreadBits21(x) | spreadBits21(y) << 1 | spreadBits21(z) << 2, std::uint32_t(i)};
    }
  });
  radixSort(keyed);
  std::vector<std::uint32_t> order(n);
  for (std::size_t i = 0; i < n; ++i) order[i] = keyed[i].second;
  return order;
}

std::vector<float> localSpacing(const std::vector<glm::dvec3>& p) {
  std::vector<float> spacing(p.size(), 0.0f);
  const std::size_t blocks = (p.size() + kSpacingBlock - 1) / kSpacingBlock;
  // Split by whole blocks: a range of points starts where TBB's split fell, which depends on the
  // threads' timing, and blocks starting there gave another picture on every run.
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks, 16), [&](const auto& range) {
    std::vector<double> gaps;
    for (std::size_t block = range.begin(); block < range.end(); ++block) {
      const std::size_t start = block * kSpacingBlock;
      const std::size_t end = std::min(start + kSpacingBlock, p.size());
      gaps.clear();
      for (std::size_t i = start + 1; i < end; ++i) {
        const double gap = glm::length(p[i] - p[i - 1]);
        if (gap > 0) gaps.push_back(gap);  // duplicates say nothing about spacing
      }
      // A median ignores the jumps of the Morton curve between distant cells.
      double value = 0.0;
      if (!gaps.empty()) {
        std::nth_element(gaps.begin(), gaps.begin() + gaps.size() / 2, gaps.end());
        value = gaps[gaps.size() / 2];
      }
      for (std::size_t i = start; i < end; ++i) spacing[i] = float(value);
    }
  });
  return spacing;
}

StagedChunk stagePointChunk(const PointCloud& cloud, std::span<const std::uint32_t> indices,
                            const ChunkLayout& layout) {
  const std::size_t count = indices.size();
  StagedChunk staged;
  PointChunk& chunk = staged.chunk;
  chunk.count = std::uint32_t(count);
  chunk.source_indices =
      std::make_shared<const std::vector<std::uint32_t>>(indices.begin(), indices.end());

  std::vector<glm::dvec3> world(count);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count), [&](const auto& range) {
    for (std::size_t i = range.begin(); i < range.end(); ++i) {
      const std::size_t src = indices[i];
      world[i] = {cloud.worldX(src), cloud.worldY(src), cloud.worldZ(src)};
    }
  });
  for (const glm::dvec3& p : world) chunk.bounds.extend(p.x, p.y, p.z);
  const auto center = chunk.bounds.center();
  chunk.origin = count ? glm::dvec3{center[0], center[1], center[2]} : glm::dvec3{0.0};
  std::vector<float> spacing;
  if (layout.uniform_spacing <= 0.0f) spacing = localSpacing(world);

  std::size_t size = 0;
  chunk.positions_offset = size, size = alignUp(size + count * 12);
  if (layout.colors) chunk.colors_offset = size, size = alignUp(size + count * 4);
  if (layout.normals) chunk.normals_offset = size, size = alignUp(size + count * 4);
  chunk.extras_offset = size, size = alignUp(size + count * kExtraBytes);
  if (layout.gps_time) chunk.gps_offset = size, size = alignUp(size + count * 8);
  chunk.batch_count = std::uint32_t((count + kBatchPoints - 1) / kBatchPoints);
  chunk.batches_offset = size, size = alignUp(size + std::size_t(chunk.batch_count) * 32);

  staged.bytes.resize(size);
  std::byte* base = staged.bytes.data();
  auto* positions = reinterpret_cast<float*>(base + chunk.positions_offset);
  auto* colors = reinterpret_cast<Rgba8*>(base + chunk.colors_offset);
  auto* normals = reinterpret_cast<std::uint32_t*>(base + chunk.normals_offset);
  std::byte* extras = base + chunk.extras_offset;
  const bool has_colors = cloud.hasColors(), has_normals = cloud.hasNormals();
  const bool has_intensity = cloud.hasIntensity();
  const bool has_classification = cloud.hasClassification();
  // Returns as core/point_filter.h counts them: absent is return 1 of 1, above 15 is 15.
  const ScalarColumn* return_number = cloud.findScalar(filter_names::kReturnNumber);
  const ScalarColumn* number_of_returns = cloud.findScalar(filter_names::kNumberOfReturns);
  const auto nibble = [](const ScalarColumn* column, std::size_t i) {
    if (!column) return 1u;
    const double v = column->valueAsDouble(i);
    return std::isnan(v) ? 0u : std::uint32_t(std::clamp(std::round(v), 0.0, 15.0));
  };
  const ScalarColumn* gps_time =
      layout.gps_time ? cloud.findScalar(filter_names::kGpsTime) : nullptr;
  if (gps_time && count > 0) {
    chunk.gps_base = INFINITY;
    for (std::size_t i = 0; i < count; ++i) {
      chunk.gps_base = std::min(chunk.gps_base, gps_time->valueAsDouble(indices[i]));
    }
    if (!std::isfinite(chunk.gps_base)) chunk.gps_base = 0.0;
  }
  auto* gps = reinterpret_cast<float*>(base + chunk.gps_offset);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count), [&](const auto& range) {
    for (std::size_t i = range.begin(); i < range.end(); ++i) {
      const std::size_t src = indices[i];
      // The subtraction is done in double: only the small remainder becomes a float.
      positions[3 * i + 0] = float(world[i].x - chunk.origin.x);
      positions[3 * i + 1] = float(world[i].y - chunk.origin.y);
      positions[3 * i + 2] = float(world[i].z - chunk.origin.z);
      if (layout.colors) colors[i] = has_colors ? cloud.colors[src] : Rgba8{255, 255, 255, 255};
      if (layout.normals) normals[i] = has_normals ? packNormal(cloud.normals[src]) : 0u;
      const std::uint16_t intensity =
          has_intensity ? quantizeIntensity(cloud.intensity[src], layout) : std::uint16_t(0);
      const std::uint8_t classification =
          has_classification ? cloud.classification[src] : std::uint8_t(1);
      const float point_spacing = spacing.empty() ? layout.uniform_spacing : spacing[i];
      std::byte* extra = extras + i * kExtraBytes;
      std::memcpy(extra, &intensity, 2);
      std::memcpy(extra + 2, &classification, 1);
      extra[3] = std::byte(nibble(return_number, src) | nibble(number_of_returns, src) << 4);
      std::memcpy(extra + 4, &point_spacing, 4);
      if (layout.gps_time) {
        const auto [hi, lo] = gps_time ? splitGpsTime(gps_time->valueAsDouble(src), chunk.gps_base)
                                       : std::array<float, 2>{0.0f, 0.0f};
        gps[2 * i] = hi, gps[2 * i + 1] = lo;
      }
    }
  });
  // Batch boxes from the floats the GPU gets, so that culling a batch never drops a point.
  auto* batches = reinterpret_cast<float*>(base + chunk.batches_offset);
  std::vector<glm::vec3> centers(chunk.batch_count);
  tbb::parallel_for(std::uint32_t(0), chunk.batch_count, [&](std::uint32_t b) {
    float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    const std::size_t end = std::min<std::size_t>(count, std::size_t(b + 1) * kBatchPoints);
    for (std::size_t i = std::size_t(b) * kBatchPoints; i < end; ++i) {
      for (int a = 0; a < 3; ++a) {
        lo[a] = std::min(lo[a], positions[3 * i + a]);
        hi[a] = std::max(hi[a], positions[3 * i + a]);
      }
    }
    float* box = batches + std::size_t(b) * 8;
    box[0] = lo[0], box[1] = lo[1], box[2] = lo[2], box[3] = 0.0f;
    box[4] = hi[0], box[5] = hi[1], box[6] = hi[2], box[7] = 0.0f;
    centers[b] = 0.5f * (glm::vec3(lo[0], lo[1], lo[2]) + glm::vec3(hi[0], hi[1], hi[2]));
  });
  chunk.batch_centers = std::make_shared<const std::vector<glm::vec3>>(std::move(centers));
  chunk.max_spacing = layout.uniform_spacing;
  for (const float s : spacing) chunk.max_spacing = std::max(chunk.max_spacing, s);
  return staged;
}

PointChunk uploadStagedChunk(StagedChunk& staged) {
  PointChunk chunk = staged.chunk;
  glCreateBuffers(1, &chunk.buffer);
  // An empty chunk still gets a (1-byte) buffer: glNamedBufferStorage refuses size 0.
  const std::byte zero{0};
  glNamedBufferStorage(chunk.buffer, GLsizeiptr(std::max<std::size_t>(staged.bytes.size(), 1)),
                       staged.bytes.empty() ? &zero : staged.bytes.data(), 0);
  uploaded_bytes += staged.bytes.size();
  staged.bytes = {};
  return chunk;
}

GpuPointCloud::GpuPointCloud(const PointCloud& cloud, const PointUploadOptions& options) {
  const std::size_t n = cloud.positions.size();
  point_count_ = n;
  has_colors_ = cloud.hasColors();
  has_normals_ = cloud.hasNormals();
  has_intensity_ = cloud.hasIntensity();
  has_classification_ = cloud.hasClassification();

  std::vector<std::uint32_t> order;
  if (options.morton_order) {
    order = mortonOrder(cloud);
  } else {
    order.resize(n);
    for (std::size_t i = 0; i < n; ++i) order[i] = std::uint32_t(i);
  }

  ChunkLayout& layout = layout_;
  layout.colors = has_colors_, layout.normals = has_normals_;
  layout.gps_time = cloud.findScalar(filter_names::kGpsTime) != nullptr;
  if (has_intensity_ && n > 0) {
    const auto [lo, hi] = std::minmax_element(cloud.intensity.begin(), cloud.intensity.end());
    layout.intensity_min = *lo, layout.intensity_max = *hi > *lo ? *hi : *lo + 1.0f;
    intensity_integral_ = std::all_of(cloud.intensity.begin(), cloud.intensity.end(),
                                      [](float v) { return v == std::floor(v); });
  }

  std::vector<double> spacing_samples;
  const std::size_t chunk_size = std::max<std::uint32_t>(options.max_chunk_points, 1);
  for (std::size_t first = 0; first < n; first += chunk_size) {
    const std::size_t count = std::min(chunk_size, n - first);
    StagedChunk staged = stagePointChunk(cloud, std::span(order).subspan(first, count), layout);
    bounds_.extend(staged.chunk.bounds);
    for (std::size_t i = 0; i < count; i += 997) {
      float spacing = 0.0f;
      std::memcpy(&spacing, staged.bytes.data() + staged.chunk.extras_offset + i * kExtraBytes + 4,
                  4);
      spacing_samples.push_back(spacing);
    }
    gpu_bytes_ += staged.bytes.size();
    chunks_.push_back(uploadStagedChunk(staged));
  }
  if (!spacing_samples.empty()) {
    std::nth_element(spacing_samples.begin(), spacing_samples.begin() + spacing_samples.size() / 2,
                     spacing_samples.end());
    typical_spacing_ = spacing_samples[spacing_samples.size() / 2];
  }
}

void GpuPointCloud::release() {
  for (PointChunk& chunk : chunks_) glDeleteBuffers(1, &chunk.buffer);
  chunks_.clear();
}

GpuPointCloud::~GpuPointCloud() {
  release();
}

GpuPointCloud::GpuPointCloud(GpuPointCloud&& other) noexcept {
  *this = std::move(other);
}

GpuPointCloud& GpuPointCloud::operator=(GpuPointCloud&& other) noexcept {
  if (this == &other) return *this;
  release();
  chunks_ = std::exchange(other.chunks_, {});
  point_count_ = std::exchange(other.point_count_, 0);
  gpu_bytes_ = std::exchange(other.gpu_bytes_, 0);
  bounds_ = other.bounds_;
  has_colors_ = other.has_colors_, has_normals_ = other.has_normals_;
  has_intensity_ = other.has_intensity_, has_classification_ = other.has_classification_;
  intensity_integral_ = other.intensity_integral_;
  layout_ = other.layout_;
  typical_spacing_ = other.typical_spacing_;
  return *this;
}

DrawSet GpuPointCloud::drawSet() const {
  DrawSet set;
  set.items.reserve(chunks_.size());
  for (const PointChunk& chunk : chunks_) set.items.push_back({&chunk, 0.0f, 0, -1});
  set.bounds = bounds_;
  set.has_colors = has_colors_;
  set.has_normals = has_normals_;
  set.has_intensity = has_intensity_;
  set.has_classification = has_classification_;
  set.has_gps_time = layout_.gps_time;
  set.intensity_min = layout_.intensity_min, set.intensity_max = layout_.intensity_max;
  set.intensity_integral = intensity_integral_;
  set.typical_spacing = typical_spacing_;
  return set;
}

}  // namespace parallax
