// Stage 4 of the conversion (convert_stages.h): each chunk's subtree, built in memory with the
// same core as the in-memory octree (subtree_builder.h), written to octree.bin node by node.
// The chunk's root stays in memory: the top levels sample from it.
#include <cerrno>
#include <cstring>
#include <fstream>
#include <stdexcept>

#include "core/error.h"
#include "lod/convert_stages.h"
#include "lod/subtree_builder.h"

namespace parallax {
namespace {

ByteBuffer readSpillFile(const std::filesystem::path& path, std::uint64_t bytes) {
  ByteBuffer data(bytes);
  std::FILE* file = std::fopen(path.c_str(), "rb");
  if (!file && bytes == 0) return data;
  if (!file) throw std::runtime_error(path.string() + ": cannot open: " + std::strerror(errno));
  const std::size_t got = std::fread(data.data(), 1, bytes, file);
  std::fclose(file);
  if (got != bytes) {
    throw std::runtime_error(path.string() + ": expected " + std::to_string(bytes) +
                             " bytes, read " + std::to_string(got));
  }
  return data;
}

// The records of `indices`, gathered in order.
void gatherRecords(const std::byte* records, std::size_t record_size,
                   std::span<const std::uint32_t> indices, std::vector<std::byte>& out) {
  out.resize(indices.size() * record_size);
  for (std::size_t i = 0; i < indices.size(); ++i) {
    std::memcpy(out.data() + i * record_size, records + std::size_t(indices[i]) * record_size,
                record_size);
  }
}

}  // namespace

OctreeBinWriter::OctreeBinWriter(const std::filesystem::path& path, std::uint64_t fail_after_bytes)
    : path_(path), fail_after_(fail_after_bytes) {
  file_ = std::fopen(path.c_str(), "wb");
  if (!file_) throw std::runtime_error(path.string() + ": cannot create: " + std::strerror(errno));
}

OctreeBinWriter::~OctreeBinWriter() {
  if (file_) std::fclose(file_);
}

std::uint64_t OctreeBinWriter::append(const std::byte* data, std::size_t size) {
  if (fail_after_ > 0 && size_ + size > fail_after_) {
    // Write what fits first, so the interruption leaves a half-written file behind.
    std::fwrite(data, 1, std::size_t(fail_after_ - size_), file_);
    throw std::runtime_error(path_.string() + ": simulated interruption after " +
                             std::to_string(fail_after_) + " bytes");
  }
  if (size > 0 && std::fwrite(data, 1, size, file_) != size) {
    throw std::runtime_error(path_.string() + ": cannot write: " + std::strerror(errno));
  }
  const std::uint64_t offset = size_;
  size_ += size;
  return offset;
}

void OctreeBinWriter::close() {
  if (file_ && std::fclose(file_) != 0) {
    file_ = nullptr;
    throw std::runtime_error(path_.string() + ": cannot write: " + std::strerror(errno));
  }
  file_ = nullptr;
}

std::vector<ChunkRoot> buildChunks(const ConvertPlan& plan, const std::filesystem::path& chunk_dir,
                                   const OctreeBuildOptions& options, const Sampler& sampler,
                                   OctreeBinWriter& octree, std::vector<PotreeNodeEntry>& entries,
                                   const ProgressFactory& progress) {
  const std::size_t record = plan.layout.recordSize();
  std::unique_ptr<Progress> bar = progress ? progress("indexing", plan.points) : nullptr;
  std::vector<ChunkRoot> roots;
  roots.reserve(plan.chunks.size());
  std::vector<std::byte> node_records;
  for (std::size_t c = 0; c < plan.chunks.size(); ++c) {
    const ChunkPlan& chunk = plan.chunks[c];
    const auto path = chunkFilePath(chunk_dir, c);
    const ByteBuffer records = readSpillFile(path, chunk.points * record);
    std::filesystem::remove(path);
    const Column<Int3> positions = positionsOfRecords(records.data(), chunk.points, record);
    const int level = int(chunk.name.size()) - 1;
    const SubtreeFrame frame{.name = chunk.name,
                             .level = level,
                             .box = nodeBox(plan.cube, chunk.name),
                             .spacing = plan.spacing / double(1ull << level)};
    const BuiltSubtree built =
        buildSubtree(positions.span(), plan.quantization, frame, options, sampler);
    for (std::size_t n = 1; n < built.nodes.size(); ++n) {
      const BuiltNode& node = built.nodes[n];
      gatherRecords(records.data(), record, std::span(built.order).subspan(node.first, node.count),
                    node_records);
      const std::uint64_t offset = octree.append(node_records.data(), node_records.size());
      entries.push_back({.name = node.name,
                         .point_count = node.count,
                         .byte_offset = offset,
                         .byte_size = node_records.size()});
    }
    const BuiltNode& root = built.nodes.front();
    ChunkRoot kept{.name = chunk.name, .has_children = root.child_mask != 0};
    gatherRecords(records.data(), record, std::span(built.order).subspan(root.first, root.count),
                  kept.records);
    roots.push_back(std::move(kept));
    if (bar) bar->advance(chunk.points);
  }
  return roots;
}

}  // namespace parallax
