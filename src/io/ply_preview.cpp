#include "io/ply_preview.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <vector>

#include "core/error.h"
#include "io/mapped_file.h"
#include "io/ply_decoder.h"
#include "io/ply_header.h"
#include "io/ply_reader.h"

namespace parallax {

namespace {

// Records are taken in runs: a run of consecutive records costs one page fault where single
// records at the same step would cost one each, and neighbouring records of a scan give the
// adaptive point size a local spacing to work with.
constexpr std::uint64_t kRunRecords = 64;

}  // namespace

PointCloud readPlyPreview(const std::filesystem::path& path, std::uint64_t max_points) {
  MappedFile file(path);
  const std::string& name = file.path();
  PlyHeader header = parsePlyHeader(file.bytes(), name);
  const int point_element = header.pointElement();
  if (point_element < 0 || header.elements[std::size_t(point_element)].count <= max_points) {
    return readPly(path);  // small enough (or no points: readPly names the problem)
  }
  const PlyElement& element = header.elements[std::size_t(point_element)];
  ply::PointLayout layout = ply::planPointLayout(element, name);
  ply::DecodeContext context{file.bytes(), name, header, layout, &file};

  // One range per run: the planner cuts the body into ranges of about the step's bytes, and
  // the first kRunRecords records of each are decoded.
  const std::uint64_t runs = std::max<std::uint64_t>(1, max_points / kRunRecords);
  const std::size_t body_bytes = file.size() - std::min(file.size(), header.body_offset);
  const std::size_t step_bytes = std::max<std::size_t>(1, body_bytes / runs);
  std::vector<ply::RecordRange> ranges = ply::planRanges(context, step_bytes, true);

  std::vector<std::uint64_t> first_index(ranges.size() + 1, 0);
  for (std::size_t i = 0; i < ranges.size(); ++i) {
    first_index[i + 1] = first_index[i] + std::min(kRunRecords, ranges[i].count);
  }
  Quantization quantization =
      chooseQuantization(ply::sampleBounds(context, ranges, ply::kQuantizationSamples),
                         ply::kQuantizationSampleMargin);
  PointCloud cloud = ply::allocatePointCloud(layout, first_index.back(), quantization);

  auto decodeAll = [&] {
    std::vector<Bounds3> raw(ranges.size());
    tbb::parallel_for(std::size_t(0), ranges.size(), [&](std::size_t i) {
      const std::uint64_t count = first_index[i + 1] - first_index[i];
      raw[i] = ply::decodeRange(context, ranges[i], count, cloud, first_index[i]).raw_bounds;
    });
    Bounds3 all;
    for (const Bounds3& b : raw) all.extend(b);
    return all;
  };
  Bounds3 raw = decodeAll();
  bool fits = true;
  for (int axis = 0; axis < 3 && !raw.empty(); ++axis) {
    fits = fits && quantization.fits(axis, raw.min[axis]) && quantization.fits(axis, raw.max[axis]);
  }
  if (!fits) {
    cloud.quantization = chooseQuantization(raw, 1.0);
    decodeAll();
  }
  cloud.computeBounds();
  return cloud;
}

}  // namespace parallax
