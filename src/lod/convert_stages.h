// The stages of the out-of-core conversion to Potree 2.0 (potree_converter.h runs them in order):
//
//   scan        (convert_count.cpp)        bounds, attribute layout, output quantization, cube
//   count       (convert_count.cpp)        points per cell of a 128^3 grid over the cube, merged
//                                          into chunks: the largest octree nodes that hold at most
//                                          the chunk size the memory budget allows
//   distribute  (convert_distribute.cpp)   every point, encoded once as an octree.bin record, into
//                                          its chunk's spill file
//   build       (convert_build_chunks.cpp) each chunk's subtree in memory (subtree_builder.h),
//                                          several chunks at once within the budget; all nodes
//                                          but the chunk's root go to octree.bin, in chunk order
//   top levels  (convert_top_levels.cpp)   the nodes above the chunks, sampled from the chunks'
//                                          roots, which are written with them
// Each stage reads the inputs (or the spill files) in batches, so memory depends on the batch
// and chunk sizes, never on the input's size.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/attribute_selection.h"
#include "core/bounds.h"
#include "core/point_cloud.h"
#include "core/point_filter.h"
#include "core/progress.h"
#include "io/coordinate_system.h"
#include "io/mapped_file.h"
#include "lod/octree_build_options.h"
#include "lod/point_spill.h"
#include "lod/potree_hierarchy_writer.h"
#include "lod/potree_layout.h"
#include "lod/sampler.h"

namespace parallax {

// A point file read in batches whatever its format, through the formats' chunk readers (PLY,
// LAS, LAZ, text), so memory holds one batch. Unknown formats throw InputError as readPointFile
// does. Every batch is in quantization(): LAS's and LAZ's header's; for PLY and text the
// reader's own choice (PLY: from a sample; text: exact, from a first pass over the positions),
// or `quantization` when given (a later pass over a file whose quantization an earlier pass
// found: text files are then not read twice).
//
// With a `filter`, batches hold only the points it keeps (core/point_filter.h; a file without
// classification is class 0): this is where every stage of the conversion reads its points, so
// the scan's bounds, the counts and the spacing describe the kept points only. pointCount()
// stays the file's count (the scan's progress total), the points of all batches together may be
// fewer.
class PointStream {
 public:
  //
  // With `attributes` (not every one), batches hold the positions and those attributes only
  // (core/attribute_selection.h): the format's reader is asked for them and for what the filter
  // tests, and the columns the filter alone needed are dropped after it.
  PointStream(const std::filesystem::path& path, const std::vector<std::string>& text_columns,
              const Quantization* quantization = nullptr, const PointFilter* filter = nullptr,
              const AttributeSelection& attributes = {});
  // The points of `source` as they are (a PointSpill's: already filtered).
  explicit PointStream(std::unique_ptr<PointChunkSource> source);
  ~PointStream();

  std::uint64_t pointCount() const;
  const Quantization& quantization() const;
  // The file's coordinate reference system (LAS: its projection records; PLY, text: none).
  const CoordinateSystem& crs() const;
  // The next at most `max_points` points (at least one); false at the end.
  bool next(PointCloud& batch, std::size_t max_points);

  // Whether restrictTo may start past the first point without reading what comes before: PLY
  // (ranges of known start) and LAS (fixed-size records). Text, LAZ (whose colour depth may be
  // settled only by a later batch) and octree inputs are read whole by one task.
  bool canSkip() const;
  // Limits the stream to the file's points [first, last) (counted before filtering; last <=
  // pointCount()), before the first next(). A `first` past 0 needs canSkip().
  void restrictTo(std::uint64_t first, std::uint64_t last);

  struct State;  // opaque (point_stream.cpp)

 private:
  bool nextUnfiltered(PointCloud& batch, std::size_t max_points);
  bool readNext(PointCloud& batch, std::size_t max_points);
  std::unique_ptr<State> state_;
};

struct ConvertInput {
  std::filesystem::path path;
  std::vector<std::string> text_columns;  // text files only (see point_file.h)
  PointFilter filter;                     // the points of this input that are converted
  // The attributes the octree keeps of this input (`convert --properties`); every one by
  // default. Formats that can skip the others (LAZ of formats 6-10: their layers) never decode
  // them; the attributes the filter tests are read for it and dropped after it.
  AttributeSelection attributes;
};

// Creates a progress sink for one stage ("counting", ...) over `total` points; may return null.
using ProgressFactory =
    std::function<std::unique_ptr<Progress>(const std::string& stage, std::uint64_t total)>;

struct ChunkPlan {
  std::string name;  // the chunk's octree node
  std::uint64_t points = 0;
};

struct ConvertPlan {
  std::uint64_t points = 0;
  Bounds3 bounds;  // tight, world units
  Bounds3 cube;    // the root node
  double spacing = 0.0;
  Quantization quantization;                      // of the output positions
  std::vector<Quantization> input_quantizations;  // each input's, as its first stream chose it
  CoordinateSystem crs;  // the inputs' (those that state one must agree); empty: none stated
  PotreeLayout layout;
  AttributeStats stats;                 // filled by distribute
  std::uint64_t batch_points = 0;       // points read at a time
  std::uint64_t max_chunk_points = 0;   // chunk size the memory budget allows
  static constexpr int kGridLevel = 7;  // the count grid is 2^7 cells a side
  static constexpr int kGridSide = 1 << kGridLevel;
  static constexpr std::size_t kGridCells = std::size_t(1) << (3 * kGridLevel);
  std::vector<std::int32_t> cell_chunk;  // count grid cell -> index into chunks, -1: empty
  std::vector<ChunkPlan> chunks;
  // Per input, its points as the scan decoded them, for the count and distribute passes; null:
  // the input is read again (its format rereads cheaply, or the scan was given no scratch
  // directory). Dropped after the distribute pass (releaseSpills).
  std::vector<std::shared_ptr<PointSpill>> spills;
  // OctreeBuildOptions::cancel, which the passes that get only the plan check once a batch.
  const std::atomic<bool>* cancel = nullptr;

