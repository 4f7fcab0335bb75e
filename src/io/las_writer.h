// Writing PointClouds as uncompressed LAS 1.0-1.4 (and, with laz_chunk_points, LAZ).
//
// Positions are written as the cloud's own int32 values with its quantization as the header's
// scale and offset: nothing is re-rounded.
//
// From a LAS or LAZ source (LasWriteOptions::source, which `parallax convert` sets), the records
// are kept: the source's point format and version, its system identifier, generating software,
// GUID, global encoding, file source ID and creation date, every VLR and EVLR (but its LASzip
// and COPC records, which describe the source's compression and layout), its extra bytes at
// their offsets with their descriptions (scaled ones stored back as raw = (value - offset) /
// scale), and colours as stored (PointCloud::stored_colors). A format or version changes only
// when asked (minor_version, point_format) or when the source's cannot hold what the cloud has;
// the plan then says which field forced it (LasWritePlan::changes).
//
// Without a source the point format is chosen from the attributes:
//   LAS 1.2: 0, +gps_time 1, +colors 2, both 3
//   LAS 1.4: 6, +colors 7, +nir 8 (GPS time is always present in 6-10)
// Version 1.4 is chosen (when not forced) if the cloud needs it: a scan_angle (int16),
// scanner_channel or nir column, classes above 31, return numbers or counts above 7, the overlap
// flag, or more than 2^32 - 1 points.
//
// Scalar columns with the names the LAS reader gives (las_reader.h), case-insensitively and
// ignoring '_' and a "scalar_" prefix (so PDAL's ReturnNumber and CloudCompare's
// scalar_Return_Number match too), fill the LAS fields; synthetic, key_point, withheld and overlap
// columns fill the classification flags; the wave packet columns fill formats 4, 5, 9 and 10.
// Everything else is written as extra bytes with a LASF_Spec record 4 description, in its own
// type; names are cut to 32 characters. Normals first, as float NormalX NormalY NormalZ, the
// names CloudCompare and PDAL write and read back as normals (as the LAS reader does); from a
// source that held its normals as extra bytes, in its own bytes' places, names and types.
// Colours: stored_colors when the cloud has them (a LAS source's values, whatever their range),
// else the 8-bit colours scaled to 16 bits as c * 257 (255 -> 65535), as LAS 1.4 R15 asks
// ("normalized to 16 bits"): a PLY's uchar colours, which a LAS reader scales back. Colour is
// never scaled between LAS files. Alpha has no place in LAS and is dropped.
// Extra bytes are a LAS 1.4 feature; they are written in 1.0-1.3 files too (record length above
// the format's size), which common readers accept.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/point_cloud.h"
#include "core/progress.h"
#include "io/las_header.h"

namespace parallax {

struct LasWriteOptions {
  int minor_version = 0;  // 2, 3 or 4 forces the version; 0 keeps the source's, or chooses
  int point_format = -1;  // 0-10 forces the point format; -1 keeps the source's, or chooses
  // The LAS or LAZ header whose fields, records and layout the output keeps (above), with every
  // VLR and EVLR payload loaded (readLasHeaderWithRecords); null for a cloud from elsewhere.
  std::shared_ptr<const LasHeader> source;
  // Records copied as VLRs, e.g. the source's LASF_Projection records to keep the CRS. Records
  // with a payload over 65 535 bytes, and LASF_Spec record 4 (written here), are skipped.
  std::vector<LasVlr> vlrs;
  // Global encoding bit 0 (GPS time is adjusted standard time rather than GPS week seconds);
  // default false. `parallax convert` copies it from a LAS source.
  std::optional<bool> gps_time_standard;
  std::uint16_t file_source_id = 0;
  Progress* progress = nullptr;  // advanced by points written
  // 0: LAS. More: LAZ, the point data compressed in chunks of this many points (laz_writer.h;
  // writeLaz sets it).
  std::uint32_t laz_chunk_points = 0;
};

struct LasWritePlan {
  int minor_version = 2;
  int point_format = 0;
  std::size_t record_length = 0;
  std::vector<std::string> extra_bytes;  // names written as extra bytes, in record order
  std::vector<std::string> losses;       // what is dropped or changed, one phrase each
  // The source's format or version changed without being asked, each with the field that forced
  // it ("point format 3 -> 7: scanner_channel needs formats 6-10"); also listed in losses.
  std::vector<std::string> changes;
};

// The layout writeLas would use for `cloud`, and what it would drop or change.
LasWritePlan planLasWrite(const PointCloud& cloud, const LasWriteOptions& options = {});

// The records writeLas would write for the cloud.count points of `cloud` with `options`, into
// `out` (plan.record_length bytes each); returns the plan. For writers of LAS records of their
// own (the COPC writer encodes a node at a time): with options.minor_version set, clouds with
// the same columns get the same plan.
LasWritePlan encodeLasRecords(const PointCloud& cloud, const LasWriteOptions& options,
                              std::byte* out);
// The LASF_Spec record 4 that describes the extra bytes of that plan; nullopt without any.
std::optional<LasVlr> lasExtraBytesVlr(const PointCloud& cloud, const LasWriteOptions& options);

// The layout a file of `point_count` points whose columns and column maxima are `layout`'s
// would have (what LasStreamWriter decides at its construction).
LasWritePlan planLasWrite(const PointCloud& layout, const LasWriteOptions& options,
                          std::uint64_t point_count);

// A LAS or LAZ file (options.laz_chunk_points > 0, laz_writer.h) whose points arrive in batches,
// in file order, with memory bounded by a batch (and LAZ's chunks in flight) whatever the
// count: the bytes writeLas writes for the batches joined into one cloud. The header (counts,
// bounds, returns) is written by finish(), the one header encoder (encodeLasHeader); the file is
// written under a temporary name and renamed by finish() (removed if the writer is destroyed
// unfinished).
//
// The layout (version, point format, extra bytes) is decided at construction, as writeLas
// decides it for the whole cloud: from `layout`'s columns and quantization, and from their
// maxima (a classification above 31, return numbers above 7, the overlap flag need formats
// 6-10). So `layout` holds the columns of every batch to come and, for each, a value at least
// the maximum of what is to come for the columns those tests read; a one-point cloud holding
// each column's maximum does. `point_count` is the number of points to come (over 2^32 - 1
// needs LAS 1.4).
class LasStreamWriter {
 public:
  LasStreamWriter(const std::filesystem::path& path, const PointCloud& layout,
                  std::uint64_t point_count, const LasWriteOptions& options = {});
  ~LasStreamWriter();
  LasStreamWriter(const LasStreamWriter&) = delete;
  LasStreamWriter& operator=(const LasStreamWriter&) = delete;

  const LasWritePlan& plan() const;
  // Appends the batch's points: the layout's columns and quantization (asserted).
  void write(const PointCloud& batch);
  // The EVLRs, the header, the rename; asserts that point_count points were written.
  void finish();

 private:
  struct State;
  std::unique_ptr<State> state_;
};

// Writes to a temporary file beside `path`, renamed at the end. Throws std::runtime_error on I/O
// failure; asserts nothing about the cloud beyond its own invariants.
void writeLas(const PointCloud& cloud, const std::filesystem::path& path,
              const LasWriteOptions& options = {});

}  // namespace parallax
