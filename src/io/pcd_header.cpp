#include "io/pcd_header.h"

#include <fast_float/fast_float.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <sstream>
#include <string_view>

#include "core/error.h"

namespace parallax {
namespace {

// 'text', quoted for a message, with what a terminal should not see escaped.
std::string quoted(std::string_view text) {
  return quoteInput(text);
}

// Beyond this a "header" is not one: a PCD header is a dozen short lines (FIELDS of a few hundred
// names at most).
constexpr std::size_t kMaxHeaderBytes = 1 << 20;

bool equalsNoCase(std::string_view a, std::string_view b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
           return std::tolower((unsigned char)x) == std::tolower((unsigned char)y);
         });
}

std::vector<std::string_view> splitWords(std::string_view line) {
  std::vector<std::string_view> words;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
    std::size_t start = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t' && line[i] != '\r') ++i;
    if (i > start) words.push_back(line.substr(start, i - start));
  }
  return words;
}

struct Parser {
  const std::string& file;
  std::uint64_t line = 0;
  std::string keyword;

  [[noreturn]] void fail(const std::string& expected, const std::string& found,
                         const std::string& hint = "") const {
    throw InputError({.file = file,
                      .line = line,
                      .element = "header",
                      .property = keyword,
                      .expected = expected,
                      .found = found,
                      .hint = hint});
  }

  std::uint64_t unsignedValue(std::string_view word, std::uint64_t max) const {
    std::uint64_t value = 0;
    auto [end, error] = std::from_chars(word.data(), word.data() + word.size(), value);
    if (error != std::errc() || end != word.data() + word.size() || value > max) {
      fail("a whole number from 0 to " + std::to_string(max), quoted(word));
    }
    return value;
  }

  double realValue(std::string_view word) const {
    double value = 0;
    auto result = fast_float::from_chars(word.data(), word.data() + word.size(), value);
    if (result.ec != std::errc() || result.ptr != word.data() + word.size() ||
        !std::isfinite(value)) {
      fail("a finite number", quoted(word));
    }
    return value;
  }
};

}  // namespace

const char* pcdDataName(PcdData data) {
  switch (data) {
    case PcdData::Ascii:
      return "ascii";
    case PcdData::Binary:
      return "binary";
    case PcdData::BinaryCompressed:
      return "binary_compressed";
  }
  return "?";
}

int PcdHeader::find(std::string_view name) const {
  for (std::size_t i = 0; i < fields.size(); ++i) {
    if (equalsNoCase(fields[i].name, name)) return int(i);
  }
  return -1;
}

