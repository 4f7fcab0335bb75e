// The decoded points of an input that is slow to read again (LAZ, text, E57, ...: the format
// table says which, io/point_format.h `rereads_cheaply`), kept by the conversion's first pass
// (the scan) for the passes after it (count, distribute), so that every point is decoded once.
//
// Batches are kept in memory while they fit in the budget given; the rest go, column after
// column, to a scratch file in the conversion's temporary directory, which the spill removes
// when it goes (the conversion drops it after the last pass; on failure the temporary directory
// goes with it). The file is this process's own: what describes each batch (its count, which
// columns, the scalars' names and types) stays in memory, the file holds only column bytes.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <vector>

#include "core/point_cloud.h"
#include "io/coordinate_system.h"
#include "io/point_chunk_source.h"

namespace parallax {

class PointSpill {
 public:
  // `file`: the scratch file, created at the first batch that does not fit `memory_bytes`.
  PointSpill(std::filesystem::path file, std::uint64_t memory_bytes, Quantization quantization,
             CoordinateSystem crs);
  PointSpill(const PointSpill&) = delete;
  PointSpill& operator=(const PointSpill&) = delete;
  ~PointSpill();  // removes the file

  // Keeps `batch` (its quantization must be the spill's).
  void add(PointCloud batch);

  // The kept points from the first, in the order they were added. With `last_pass` the batches
  // held in memory are handed over (moved) and freed as they go: no later read may follow.
  // With `positions_only` (the count pass) the batches hold their positions alone: the other
  // columns are neither copied nor read back (for 20 M points of format 3, 640 MB of copies
  // and fresh pages less). Not with `last_pass`.
  std::unique_ptr<PointChunkSource> read(bool last_pass, bool positions_only = false);

  std::uint64_t points() const { return points_; }
  std::uint64_t memoryBytes() const { return memory_used_; }
  std::uint64_t fileBytes() const { return file_bytes_; }
  const std::filesystem::path& file() const { return file_; }

  // What one batch holds, without its column bytes (in memory: the batch itself; in the file:
  // its shape, the columns at `offset`).
  struct Batch {
    PointCloud cloud;  // whole, or (in the file) with every column empty
    bool in_file = false;
    std::uint64_t offset = 0;
    bool has_colors = false, has_stored_colors = false, has_normals = false, has_intensity = false,
         has_classification = false;
  };

 private:
  friend class SpillReader;  // point_spill.cpp
  void writeToFile(Batch& entry, const PointCloud& batch);

  std::filesystem::path file_;
  std::uint64_t memory_budget_ = 0;
  std::uint64_t memory_used_ = 0;
  std::uint64_t file_bytes_ = 0;
  std::uint64_t points_ = 0;
  Quantization quantization_;
  CoordinateSystem crs_;
  int fd_ = -1;
  std::vector<Batch> batches_;
};

// The bytes a batch's columns take.
std::uint64_t pointCloudBytes(const PointCloud& cloud);

}  // namespace parallax