  // The count grid cell of a quantized position (clamped into the grid). Inline: called per
  // point in two passes.
  std::size_t cellOf(const Int3& p) const {
    const double factor = double(kGridSide) / (cube.max[0] - cube.min[0]);
    auto cell = [&](int axis, std::int32_t value) {
      const double c = std::floor((quantization.toWorld(axis, value) - cube.min[axis]) * factor);
      return std::size_t(std::clamp(c, 0.0, double(kGridSide - 1)));
    };
    return cellIndex(cell(0, p.x), cell(1, p.y), cell(2, p.z));
  }
  // The count grid cell at column x, row y, layer z.
  static std::size_t cellIndex(std::size_t x, std::size_t y, std::size_t z) {
    return (x * kGridSide + y) * kGridSide + z;
  }
};

// octree.bin, written by the build stages at known offsets (see topLevelsSplit for the layout).
// `fail_after_bytes` (tests) throws once more than that many bytes would have been written, to
// simulate an interrupted conversion.
class OctreeBinWriter {
 public:
  enum class Open { kCreate, kExisting };  // kCreate truncates; kExisting keeps what is there
  OctreeBinWriter(const std::filesystem::path& path, std::uint64_t fail_after_bytes,
                  Open open = Open::kCreate);
  OctreeBinWriter(const OctreeBinWriter&) = delete;
  OctreeBinWriter& operator=(const OctreeBinWriter&) = delete;
  ~OctreeBinWriter();
  // Writes at the cursor, moves the cursor past the bytes, and returns where they start.
  std::uint64_t append(const std::byte* data, std::size_t size);
  // Writes at `offset`; the cursor stays.
  void writeAt(std::uint64_t offset, const std::byte* data, std::size_t size);
  void seek(std::uint64_t offset) { cursor_ = offset; }
  std::uint64_t cursor() const { return cursor_; }
  void close();
  // The end of the furthest byte written (with kExisting, at least the file's size when opened).
  std::uint64_t size() const { return size_; }

