// Reading plain-text point files: .xyz, .txt, .csv, .asc, .pts.
//
// Layout, decided from the start of the file:
//   - lines starting (after blanks) with '#' or "//" are comments; blank lines are skipped;
//   - values are separated by commas, else semicolons, else blanks (spaces, tabs), as found on
//     the first data line; CRLF line ends are accepted;
//   - PTS: a first line holding one integer is the point count, and later one-integer lines are
//     the counts of further scans (Leica PTS concatenates scans); they are skipped;
//   - the column names are, in order of precedence: TextReadOptions::columns, a header line (the
//     first non-comment line when it is not all numbers), the last comment line before the data
//     when it holds one name per column (CloudCompare writes "//X,Y,Z,R,G,B"), else the common
//     layouts by column count: 3 xyz, 4 xyz intensity, 6 xyz rgb, 7 xyz intensity rgb (PTS;
//     outside a .pts file xyz rgb intensity, CloudCompare's ASCII export, when columns 4-6 of
//     the first 1024 lines are integers 0..255 and column 7 is not always one),
//     9 xyz rgb nx ny nz; Open3D's fixed layouts by extension: .xyzn x y z nx ny nz, .xyzrgb
//     x y z r g b with colours as fractions 0..1 (scaled to 0..255; integers stay as they are).
// Names (case-insensitive): x y z; r g b [a] or red green blue [alpha]; nx ny nz or normal_x ...;
// intensity or i; classification or class; "_" skips a column; any other name is a scalar column
// (the LAS names of las_reader.h in their LAS types, anything else as double).
//
// Positions: per axis, when every value is written in plain decimal notation with at most 9
// decimals (the usual case), the scale is 10^-d (d = most decimals seen) and the offset 0, or a
// whole number near the centre when 0 does not fit, so each written value is held exactly and a
// LAS written from it gets the file's own resolution; otherwise a power-of-two scale
// (chooseQuantization, core/quantization.h: from the exact bounds for files of at most 64 Ki
// points, else from a sample of 4096 lines with a 16x margin, verified). Colours are rounded and
// clamped to 0..255.
//
// Memory: the columns, plus the pages of the input being parsed (the file is mapped and its
// pages released as blocks are passed). Positions go straight into their int32 columns: the
// quantization is chosen from a sample of lines taken while the lines are counted, and checked
// against every position after the parse (text_decoder.h says how it is mended when the sample
// was wrong).
#pragma once

#include <cstddef>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "core/point_cloud.h"
#include "core/progress.h"
#include "io/point_chunk_source.h"

namespace parallax {

struct TextReadOptions {
  std::vector<std::string> columns;  // empty: from the file (above)
  Progress* progress = nullptr;      // advanced by bytes read
  bool parallel = true;
  // Treat the first line as a PTS count when it is one integer, even without a .pts extension.
  bool pts = false;
};

// Reads every point. Throws InputError naming the file, line (1-based), column name, expected and
// found for: a line with the wrong number of values, a value that is not a number (or a
// non-finite position), no x, y or z column, an empty file.
PointCloud readText(const std::filesystem::path& path, const TextReadOptions& options = {});

// The same from bytes in memory; `name` stands for the file in messages (and its extension ".pts"
// turns on `pts`).
PointCloud readTextFromMemory(std::span<const std::byte> bytes, const std::string& name,
                              const TextReadOptions& options = {});

// The number of points (data lines) of a text file, counted without parsing them (the layout is
// detected as readText does, so comments, a header line and PTS counts are not counted). Throws
// what readText throws for a file whose first lines are not a text point file.
std::uint64_t countTextPoints(const std::filesystem::path& path,
                              const TextReadOptions& options = {});

// Streams the points of a text file in chunks, in file order, holding one chunk and the pages of
// the input it is parsing. The quantization is fixed before the first chunk: given, or the exact
// choice of readText, from a first pass that parses the positions alone (text has no header to
// say it). Only `columns` and `pts` of the options are used.
class TextChunkReader final : public PointChunkSource {
 public:
  // Throws InputError as readText does for the layout; `quantization`, when given, is used for
  // every chunk (a point outside it is an InputError).
  explicit TextChunkReader(const std::filesystem::path& path, const TextReadOptions& options = {},
                           const Quantization* quantization = nullptr);
  ~TextChunkReader() override;
  TextChunkReader(TextChunkReader&&) noexcept;

  std::uint64_t pointCount() const override;
  const Quantization& quantization() const override;
  // Replaces `chunk` with the next at most `max_points` points (`max_points` > 0); false (and an
  // empty chunk) at the end. Throws InputError for a bad line (its number and column).
  bool next(PointCloud& chunk, std::size_t max_points) override;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

// True when `bytes` (the start of a file) look like a text point file: no control bytes other
// than blanks and line ends in the first 64 KiB, and a line of at least three numbers.
bool looksLikeTextPoints(std::span<const std::byte> bytes);

}  // namespace parallax
