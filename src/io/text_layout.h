// Internal to the text reader (text_reader.h): the layout of a text point file, decided from its
// first lines (delimiter, column names and where they go, where the data starts), and the small
// line and token helpers the decoder shares with it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/scalar_type.h"

namespace parallax::text {

// Where a column's values go.
enum class Target { Skip, X, Y, Z, R, G, B, A, Nx, Ny, Nz, Intensity, Classification, Scalar };

struct ColumnSpec {
  std::string name;
  Target target = Target::Skip;
  std::size_t scalar = 0;  // index into cloud.scalars for Target::Scalar
};

struct Layout {
  char delimiter = ' ';  // ',' ';' or ' ' (any run of blanks)
  bool pts = false;      // one-integer lines are PTS scan counts, skipped
  // Colour values are fractions of full scale (0..1), not 0..255: Open3D's .xyzrgb. The decoder
  // multiplies them by this before rounding; 1 for every other layout.
  double color_scale = 1;
  std::vector<ColumnSpec> columns;
  std::vector<std::pair<std::string, ScalarType>> scalars;  // name and type of each Scalar column
  std::size_t body_offset = 0;                              // the first data line
  std::uint64_t body_line = 1;                              // its 1-based number

  bool has(Target target) const;
  // The last column holding x, y or z: a positions-only parse stops after it.
  std::size_t lastPositionColumn() const;
};

inline bool isBlank(char c) {
  return c == ' ' || c == '\t' || c == '\r';
}

// A line without its end ('\n' and a '\r' before it).
struct Line {
  const char* begin;
  const char* end;
  const char* next;  // start of the following line
};

inline Line lineAt(const char* p, const char* end) {
  const char* nl = static_cast<const char*>(std::memchr(p, '\n', std::size_t(end - p)));
  const char* stop = nl ? nl : end;
  const char* content_end = stop;
  if (content_end > p && content_end[-1] == '\r') --content_end;
  return {p, content_end, nl ? nl + 1 : end};
}

// Blank lines, and comments: '#' or "//" after blanks.
bool isCommentOrBlank(const Line& line);

// Lines that hold no point: comments, blank lines, and in PTS files the scan counts (one integer
// alone on its line).
bool isSkippedLine(const Line& line, const Layout& layout);

// Decides the layout from the start of `text` (the rules are in text_reader.h). `columns`
// overrides the names; `pts` forces the PTS count lines (also on for a ".pts" file name). Throws
// InputError naming `file` and the line for: no data, a line of numbers that fits no common
// layout, names that do not match the values, no x, y or z column.
Layout detectLayout(std::string_view text, const std::string& file,
                    const std::vector<std::string>& columns, bool pts);

// Throws the InputError of a bad line: `file`, its 1-based `line`, the column name.
[[noreturn]] void failAt(const std::string& file, std::uint64_t line, const std::string& property,
                         const std::string& expected, const std::string& found,
                         const std::string& hint = "");

// True when `text` (the start of a file; `cut`: the file goes on, so its last line may be
// partial) look like a text point file (see text_reader.h).
bool looksLikeTextPoints(std::string_view text, bool cut);

}  // namespace parallax::text
