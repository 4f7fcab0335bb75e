#include "io/pts_reader.h"

#include <cstring>

#include "core/error.h"
#include "io/bytes_as_text.h"
#include "io/mapped_file.h"
#include "io/text_reader.h"

namespace parallax {
namespace {

struct Line {
  std::string_view text;
  std::size_t words = 0;
  bool integer = false;  // one word, all digits
  bool comment = false;  // '#' or "//" after blanks: skipped, as the text reader skips it
};

Line lineAt(std::string_view text, std::size_t& pos) {
  const std::size_t newline = text.find('\n', pos);
  const std::size_t end = newline == std::string_view::npos ? text.size() : newline;
  Line line{text.substr(pos, end - pos)};
  pos = newline == std::string_view::npos ? text.size() : newline + 1;
  bool in_word = false, digits = true;
  for (char c : line.text) {
    const bool blank = c == ' ' || c == '\t' || c == '\r' || c == ',';
    if (!blank && !in_word) ++line.words;
    if (!blank && (c < '0' || c > '9')) digits = false;
    in_word = !blank;
  }
  line.integer = line.words == 1 && digits;
  const std::size_t first = line.text.find_first_not_of(" \t\r");
  line.comment = first != std::string_view::npos &&
                 (line.text[first] == '#' || line.text.substr(first, 2) == "//");
  return line;
}

}  // namespace

std::uint64_t checkPtsCounts(std::string_view text, const std::string& name) {
  std::size_t pos = 0;
  std::uint64_t line_number = 0, total = 0;
  std::uint64_t count_line = 0, expected = 0, seen = 0;
  bool started = false;
  auto closeScan = [&](std::uint64_t at) {
    if (started && seen != expected) {
      throw InputError({.file = name,
                        .line = count_line,
                        .element = "scan count",
                        .expected = std::to_string(expected) + " point lines after it",
                        .found = std::to_string(seen) + " (up to line " + std::to_string(at) + ")",
                        .hint = "the file is truncated, or the count is wrong"});
    }
  };
  while (pos < text.size()) {
    const Line line = lineAt(text, pos);
    ++line_number;
    // Comments are no points: CloudCompare's -ADD_HEADER puts "//X Y Z R G B ..." before the
    // count line (which the text reader takes for the column names).
    if (line.words == 0 || line.comment) continue;
    if (line.integer) {
      closeScan(line_number - 1);
      started = true;
      count_line = line_number;
      expected = 0;
      for (char c : line.text) {
        if (c >= '0' && c <= '9') {
          if (expected > (UINT64_MAX - 9) / 10)
            expected = UINT64_MAX;  // reported as wrong below
          else
            expected = expected * 10 + std::uint64_t(c - '0');
        }
      }
      seen = 0;
      continue;
    }
    if (!started) {
      throw InputError({.file = name,
                        .line = line_number,
                        .element = "scan count",
                        .expected = "a first line holding the point count (PTS)",
                        .found = quoteInput(line.text),
                        .hint = "a text file of points named .pts: rename it .txt to read it as "
                                "text (CloudCompare writes the count with -ADD_PTS_COUNT)"});
    }
    ++seen, ++total;
  }
  closeScan(line_number);
  return total;
}

PointCloud readPtsFromMemory(std::span<const std::byte> bytes, const std::string& name,
                             const PtsReadOptions& options) {
  checkPtsCounts(bytesAsText(bytes), name);
  return readTextFromMemory(
      bytes, name, {.progress = options.progress, .parallel = options.parallel, .pts = true});
}

PointCloud readPts(const std::filesystem::path& path, const PtsReadOptions& options) {
  {
    const MappedFile file(path);
    checkPtsCounts(bytesAsText(file.bytes()), path.string());
  }
  return readText(path, {.progress = options.progress, .parallel = options.parallel, .pts = true});
}

bool looksLikePts(std::span<const std::byte> bytes) {
  const std::string_view text = bytesAsText(bytes.first(std::min<std::size_t>(bytes.size(), 4096)));
  std::size_t pos = 0;
  Line first{}, second{};
  while (pos < text.size() && first.words == 0) first = lineAt(text, pos);
  if (!first.integer) return false;
  if (pos >= text.size()) return false;
  second = lineAt(text, pos);
  for (char c : second.text) {
    if (!(std::isdigit((unsigned char)c) || c == ' ' || c == '\t' || c == '\r' || c == '-' ||
          c == '+' || c == '.' || c == 'e' || c == 'E' || c == ',')) {
      return false;
    }
  }
  return second.words == 3 || second.words == 4 || second.words == 6 || second.words == 7;
}

}  // namespace parallax
