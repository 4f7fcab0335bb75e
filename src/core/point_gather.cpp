#include "core/point_gather.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cassert>
#include <cstring>
#include <type_traits>

namespace parallax {
namespace {

// Copies the same records from every column: `pick(i)` is the source record of target i.
template <class Pick>
PointCloud copyRecords(const PointCloud& cloud, std::uint64_t count, Pick pick) {
  PointCloud out;
  out.count = count;
  out.quantization = cloud.quantization;
  out.source = cloud.source;
  auto copyColumn = [&](const auto& from, auto& to) {
    if (from.empty()) return;
    to = std::remove_reference_t<decltype(to)>(count);
    tbb::parallel_for(tbb::blocked_range<std::uint64_t>(0, count, 1 << 14), [&](const auto& range) {
      for (std::uint64_t i = range.begin(); i != range.end(); ++i) to[i] = from[pick(i)];
    });
  };
  copyColumn(cloud.positions, out.positions);
  copyColumn(cloud.colors, out.colors);
  copyColumn(cloud.stored_colors, out.stored_colors);
  copyColumn(cloud.normals, out.normals);
  copyColumn(cloud.intensity, out.intensity);
  copyColumn(cloud.classification, out.classification);
  for (const ScalarColumn& column : cloud.scalars) {
    ScalarColumn copy{.name = column.name, .type = column.type};
    const std::size_t size = scalarSize(column.type);
    copy.data = ByteBuffer(count * size);
    tbb::parallel_for(tbb::blocked_range<std::uint64_t>(0, count, 1 << 14), [&](const auto& range) {
      for (std::uint64_t i = range.begin(); i != range.end(); ++i) {
        std::memcpy(copy.data.data() + i * size, column.data.data() + pick(i) * size, size);
      }
    });
    out.scalars.push_back(std::move(copy));
  }
  return out;
}

}  // namespace

PointCloud gatherPoints(const PointCloud& cloud, std::span<const std::uint32_t> indices) {
  return copyRecords(cloud, indices.size(), [&](std::uint64_t i) { return indices[i]; });
}

PointCloud gatherPoints(const PointCloud& cloud, std::span<const std::uint64_t> indices) {
  return copyRecords(cloud, indices.size(), [&](std::uint64_t i) { return indices[i]; });
}

PointCloud slicePoints(const PointCloud& cloud, std::uint64_t first, std::uint64_t count) {
  assert(first + count <= cloud.count && "slice past the end of the cloud");
  return copyRecords(cloud, count, [&](std::uint64_t i) { return first + i; });
}

}  // namespace parallax
