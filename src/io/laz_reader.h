// Reading LAZ (LASzip-compressed LAS) files: point formats 0-5 through the point-wise codec
// (compressors 1 and 2), 6-10 through the layered one (compressor 3), LASzip's LAS 1.4
// compatibility mode, into the same columns as the LAS reader (las_reader.h has the mapping):
// a LAZ file reads exactly as its uncompressed twin.
//
// Chunks are independent, so they are decoded on every core, each through a per-thread buffer
// of one chunk's records straight into the columns. A file without a usable chunk table (a
// writer that was interrupted, a table cut off) is still read when its chunks have a fixed size:
// they are found by decoding them in order, on one core. Damage (a corrupt or truncated chunk, a
// lying table or header, an unknown compressor or item) is an InputError naming the file, the
// chunk, its byte offset and the first point affected.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "core/attribute_selection.h"
#include "core/point_cloud.h"
#include "core/progress.h"
#include "io/las_header.h"
#include "io/point_chunk_source.h"

namespace parallax {

struct LazReadOptions {
  Progress* progress = nullptr;  // advanced by points read
  bool parallel = true;          // all cores (TBB); false runs on the calling thread only
  // The columns filled; the others are absent, and in layered chunks (formats 6-10) their
  // layers are never read (laz::ChunkDecoder::selectFields). Positions always.
  AttributeSelection attributes;
};

// Reads every point. Throws InputError for malformed input.
PointCloud readLaz(const std::filesystem::path& path, const LazReadOptions& options = {});
PointCloud readLazFromMemory(std::span<const std::byte> bytes, const std::string& name,
                             const LazReadOptions& options = {});

// About `max_points` points of a LAZ file over the budget, for a first picture: whole chunks
// spread evenly through the file, decoded on every core, every k-th point kept so that the
// sample has the spacing of about twice as many. The whole file when it has at most
// `max_points` points.
PointCloud readLazPreview(const std::filesystem::path& path, std::uint64_t max_points);

// What `parallax info` shows of a LAZ file's compression.
struct LazSummary {
  int compressor = 0;            // 1 point-wise, 2 point-wise chunked, 3 layered chunked
  std::string compressor_name;   // "point-wise chunked"
  std::uint32_t chunk_size = 0;  // points a chunk; 0: variable (from the chunk table)
  std::uint64_t chunks = 0;
  std::string laszip_version;      // of the writer, "3.4.3"
  std::vector<std::string> items;  // "POINT10 v2 (20 bytes)", ...
  bool compatibility_mode = false;
  int record_format = 0;   // the point format of the decoded records (1.4's in compatibility mode)
  std::string table_note;  // empty, or why the chunk table was not used
};
// Reads the header, the laszip VLR and the chunk table (not the points). Throws InputError.
LazSummary summarizeLaz(const std::filesystem::path& path);

// Streams the points of a LAZ file in batches, in file order, holding at most one batch and
// one decoded chunk. Each batch's chunks are decoded in parallel. The quantization is the
// header's. Colours follow the 8-bit rule of las_reader.h as far as a stream can: it decides
// from a few chunks spread through the file; when a later chunk contradicts that (8-bit values
// in the sample, 16-bit ones later), the rest of this stream and every later stream of the same
// file (same path, size and time) use the 16-bit rule. (The octree builder reads a file in three
// passes and uses colours in the last only, so its colours are right.)
class LazChunkReader final : public PointChunkSource {
 public:
  // `attributes`: the columns each batch holds (as LazReadOptions::attributes).
  explicit LazChunkReader(const std::filesystem::path& path,
                          const AttributeSelection& attributes = {});
  ~LazChunkReader() override;
  LazChunkReader(LazChunkReader&&) noexcept;

  const LasHeader& header() const;  // of the records handed out (1.4 in compatibility mode)
  std::uint64_t pointCount() const override;
  const CoordinateSystem& crs() const override;  // the header's projection records
  const Quantization& quantization() const override;

  // Replaces `chunk` with the next at most `max_points` points (`max_points` > 0); false (and
  // an empty chunk) at the end.
  bool next(PointCloud& chunk, std::size_t max_points) override;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace parallax