PcdHeader parsePcdHeader(std::span<const std::byte> bytes, const std::string& file) {
  const std::string_view text(reinterpret_cast<const char*>(bytes.data()),
                              std::min(bytes.size(), kMaxHeaderBytes));
  PcdHeader header;
  Parser parser{file};
  bool seen_fields = false, seen_size = false, seen_type = false, seen_count = false;
  bool seen_width = false, seen_height = false, seen_points = false, seen_version = false;
  std::size_t pos = 0;
  const std::string hint =
      "a PCD header is VERSION, FIELDS, SIZE, TYPE, COUNT, WIDTH, HEIGHT, VIEWPOINT, POINTS and "
      "DATA lines, in this order (PCL's PCD 0.7)";
  auto needFields = [&](std::size_t got) {
    if (!seen_fields) parser.fail("a FIELDS line before " + parser.keyword, "none", hint);
    if (got != header.fields.size()) {
      parser.fail(std::to_string(header.fields.size()) + " values (one per field of FIELDS)",
                  std::to_string(got));
    }
  };
  while (true) {
    if (pos >= text.size()) {
      parser.line += 1;
      parser.keyword = "DATA";
      parser.fail("a DATA line ending the header",
                  bytes.size() > kMaxHeaderBytes ? "none in the first MiB" : "the end of the file",
                  hint);
    }
    const std::size_t newline = text.find('\n', pos);
    const std::size_t line_end = newline == std::string_view::npos ? text.size() : newline;
    const std::string_view line = text.substr(pos, line_end - pos);
    pos = newline == std::string_view::npos ? text.size() : newline + 1;
    parser.line += 1;
    const std::vector<std::string_view> words = splitWords(line);
    if (words.empty() || words[0].starts_with('#')) continue;
    parser.keyword = std::string(words[0]);
    std::transform(parser.keyword.begin(), parser.keyword.end(), parser.keyword.begin(),
                   [](unsigned char c) { return char(std::toupper(c)); });
    const std::string& key = parser.keyword;
    const std::span<const std::string_view> values(words.data() + 1, words.size() - 1);
    if (key == "VERSION") {
      if (values.size() != 1) parser.fail("one version (0.7)", std::to_string(values.size()));
      std::string_view v = values[0];
      if (v != "0.7" && v != ".7" && v != "0.6" && v != ".6" && v != "0.5" && v != ".5") {
        parser.fail("version 0.5, 0.6 or 0.7", quoted(v));
      }
      header.version = std::string(v.starts_with('.') ? "0" : "") + std::string(v);
      seen_version = true;
    } else if (key == "FIELDS" || key == "COLUMNS") {  // COLUMNS: PCD 0.5's name for FIELDS
      if (values.empty()) parser.fail("at least one field name", "none");
      header.fields.clear();
      for (std::string_view name : values) header.fields.push_back({.name = std::string(name)});
      seen_fields = true;
    } else if (key == "SIZE") {
      needFields(values.size());
      for (std::size_t i = 0; i < values.size(); ++i) {
        const std::uint64_t size = parser.unsignedValue(values[i], 8);
        if (size != 1 && size != 2 && size != 4 && size != 8) {
          parser.fail("a size of 1, 2, 4 or 8 bytes for field '" + header.fields[i].name + "'",
                      std::string(values[i]));
        }
        header.fields[i].size = std::uint32_t(size);
      }
      seen_size = true;
    } else if (key == "TYPE") {
      needFields(values.size());
      for (std::size_t i = 0; i < values.size(); ++i) {
        if (values[i].size() != 1 ||
            (values[i][0] != 'F' && values[i][0] != 'I' && values[i][0] != 'U')) {
          parser.fail("F, I or U for field '" + header.fields[i].name + "'", quoted(values[i]));
        }
        header.fields[i].type = values[i][0];
      }
      seen_type = true;
    } else if (key == "COUNT") {
      needFields(values.size());
      for (std::size_t i = 0; i < values.size(); ++i) {
        const std::uint64_t count = parser.unsignedValue(values[i], 1 << 20);
        if (count == 0)
          parser.fail("a count of at least 1 for field '" + header.fields[i].name + "'", "0");
        header.fields[i].count = std::uint32_t(count);
      }
      seen_count = true;
    } else if (key == "WIDTH" || key == "HEIGHT" || key == "POINTS") {
      if (values.size() != 1) parser.fail("one number", std::to_string(values.size()) + " values");
      const std::uint64_t value = parser.unsignedValue(values[0], std::uint64_t(1) << 48);
      if (key == "WIDTH") header.width = value, seen_width = true;
      if (key == "HEIGHT") header.height = value, seen_height = true;
      if (key == "POINTS") header.points = value, seen_points = true;
    } else if (key == "VIEWPOINT") {
      if (values.size() != 7) {
        parser.fail("7 numbers (tx ty tz qw qx qy qz)", std::to_string(values.size()));
      }
      for (std::size_t i = 0; i < 7; ++i) header.viewpoint[i] = parser.realValue(values[i]);
    } else if (key == "DATA") {
      if (values.size() != 1)
        parser.fail("one of ascii, binary, binary_compressed",
                    std::to_string(values.size()) + " words");
      if (equalsNoCase(values[0], "ascii")) {
        header.data = PcdData::Ascii;
      } else if (equalsNoCase(values[0], "binary")) {
        header.data = PcdData::Binary;
      } else if (equalsNoCase(values[0], "binary_compressed")) {
        header.data = PcdData::BinaryCompressed;
      } else {
        parser.fail("ascii, binary or binary_compressed", quoted(values[0]));
      }
      header.data_offset = pos;
      header.data_line = parser.line + 1;
      break;
    } else {
      parser.fail(
          "a PCD header keyword (VERSION FIELDS SIZE TYPE COUNT WIDTH HEIGHT VIEWPOINT "
          "POINTS DATA)",
          quoted(line), hint);
    }
  }
  // What DATA needs, checked at the DATA line.
  auto missing = [&](bool seen, const char* what) {
    if (seen) return;
    parser.keyword = what;
    parser.fail(std::string("a ") + what + " line before DATA", "none", hint);
  };
  missing(seen_fields, "FIELDS");
  missing(seen_size, "SIZE");
  missing(seen_type, "TYPE");
  missing(seen_width, "WIDTH");
  (void)seen_version;  // PCL writes it, but reads files without it
  if (!seen_height) header.height = 1;
  std::uint64_t product = 0;
  const bool overflow = __builtin_mul_overflow(header.width, header.height, &product);
  if (!seen_points && !overflow) header.points = product;
  (void)seen_count;  // absent: one value each
  std::uint64_t offset = 0;
  for (PcdField& field : header.fields) {
    if (field.type == 'F' && field.size != 4 && field.size != 8) {
      parser.keyword = "TYPE";
      parser.fail("a float of 4 or 8 bytes for field '" + field.name + "'",
                  "F of size " + std::to_string(field.size));
    }
    field.offset = std::uint32_t(offset);
    offset += std::uint64_t(field.size) * field.count;
    if (offset > (1u << 24))
      parser.fail("records of at most 16 MiB", std::to_string(offset) + " bytes");
  }
  header.record_size = std::uint32_t(offset);
  if (overflow || product != header.points) {
    parser.keyword = "POINTS";
    parser.fail("POINTS = WIDTH * HEIGHT = " + std::to_string(header.width) + " * " +
                    std::to_string(header.height),
                std::to_string(header.points));
  }
  return header;
}