 private:
  std::filesystem::path path_;
  int fd_ = -1;
  std::uint64_t cursor_ = 0;
  std::uint64_t size_ = 0;
  std::uint64_t written_ = 0;
  std::uint64_t fail_after_ = 0;
};

// Where each chunk's nodes go in octree.bin, so that a build that knows the chunks' point counts
// (after the count stage) knows where to write without waiting for the builds before it: the
// chunks before the split (the first half of the points) from the file's start up, the chunks
// from the split on from its end (the total of the records, known) down, and the nodes above the
// chunks, written last, in the gap between, which they fill exactly (every chunk root's point
// ends in one of them). A distributed build then writes into the final file from both ends
// instead of into a part to be copied (distributed_tasks.cpp). Returns the first chunk of the
// upper side.
std::size_t topLevelsSplit(const std::vector<ChunkPlan>& chunks);

// Where a range of chunks is written: up from `at` in chunk order, or (descending) down from
// `at`, the last chunk's nodes ending there.
struct ChunkPlacement {
  bool descending = false;
  std::uint64_t at = 0;
};

// What the build stage keeps of each chunk: its root's points, for the top levels to sample.
struct ChunkRoot {
  std::string name;
  bool has_children = false;
  std::vector<std::byte> records;
};

// With a `scratch_dir`, the points of the inputs that do not reread cheaply
// (io/point_format.h) are kept for the later passes (ConvertPlan::spills): in memory within half
// the budget, the rest in scratch files there.
ConvertPlan scanInputs(const std::vector<ConvertInput>& inputs, const OctreeBuildOptions& options,
                       const ProgressFactory& progress,
                       const std::filesystem::path& scratch_dir = {});
// The stream a pass after the scan reads input `index` from: its spill, or the file again.
// `last_pass`: the spill's batches in memory are handed over and freed (distribute).
// `positions_only` (count): a spill hands out the positions alone; a file read again gives
// what its reader gives.
PointStream openPassStream(const ConvertPlan& plan, const std::vector<ConvertInput>& inputs,
                           std::size_t index, bool last_pass, bool positions_only = false);
// What scanInputs derives once the points, bounds, layout and input quantizations are known:
// the cube, spacing, output quantization, empty stats, batch and chunk sizes.
void finishScan(ConvertPlan& plan, const OctreeBuildOptions& options);
void countChunks(ConvertPlan& plan, const std::vector<ConvertInput>& inputs,
                 const ProgressFactory& progress);
// countChunks in two halves, for a count split over tasks: the points of one stream added to
// `counts` (kGridCells entries, indexed as cellOf), and the chunks of the summed counts
// (plan.chunks, plan.cell_chunk). Sums do not depend on the order the streams were counted in.
void countStream(const ConvertPlan& plan, PointStream& stream, std::vector<std::uint64_t>& counts,
                 Progress* bar);
void planChunks(ConvertPlan& plan, std::vector<std::uint64_t> counts);
void distributePoints(ConvertPlan& plan, const std::vector<ConvertInput>& inputs,
                      const std::filesystem::path& chunk_dir, const ProgressFactory& progress);
// distributePoints for one stream (a range of one input, `input` names it in errors): the
// spill files of its points in `shard_dir` (chunkFilePath; none for a chunk it has no point
// of), plan.stats widened by them. Returns the points each chunk received.
std::vector<std::uint64_t> distributeStream(ConvertPlan& plan, PointStream& stream,
                                            const std::filesystem::path& input,
                                            const std::filesystem::path& shard_dir, Progress* bar);
// Every chunk's nodes but its root, laid out as topLevelsSplit says; returns the roots in chunk
// order and leaves the writer's cursor at the gap the top levels fill.
std::vector<ChunkRoot> buildChunks(const ConvertPlan& plan, const std::filesystem::path& chunk_dir,
                                   const OctreeBuildOptions& options, const Sampler& sampler,
                                   OctreeBinWriter& octree, std::vector<PotreeNodeEntry>& entries,
                                   const ProgressFactory& progress);
// The nodes above the chunks and the chunks' final roots, appended at the writer's cursor:
// exactly the roots' records.
void buildTopLevels(const ConvertPlan& plan, std::vector<ChunkRoot>& roots, const Sampler& sampler,
                    OctreeBinWriter& octree, std::vector<PotreeNodeEntry>& entries);

// The spilled records of one chunk for the build: mapped from its spill file (the local build)
// or read from the shards of several tasks into one buffer (the distributed build).
struct ChunkRecords {
  std::unique_ptr<MappedFile> mapped;  // holds `data` when set
  ByteBuffer owned;                    // holds `data` otherwise
  const std::byte* data = nullptr;
  std::uint64_t size = 0;
  std::string origin;                  // the file(s) named in errors
  std::filesystem::path remove_after;  // removed once the chunk is built; empty: kept
};
using ChunkSource = std::function<ChunkRecords(std::size_t chunk)>;

// buildChunks for the chunks [first, last) of the plan, their records from `source`: their
// nodes but the roots written to `octree` as `placement` says (`entries` with offsets into it),
// the roots returned (index 0: chunk `first`). The same bytes for a chunk whatever range it is
// built in. The nodes take the range's records less its roots' (nonRootBytes).
std::vector<ChunkRoot> buildChunkRange(const ConvertPlan& plan, std::size_t first, std::size_t last,
                                       const ChunkSource& source, const OctreeBuildOptions& options,
                                       const Sampler& sampler, OctreeBinWriter& octree,
                                       ChunkPlacement placement,
                                       std::vector<PotreeNodeEntry>& entries, Progress* bar);
// The records of the chunks [first, last) in bytes (all of them: octree.bin's size).
std::uint64_t chunkRecordBytes(const ConvertPlan& plan, std::size_t first, std::size_t last);
// The bytes the chunks [first, last) wrote to octree.bin, from their roots.
std::uint64_t nonRootBytes(const ConvertPlan& plan, std::size_t first, std::size_t last,
                           const std::vector<ChunkRoot>& roots);

// Memory the build of a chunk takes per point: its record, the positions (twice), the Morton
// pairs and the index lists. The chunk size (3/8 of the budget) and the number of chunks built
// at once (three quarters of it together) are derived from it.
std::uint64_t chunkBuildBytesPerPoint(std::size_t record_size);

// The spill file of chunk `index`.
std::filesystem::path chunkFilePath(const std::filesystem::path& chunk_dir, std::size_t index);

// Copies the quantized positions out of `count` records.
Column<Int3> positionsOfRecords(const std::byte* records, std::uint64_t count,
                                std::size_t record_size);

}  // namespace parallax
