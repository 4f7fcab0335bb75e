// Format detection, reading and writing of any supported point file through the format table
// (point_format.h), and the temporary-file output that every writer uses.
#pragma once

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/point_cloud.h"
#include "core/progress.h"
#include "io/pcd_header.h"
#include "io/point_format.h"

namespace parallax {

// The formats themselves are the rows of the format table (point_format.h); these functions
// pick the row and call it.

// "PLY", "LAS", "LAZ", "text (XYZ/CSV/PTS)", ...; "unknown".
std::string pointFormatName(PointFormat format);

// "supported formats: PLY (...), LAS 1.0-1.4 (...), text ..." for error messages: every row's
// description.
std::string supportedFormatsText();

// Detects the format from the file's first bytes (magic and header), not from its extension:
// the first row whose `detect` takes them (PointFormatEntry::detect: the line "ply" is PLY;
// "LASF" is LAS, or LAZ when the header says LASzip; a file whose first 64 KiB are printable
// text with a line of at least three numbers is text). Throws InputError when the file cannot
// be opened.
PointFormat detectPointFormat(const std::filesystem::path& path);

// The same for the first bytes of a file held in memory (as many as are at hand; 64 KiB suffice).
PointFormat detectPointFormatFromMemory(std::span<const std::byte> bytes);

// What the file's header says (count, declared bounds, attributes, CRS), read without the points.
// Throws InputError as the readers do, and for an unknown format.
PointFileHeader readPointFileHeader(const std::filesystem::path& path);

// The point count a file's header states, read without the points; std::nullopt for formats
// whose header states none (text: see countTextPoints in text_reader.h) and for anything that
// cannot be read (the caller's ordinary read reports why).
std::optional<std::uint64_t> headerPointCount(const std::filesystem::path& path);

struct PointReadOptions {
  Progress* progress = nullptr;  // advanced by points (PLY, LAS) or bytes (text)
  bool parallel = true;
  // Text files only: the columns' names ("x", "y", "z", "r", ..., "_" to skip one), overriding a
  // header line and the common layouts. Empty: from the file.
  std::vector<std::string> text_columns;
  // The attributes the caller uses (core/attribute_selection.h); formats that can skip the
  // others (LAZ) leave them out. Every attribute by default.
  AttributeSelection attributes;
};

// Reads a whole point file of any supported format. Throws InputError for unreadable or malformed
// files, and for an unknown format with the list of supported ones.
PointCloud readPointFile(const std::filesystem::path& path, const PointReadOptions& options = {});

// Whether readPointFilePreview samples files of `format` (its row has a preview: PLY, LAS, LAZ;
// not text, whose lines cannot be addressed without reading them all).
bool hasPointFilePreview(PointFormat format);

// About `max_points` points spread over a large file, read in a fraction of the time of the
// whole, for a first picture while its octree is built (ply_preview.h, readLasPreview,
// readLazPreview). Throws InputError as the readers do, and for a format without a preview.
PointCloud readPointFilePreview(const std::filesystem::path& path, std::uint64_t max_points);

// The points of `path` in chunks (its row's chunk source: point_chunk_source.h), for the
// out-of-core builder. Throws InputError as readPointFile does, and for a format without one.
std::unique_ptr<PointChunkSource> openPointChunks(const std::filesystem::path& path,
                                                  const ChunkSourceOptions& options = {});
// Whether reading the file's points again is cheap (its row's `rereads_cheaply`; false where the
// row does not say). Throws InputError as openPointChunks does.
bool rereadsCheaply(const std::filesystem::path& path);

// The format a path's extension asks for when writing (a row's extensions: .ply, .las, .laz,
// .xyz/.txt/.csv/.pts/.asc, ...); Unknown otherwise.
PointFormat formatForExtension(const std::filesystem::path& path);

struct PointWriteOptions {
  Progress* progress = nullptr;
  bool ply_ascii = false;  // PLY: ascii instead of binary little endian
  // LAS, LAZ: 2, 3 or 4 forces the version; 0 keeps a LAS source's or chooses (las_writer.h).
  int las_minor_version = 0;
  int las_point_format = -1;  // LAS, LAZ: 0-10 forces the point format; -1 keeps or chooses
  std::uint32_t laz_chunk_points = 50000;  // LAZ: points a chunk (laz_writer.h)
  // PCD: the DATA encoding (pcd_writer.h); ply_ascii also asks for ascii.
  PcdData pcd_data = PcdData::Binary;
  // PLY and text (not PTS): the attributes to write, in this order (PointCloud::attributeOrder);
  // empty: all, in the source's order. LAS and LAZ records have a fixed layout: a non-empty list
  // is an InputError there.
  std::vector<std::string> properties;
  // The file the cloud was read from, if any: a LAS or LAZ output keeps a LAS or LAZ source's
  // header fields, VLRs, EVLRs, point format and version (las_writer.h), and the losses name
  // what the output has no place for.
  std::filesystem::path source;
};

// What writing `cloud` to `path` would drop or change: one short phrase each ("alpha (LAS has no
// alpha)", ...). Empty when every attribute is kept exactly.
std::vector<std::string> describeWriteLosses(const PointCloud& cloud,
                                             const std::filesystem::path& path,
                                             const PointWriteOptions& options = {});

// Writes `cloud` in the format of `path`'s extension (formatForExtension). Throws InputError
// naming the supported extensions for any other, and std::runtime_error on I/O failure. The file
// appears under its name only when complete (temporary file + rename).
void writePointFile(const PointCloud& cloud, const std::filesystem::path& path,
                    const PointWriteOptions& options = {});

// A file written under a temporary name beside `path` (".NAME.partial-PID-N", partial_output.h)
// and renamed over it by `commit()`; if it is destroyed uncommitted (an exception), the temporary
// file is removed. Errors throw
// std::runtime_error with the path and the system's reason.
class OutputFile {
 public:
  explicit OutputFile(const std::filesystem::path& path);
  ~OutputFile();
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;

  void write(const void* data, std::size_t size);
  void write(std::string_view text) { write(text.data(), text.size()); }
  // Overwrites bytes already written (headers whose counts are known at the end).
  void writeAt(std::uint64_t offset, const void* data, std::size_t size);
  void commit();

 private:
  [[noreturn]] void fail(const char* what);

  std::filesystem::path path_;
  std::filesystem::path temp_;
  std::FILE* file_ = nullptr;
  bool committed_ = false;
};

}  // namespace parallax
