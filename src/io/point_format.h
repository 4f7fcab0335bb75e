// The format table: one row per point-file format, and everything that reads, writes, detects,
// describes, streams or lists point files asks it (point_file.h, lod's PointStream, `parallax
// info`, `convert`, the help texts, docs/FORMATS.md's list). Adding a format is its reader and
// writer, its tests and fuzz target, and one row (see NOTES.md "Adding a format").
//
// Rows are the built-in ones (point_formats.cpp, in detection order) followed by those added at
// run time with registerPointFormat (tests add a toy format that way).
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <ostream>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/attribute_selection.h"
#include "core/bounds.h"
#include "core/point_cloud.h"
#include "core/quantization.h"
#include "io/coordinate_system.h"
#include "io/point_chunk_source.h"

namespace parallax {

struct PointReadOptions;   // point_file.h
struct PointWriteOptions;  // point_file.h

// What a file's header says without reading its points. Formats state what they can: text
// files state nothing but what their layout names.
struct PointFileHeader {
  std::optional<std::uint64_t> point_count;  // absent: not stated (text)
  std::optional<Bounds3> bounds;             // the file's declared bounds (LAS)
  std::vector<std::string> attributes;       // the model's names, as a read would give them
  CoordinateSystem crs;                      // empty: none stated
};

struct FormatDescription;  // format_description.h: a format's own account of a file for `info`

// How a chunk source is opened by the octree builder.
struct ChunkSourceOptions {
  std::vector<std::string> text_columns;  // text files: as PointReadOptions::text_columns
  // The grid to put positions on when the format lets the caller choose (PLY, text: the
  // builder's counting pass found it); formats with their own (LAS) keep theirs. Null: the
  // format chooses.
  const Quantization* quantization = nullptr;
  // The attributes the builder keeps (PointReadOptions::attributes); every one by default.
  AttributeSelection attributes;
};

// One row of the table. Every function gets the file's path and reports bad input as InputError
// naming the file; the empty ones are what the format cannot do.
struct PointFormatEntry {
  std::string id;    // short, lower case, unique: "ply"; `info --json`'s "format"
  std::string name;  // in messages: "PLY", "text (XYZ/CSV/PTS)"
  // For the list of supported formats: "PLY (ascii, binary little and big endian; .ply)".
  std::string description;
  // Lower case with the dot, the usual one first: read by any of them, written by all of them.
  std::vector<std::string> extensions;
  // Detection by content: the file's first bytes (64 KiB, or the whole of a smaller file).
  // Exact signatures are tried first, in table order; a `fallback` row (text: any printable
  // bytes with numbers) only when no exact one matched.
  std::function<bool(std::span<const std::byte> head)> detect;
  bool fallback = false;

  std::function<PointFileHeader(const std::filesystem::path&)> header;
  // A count by a pass over the file, for formats whose header states none (text), and the
  // fewest bytes a point takes, so that a small file is known to be small without the pass.
  std::function<std::uint64_t(const std::filesystem::path&)> count_points;
  std::uint64_t min_point_bytes = 1;

  std::function<PointCloud(const std::filesystem::path&, const PointReadOptions&)> read;
  // About max_points points spread over the file, in a fraction of the time of the whole (a
  // first picture of a large file). Empty: the format cannot address points without reading
  // everything before them.
  std::function<PointCloud(const std::filesystem::path&, std::uint64_t max_points)> preview;
  std::function<std::unique_ptr<PointChunkSource>(const std::filesystem::path&,
                                                  const ChunkSourceOptions&)>
      open_chunks;
  // Whether reading this file's points again costs little beside what is done with them (local
  // records of fixed layout, copied or byte-swapped: LAS, binary PLY). The octree builder reads
  // such a file once per pass; any other (compressed, parsed from text, ...) it reads once and
  // keeps the decoded points for its later passes (lod/point_spill.h). Empty: never cheap.
  std::function<bool(const std::filesystem::path&)> rereads_cheaply;
  // `parallax info`'s account of the header; empty: the name alone.
  std::function<FormatDescription(const std::filesystem::path&)> describe;

  // Empty: the format is read only.
  std::function<void(const PointCloud&, const std::filesystem::path&, const PointWriteOptions&)>
      write;
  // What `write` would drop or change of `cloud`: one short phrase each; empty when all is kept.
  std::function<std::vector<std::string>(const PointCloud&, const std::filesystem::path&,
                                         const PointWriteOptions&)>
      write_losses;
  // Whether the written file carries the source's coordinate reference system.
  bool writes_crs = false;
  // Whether the records have a fixed layout at this path (no attribute order to choose with
  // PointWriteOptions::properties); empty: never.
  std::function<bool(const std::filesystem::path&)> fixed_layout;
};

// A format: a handle on its row, compared by id. The default one is unknown (no row).
class PointFormat {
 public:
  constexpr PointFormat() = default;
  explicit constexpr PointFormat(std::string_view id) : id_(id) {}

  // The built-in formats by name, for code and tests that ask about one of them; a format added
  // to the table needs no name here.
  static const PointFormat Ply, Las, Laz, Text, Unknown;

  std::string_view id() const { return id_; }
  bool known() const { return entry() != nullptr; }
  // The row; null for an unknown format.
  const PointFormatEntry* entry() const;

  friend bool operator==(PointFormat a, PointFormat b) { return a.id_ == b.id_; }
  friend std::ostream& operator<<(std::ostream& out, PointFormat format) {
    return out << (format.id_.empty() ? std::string_view("unknown") : format.id_);
  }

 private:
  std::string_view id_;  // the row's id (rows live as long as the program); empty: unknown
};

inline constexpr PointFormat PointFormat::Ply{"ply"};
inline constexpr PointFormat PointFormat::Las{"las"};
inline constexpr PointFormat PointFormat::Laz{"laz"};
inline constexpr PointFormat PointFormat::Text{"text"};
inline constexpr PointFormat PointFormat::Unknown{};

// Every row, built-in ones first, in detection order. Rows never move once listed.
std::vector<const PointFormatEntry*> pointFormats();

// Adds a row at the end of the table (after the built-in ones). Throws std::invalid_argument
// for an id already listed or a row without an id, name or detect function.
PointFormat registerPointFormat(PointFormatEntry entry);

// The format whose `detect` takes these first bytes; Unknown when none does.
PointFormat detectFormatOf(std::span<const std::byte> head);

// The format a path's extension names (case-insensitive); Unknown when none.
PointFormat formatOfExtension(const std::filesystem::path& path);

// "PLY, LAS, LAZ or text": the formats' short names for help texts.
std::string pointFormatNamesText();
// ".ply", ".las", ...: the extensions of every row that writes, in table order.
std::vector<std::string> writableExtensions();
// ".ply .las .laz .xyz .txt .csv .asc .pts": the same for help texts.
std::string writableExtensionsText();
// The formats with a preview (PointFormatEntry::preview): "PLY, LAS and LAZ".
std::string previewFormatNamesText();
// The table as the Markdown table of docs/FORMATS.md (`parallax info --formats`).
std::string pointFormatsMarkdown();

}  // namespace parallax
