// PointStream (convert_stages.h): batches from a format's chunk source (io/point_format.h) or
// from the nodes of a Potree directory, filtered and restricted to a range of points.
#include <algorithm>
#include <cassert>
#include <cstdint>
#include <optional>

#include "core/column_names.h"
#include "core/error.h"
#include "core/filter_attributes.h"
#include "core/point_gather.h"
#include "io/point_chunk_source.h"
#include "io/point_file.h"
#include "lod/convert_stages.h"
#include "lod/in_memory_octree.h"
#include "lod/octree_node_batches.h"
#include "lod/potree_reader.h"

namespace parallax {

namespace {

// A Potree directory as an input of the builder (an octree rebuilt: another cube or spacing):
// its nodes one after the other, each handed out whole or in slices.
class OctreeNodeSource final : public PointChunkSource {
 public:
  explicit OctreeNodeSource(const std::filesystem::path& path) : octree_(openPotree(path)) {
    expandWholeOctree(*octree_);
  }

  std::uint64_t pointCount() const override { return octree_->info().point_count; }
  const Quantization& quantization() const override { return octree_->info().quantization; }

  bool next(PointCloud& batch, std::size_t max_points) override {
    const auto nodes = octree_->nodes();
    while (next_point_ >= node_.count) {
      if (next_node_ >= nodes.size()) {
        batch = PointCloud{};
        return false;
      }
      node_ = octree_->loadNode(nodes[next_node_++]);
      next_point_ = 0;
    }
    const std::uint64_t n = std::min<std::uint64_t>(max_points, node_.count - next_point_);
    if (next_point_ == 0 && n == node_.count) {
      batch = std::move(node_);
      node_ = PointCloud{};
    } else {
      batch = slicePoints(node_, next_point_, n);
      next_point_ += n;
    }
    return true;
  }

 private:
  std::unique_ptr<Octree> octree_;
  std::size_t next_node_ = 0;
  PointCloud node_;
  std::uint64_t next_point_ = 0;
};

// Removes the columns of `batch` that `kept` does not select (positions stay). Readers that
// cannot skip an attribute (LAS, PLY, an octree's nodes) still fill it, and the filter may have
// needed one the output does not keep.
void keepOnly(PointCloud& batch, const AttributeSelection& kept) {
  if (kept.all()) return;
  if (!kept.wantsColor()) {
    batch.colors = {};
    batch.stored_colors = {};
  }
  if (!kept.wants(column_names::kNx)) batch.normals = {};
  if (!kept.wants(column_names::kIntensity)) batch.intensity = {};
  if (!kept.wants(column_names::kClassification)) batch.classification = {};
  std::erase_if(batch.scalars, [&](const ScalarColumn& c) { return !kept.wants(c.name); });
  std::erase_if(batch.source.order, [&](const std::string& name) { return !kept.wants(name); });
}

}  // namespace

struct PointStream::State {
  std::unique_ptr<PointChunkSource> source;  // the format's (io/point_format.h) or an octree's
  std::optional<PointFilter> filter;         // absent: every point
  std::uint64_t remaining = UINT64_MAX;      // points left before the end of restrictTo's range
  AttributeSelection kept;                   // the columns batches hold
};

PointStream::PointStream(const std::filesystem::path& path,
                         const std::vector<std::string>& text_columns,
                         const Quantization* quantization, const PointFilter* filter,
                         const AttributeSelection& attributes)
    : state_(std::make_unique<State>()) {
  if (filter && !filter->keepsAll()) state_->filter = *filter;
  state_->kept = attributes;
  AttributeSelection read = attributes;
  if (state_->filter) {
    for (std::string& name : attributesTested(*state_->filter)) read.add(std::move(name));
  }
  if (isPotreeDirectory(path)) {
    state_->source = std::make_unique<OctreeNodeSource>(path);
  } else {
    state_->source = openPointChunks(
        path, {.text_columns = text_columns, .quantization = quantization, .attributes = read});
  }
}
PointStream::PointStream(std::unique_ptr<PointChunkSource> source)
    : state_(std::make_unique<State>()) {
  state_->source = std::move(source);
}

PointStream::~PointStream() = default;

PointStream openPassStream(const ConvertPlan& plan, const std::vector<ConvertInput>& inputs,
                           std::size_t index, bool last_pass, bool positions_only) {
  if (index < plan.spills.size() && plan.spills[index]) {
    return PointStream(plan.spills[index]->read(last_pass, positions_only));
  }
  return PointStream(inputs[index].path, inputs[index].text_columns,
                     &plan.input_quantizations[index], &inputs[index].filter,
                     inputs[index].attributes);
}

std::uint64_t PointStream::pointCount() const {
  return state_->source->pointCount();
}

const Quantization& PointStream::quantization() const {
  return state_->source->quantization();
}

const CoordinateSystem& PointStream::crs() const {
  return state_->source->crs();
}

bool PointStream::canSkip() const {
  return state_->source->canSkip();
}

void PointStream::restrictTo(std::uint64_t first, std::uint64_t last) {
  assert(first <= last && last <= pointCount() && "PointStream::restrictTo: a range of the file");
  assert((first == 0 || canSkip()) && "PointStream::restrictTo: this format starts at point 0");
  if (first > 0) state_->source->skip(first);
  state_->remaining = last - first;
}

bool PointStream::next(PointCloud& batch, std::size_t max_points) {
  if (!state_->filter) {
    if (!nextUnfiltered(batch, max_points)) return false;
    keepOnly(batch, state_->kept);
    return true;
  }
  // Batches the filter empties are skipped: a stage never sees an empty batch.
  while (nextUnfiltered(batch, max_points)) {
    batch = filterPoints(batch, *state_->filter);
    keepOnly(batch, state_->kept);
    if (batch.count > 0) return true;
  }
  return false;
}

bool PointStream::nextUnfiltered(PointCloud& batch, std::size_t max_points) {
  if (state_->remaining == 0) {
    batch = PointCloud{};
    return false;
  }
  max_points = std::size_t(std::min<std::uint64_t>(max_points, state_->remaining));
  const bool more = readNext(batch, max_points);
  if (more) state_->remaining -= std::min<std::uint64_t>(batch.count, state_->remaining);
  return more;
}

bool PointStream::readNext(PointCloud& batch, std::size_t max_points) {
  return state_->source->next(batch, max_points);
}

}  // namespace parallax
