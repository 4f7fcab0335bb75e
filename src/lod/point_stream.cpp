// PointStream (convert_stages.h): one batch interface over the formats' chunk readers.
#include <algorithm>
#include <cassert>
#include <cstdint>
#include <optional>
#include <type_traits>
#include <variant>

#include "core/error.h"
#include "core/point_gather.h"
#include "io/las_reader.h"
#include "io/laz_reader.h"
#include "io/pcd_reader.h"
#include "io/ply_reader.h"
#include "io/point_file.h"
#include "io/ptx_reader.h"
#include "io/text_reader.h"
#include "lod/convert_stages.h"
#include "lod/in_memory_octree.h"
#include "lod/octree_node_batches.h"
#include "lod/potree_reader.h"

namespace parallax {

struct PointStream::State {
  // A Potree directory as an input of the builder (an octree rebuilt: another cube or
  // spacing): its nodes one after the other, each handed out whole or in slices.
  struct OctreeNodes {
    std::unique_ptr<Octree> octree;
    std::size_t next_node = 0;
    PointCloud node;
    std::uint64_t next_point = 0;
  };
  std::variant<PlyChunkReader, LasChunkReader, LazChunkReader, TextChunkReader, PcdChunkReader,
               PtxChunkReader, OctreeNodes>
      reader;
  CoordinateSystem crs;
  std::optional<PointFilter> filter;     // absent: every point
  std::uint64_t remaining = UINT64_MAX;  // points left before the end of restrictTo's range
};

namespace {

PointStream::State openStream(const std::filesystem::path& path,
                              const std::vector<std::string>& text_columns,
                              const Quantization* quantization) {
  if (isPotreeDirectory(path)) {
    PointStream::State::OctreeNodes nodes;
    nodes.octree = openPotree(path);
    expandWholeOctree(*nodes.octree);
    return {std::move(nodes)};
  }
  switch (detectPointFormat(path)) {
    case PointFormat::Ply: {
      PlyChunkReader reader(path);
      if (quantization) reader.setQuantization(*quantization);
      return {std::move(reader)};
    }
    case PointFormat::Las:
      return {LasChunkReader(path)};  // the header's quantization, whatever is asked
    case PointFormat::Laz:
      return {LazChunkReader(path)};  // likewise
    case PointFormat::Text:
      return {TextChunkReader(path, {.columns = text_columns}, quantization)};
    case PointFormat::Pcd:
      return {PcdChunkReader(path, quantization)};
    case PointFormat::Ptx:
      return {PtxChunkReader(path, quantization)};
    case PointFormat::Pts:  // the text reader's, in PTS mode (pts_reader.h)
      return {TextChunkReader(path, {.columns = text_columns, .pts = true}, quantization)};
    default:
      // readPointFile gives the message for unknown formats.
      readPointFile(path);
      throw InputError({.file = path.string(), .expected = supportedFormatsText()});
  }
}

}  // namespace

PointStream::PointStream(const std::filesystem::path& path,
                         const std::vector<std::string>& text_columns,
                         const Quantization* quantization, const PointFilter* filter)
    : state_(std::make_unique<State>(openStream(path, text_columns, quantization))) {
  if (filter && !filter->keepsAll()) state_->filter = *filter;
  if (const auto* las = std::get_if<LasChunkReader>(&state_->reader)) {
    state_->crs = coordinateSystemOf(las->header());
  } else if (const auto* laz = std::get_if<LazChunkReader>(&state_->reader)) {
    state_->crs = coordinateSystemOf(laz->header());
  }
}
PointStream::~PointStream() = default;

std::uint64_t PointStream::pointCount() const {
  return std::visit(
      [](const auto& r) -> std::uint64_t {
        if constexpr (std::is_same_v<std::decay_t<decltype(r)>, State::OctreeNodes>) {
          return r.octree->info().point_count;
        } else {
          return r.pointCount();
        }
      },
      state_->reader);
}

const Quantization& PointStream::quantization() const {
  return std::visit(
      [](const auto& r) -> const Quantization& {
        if constexpr (std::is_same_v<std::decay_t<decltype(r)>, State::OctreeNodes>) {
          return r.octree->info().quantization;
        } else {
          return r.quantization();
        }
      },
      state_->reader);
}

const CoordinateSystem& PointStream::crs() const {
  return state_->crs;
}

bool PointStream::canSkip() const {
  return std::holds_alternative<PlyChunkReader>(state_->reader) ||
         std::holds_alternative<LasChunkReader>(state_->reader);
}

void PointStream::restrictTo(std::uint64_t first, std::uint64_t last) {
  assert(first <= last && last <= pointCount() && "PointStream::restrictTo: a range of the file");
  assert((first == 0 || canSkip()) && "PointStream::restrictTo: this format starts at point 0");
  if (auto* ply = std::get_if<PlyChunkReader>(&state_->reader)) ply->skip(first);
  if (auto* las = std::get_if<LasChunkReader>(&state_->reader)) las->skip(first);
  state_->remaining = last - first;
}

bool PointStream::next(PointCloud& batch, std::size_t max_points) {
  if (!state_->filter) return nextUnfiltered(batch, max_points);
  // Batches the filter empties are skipped: a stage never sees an empty batch.
  while (nextUnfiltered(batch, max_points)) {
    batch = filterPoints(batch, *state_->filter);
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
  return std::visit(
      [&](auto& r) -> bool {
        if constexpr (std::is_same_v<std::decay_t<decltype(r)>, State::OctreeNodes>) {
          const auto nodes = r.octree->nodes();
          while (r.next_point >= r.node.count) {
            if (r.next_node >= nodes.size()) {
              batch = PointCloud{};
              return false;
            }
            r.node = r.octree->loadNode(nodes[r.next_node++]);
            r.next_point = 0;
          }
          const std::uint64_t n = std::min<std::uint64_t>(max_points, r.node.count - r.next_point);
          if (r.next_point == 0 && n == r.node.count) {
            batch = std::move(r.node);
            r.node = PointCloud{};
          } else {
            batch = slicePoints(r.node, r.next_point, n);
            r.next_point += n;
          }
          return true;
        } else {
          return r.next(batch, max_points);
        }
      },
      state_->reader);
}

}  // namespace parallax
