// Format detection, reading and writing of any supported point file, and the temporary-file
// output that every writer uses.
#pragma once

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "core/point_cloud.h"
#include "core/progress.h"
#include "io/pcd_header.h"

namespace parallax {

enum class PointFormat { Ply, Las, Laz, Text, Pcd, Ptx, Pts, Unknown };

// "PLY", "LAS", "LAZ", "text (XYZ/CSV)", "PCD", "PTX", "PTS", "unknown".
const char* pointFormatName(PointFormat format);

// "supported formats: PLY (...), LAS 1.0-1.4 (...), text ..." for error messages.
const char* supportedFormatsText();

// Detects the format from the file's first bytes (magic and header), not from its extension:
// the line "ply" (blanks after it and CR LF allowed) is PLY; "LASF" is LAS, or LAZ when the header
// says LASzip; a file whose first 64 KiB are printable text with a line of at least three numbers
// is text; "VERSION" or "FIELDS" header lines are PCD (pcd_header.h); PTX and PTS by their first
// lines (ptx_reader.h, pts_reader.h). A file named .pcd or .ptx whose content is no format is
// still given to that reader, which says what is wrong with it. Throws InputError when the file
// cannot be opened.
PointFormat detectPointFormat(const std::filesystem::path& path);

// The same for the first bytes of a file held in memory (as many as are at hand; 64 KiB suffice).
PointFormat detectPointFormatFromMemory(std::span<const std::byte> bytes);

// The point count a PLY or LAS file's header states, read without the points; std::nullopt for
// text files (no count without reading them: see countTextPoints in text_reader.h) and for
// anything that cannot be read (the caller's ordinary read reports why).
std::optional<std::uint64_t> headerPointCount(const std::filesystem::path& path);

struct PointReadOptions {
  Progress* progress = nullptr;  // advanced by points (PLY, LAS) or bytes (text)
  bool parallel = true;
  // Text files only: the columns' names ("x", "y", "z", "r", ..., "_" to skip one), overriding a
  // header line and the common layouts. Empty: from the file.
  std::vector<std::string> text_columns;
};

// Reads a whole point file of any supported format. Throws InputError for unreadable or malformed
// files, and for an unknown format with the list of supported ones.
PointCloud readPointFile(const std::filesystem::path& path, const PointReadOptions& options = {});

// Whether readPointFilePreview samples files of `format` (PLY, LAS, LAZ; not text, whose lines
// cannot be addressed without reading them all).
bool hasPointFilePreview(PointFormat format);

// About `max_points` points spread over a large file, read in a fraction of the time of the
// whole, for a first picture while its octree is built (ply_preview.h, readLasPreview,
// readLazPreview). Throws InputError as the readers do, and for a format without a preview.
PointCloud readPointFilePreview(const std::filesystem::path& path, std::uint64_t max_points);

// The format a path's extension asks for when writing: .ply, .las, .laz, .xyz/.txt/.csv/.asc, .pcd,
// .ptx, .pts;
// Unknown otherwise.
PointFormat formatForExtension(const std::filesystem::path& path);

struct PointWriteOptions {
  Progress* progress = nullptr;
  bool ply_ascii = false;     // PLY: ascii instead of binary little endian
  int las_minor_version = 0;  // LAS, LAZ: 2 or 4; 0 chooses from the attributes (las_writer.h)
  std::uint32_t laz_chunk_points = 50000;  // LAZ: points a chunk (laz_writer.h)
  // PCD: the DATA encoding (pcd_writer.h); ply_ascii also asks for ascii.
  PcdData pcd_data = PcdData::Binary;
  // PLY and text (not PTS): the attributes to write, in this order (PointCloud::attributeOrder);
  // empty: all, in the source's order. LAS and LAZ records have a fixed layout: a non-empty list
  // is an InputError there.
  std::vector<std::string> properties;
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
