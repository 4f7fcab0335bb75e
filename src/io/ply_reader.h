// Reading the points of a PLY file into the column model.
//
// The point element ("vertex") is read; every other element (faces of a mesh, edges, ...) is
// skipped. Property names are mapped to the model's columns:
//   x y z                                   -> positions (int32, quantized: core/quantization.h)
//   red green blue [alpha], r g b [a], diffuse_red ... (uchar, ushort scaled to 8 bits, or
//   float/double in 0..1)                   -> colors
//   nx ny nz, normal_x normal_y normal_z    -> normals
//   intensity, scalar_intensity             -> intensity
//   classification, scalar_classification   -> classification
//   any other scalar property               -> a ScalarColumn with its own name and type
// List properties of the point element are skipped.
#pragma once

#include <cstddef>
#include <filesystem>
#include <memory>
#include <span>
#include <string>

#include "core/point_cloud.h"
#include "core/progress.h"
#include "io/ply_header.h"
#include "io/point_chunk_source.h"

namespace parallax {

struct PlyReadOptions {
  Progress* progress = nullptr;  // advanced by points read
  bool parallel = true;          // all cores (TBB); false runs on the calling thread only
};

// Reads the whole point element. Throws InputError for any malformed input (see ply_header.h and
// the checks listed in ply_reader.cpp); never allocates more than the file's size justifies.
PointCloud readPly(const std::filesystem::path& path, const PlyReadOptions& options = {});

// The same from bytes in memory; `name` stands for the file in messages.
PointCloud readPlyFromMemory(std::span<const std::byte> bytes, const std::string& name,
                             const PlyReadOptions& options = {});

// Streams the points of a PLY file in chunks, in file order, holding only one chunk.
//
// The quantization is fixed before the first chunk: chosen from a strided sample of the points
// with a margin, or given by the caller (e.g. from a counting pass). A point that does not fit it
// raises InputError with a hint to pass exact bounds; `readPly` never has this limitation.
class PlyChunkReader final : public PointChunkSource {
 public:
  explicit PlyChunkReader(const std::filesystem::path& path);
  ~PlyChunkReader() override;
  PlyChunkReader(PlyChunkReader&&) noexcept;

  const PlyHeader& header() const;
  std::uint64_t pointCount() const override;
  const Quantization& quantization() const override;
  void setQuantization(const Quantization& quantization);

  // Replaces `chunk` with the next at most `max_points` points; false (and an empty chunk) at the
  // end. `max_points` must be positive.
  bool next(PointCloud& chunk, std::size_t max_points) override;
  // Steps over the next `count` points (fewer at the end) without handing them out: whole ranges
  // by their known start, the rest of one range decoded and dropped (a range is about 512 KB), so
  // a task can read points [first, last) of a large file without reading what comes before.
  bool canSkip() const override { return true; }
  void skip(std::uint64_t count) override;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace parallax