std::string formatPcdHeader(const PcdHeader& header) {
  std::ostringstream out;
  out.imbue(std::locale::classic());
  out.precision(17);
  out << "# .PCD v0.7 - Point Cloud Data file format (written by Parallax)\n";
  out << "VERSION 0.7\nFIELDS";
  for (const PcdField& f : header.fields) out << ' ' << f.name;
  out << "\nSIZE";
  for (const PcdField& f : header.fields) out << ' ' << f.size;
  out << "\nTYPE";
  for (const PcdField& f : header.fields) out << ' ' << f.type;
  out << "\nCOUNT";
  for (const PcdField& f : header.fields) out << ' ' << f.count;
  out << "\nWIDTH " << header.width << "\nHEIGHT " << header.height << "\nVIEWPOINT";
  for (double v : header.viewpoint) out << ' ' << v;
  out << "\nPOINTS " << header.points << "\nDATA " << pcdDataName(header.data) << '\n';
  return out.str();
}

bool looksLikePcd(std::span<const std::byte> bytes) {
  const std::string_view text(reinterpret_cast<const char*>(bytes.data()),
                              std::min<std::size_t>(bytes.size(), 4096));
  std::size_t pos = 0;
  while (pos < text.size()) {
    std::size_t newline = text.find('\n', pos);
    std::string_view line = text.substr(
        pos, newline == std::string_view::npos ? std::string_view::npos : newline - pos);
    pos = newline == std::string_view::npos ? text.size() : newline + 1;
    std::vector<std::string_view> words = splitWords(line);
    if (words.empty() || words[0].starts_with('#')) continue;
    return words[0] == "VERSION" || words[0] == "FIELDS";
  }
  return false;
}

}  // namespace parallax
