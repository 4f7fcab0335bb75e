#include "io/text_layout.h"

#include <fast_float/fast_float.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <span>

#include "core/column_names.h"
#include "core/error.h"
#include "core/url.h"
#include "io/las_reader.h"

namespace parallax::text {
namespace {

std::string lower(std::string_view text) {
  std::string out(text);
  for (char& c : out) c = char(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

}  // namespace

bool isCommentOrBlank(const Line& line) {
  const char* p = line.begin;
  while (p < line.end && isBlank(*p)) ++p;
  if (p == line.end) return true;
  return *p == '#' || (*p == '/' && p + 1 < line.end && p[1] == '/');
}

namespace {

// Splits [begin, end) at `delimiter` (' ' meaning runs of blanks); blanks around values are
// trimmed and a trailing delimiter at the end of the line is ignored. Calls f(token) per value.
template <class F>
void forEachToken(const char* begin, const char* end, char delimiter, F f) {
  const char* p = begin;
  if (delimiter == ' ') {
    while (true) {
      while (p < end && isBlank(*p)) ++p;
      if (p == end) return;
      const char* t = p;
      while (p < end && !isBlank(*p)) ++p;
      if (!f(std::string_view(t, std::size_t(p - t)))) return;
    }
  }
  while (p <= end) {
    const char* d = static_cast<const char*>(std::memchr(p, delimiter, std::size_t(end - p)));
    const char* stop = d ? d : end;
    const char* t = p;
    const char* e = stop;
    while (t < e && isBlank(*t)) ++t;
    while (e > t && isBlank(e[-1])) --e;
    if (!d && t == e && p != begin) return;  // trailing delimiter
    if (!f(std::string_view(t, std::size_t(e - t)))) return;
    if (!d) return;
    p = d + 1;
  }
}

std::vector<std::string_view> tokens(const Line& line, char delimiter) {
  std::vector<std::string_view> out;
  forEachToken(line.begin, line.end, delimiter, [&](std::string_view t) {
    out.push_back(t);
    return true;
  });
  return out;
}

bool parseNumber(std::string_view token, double& value) {
  const char* b = token.data();
  const char* e = b + token.size();
  if (b < e && *b == '+') ++b;
  if (b == e) return false;
  auto result = fast_float::from_chars(b, e, value);
  return result.ec == std::errc() && result.ptr == e;
}

bool isNumber(std::string_view token) {
  double ignored;
  return parseNumber(token, ignored);
}

bool isInteger(std::string_view token) {
  return !token.empty() &&
         std::all_of(token.begin(), token.end(), [](char c) { return c >= '0' && c <= '9'; });
}

char delimiterOf(const Line& line) {
  std::string_view text(line.begin, std::size_t(line.end - line.begin));
  if (text.find(',') != std::string_view::npos) return ',';
  if (text.find(';') != std::string_view::npos) return ';';
  return ' ';
}

ScalarType knownScalarType(const std::string& name) {
  using namespace las_names;
  for (const char* n : {kReturnNumber, kNumberOfReturns, kScanDirectionFlag, kEdgeOfFlightLine,
                        kClassificationFlags, kScannerChannel, kUserData}) {
    if (name == n) return ScalarType::UInt8;
  }
  if (name == kScanAngleRank) return ScalarType::Int8;
  if (name == kScanAngle) return ScalarType::Int16;
  if (name == kPointSourceId || name == kNir) return ScalarType::UInt16;
  return ScalarType::Float64;
}

Target targetFor(const std::string& raw) {
  static const std::pair<const char*, Target> kNames[] = {
      {column_names::kX, Target::X},
      {column_names::kY, Target::Y},
      {column_names::kZ, Target::Z},
      {"r", Target::R},
      {"g", Target::G},
      {"b", Target::B},
      {"a", Target::A},
      {column_names::kRed, Target::R},
      {column_names::kGreen, Target::G},
      {column_names::kBlue, Target::B},
      {column_names::kAlpha, Target::A},
      {column_names::kNx, Target::Nx},
      {column_names::kNy, Target::Ny},
      {column_names::kNz, Target::Nz},
      {"normal_x", Target::Nx},
      {"normal_y", Target::Ny},
      {"normal_z", Target::Nz},
      {column_names::kIntensity, Target::Intensity},
      {"i", Target::Intensity},
      {column_names::kClassification, Target::Classification},
      {"class", Target::Classification},
      {"_", Target::Skip},
      {"skip", Target::Skip},
  };
  std::string name = lower(raw);
  for (const auto& [text, target] : kNames) {
    if (name == text) return target;
  }
  return Target::Scalar;
}

std::vector<std::string> commonLayout(std::size_t n) {
  switch (n) {
    case 3:
      return {column_names::kX, column_names::kY, column_names::kZ};
    case 4:
      return {column_names::kX, column_names::kY, column_names::kZ, column_names::kIntensity};
    case 6:
      return {column_names::kX, column_names::kY, column_names::kZ, "r", "g", "b"};
    case 7:
      return {column_names::kX,
              column_names::kY,
              column_names::kZ,
              column_names::kIntensity,
              "r",
              "g",
              "b"};
    case 9:
      return {column_names::kX,  column_names::kY,  column_names::kZ, "r", "g", "b",
              column_names::kNx, column_names::kNy, column_names::kNz};
    default:
      return {};
  }
}

// True when every value is written with a decimal point and lies in [0, 1]: colours as
// fractions. Colours written 0..255 are integers ("112"), so an .xyzrgb file of those keeps them.
bool unitFractions(std::span<const std::string_view> values) {
  return std::all_of(values.begin(), values.end(), [](std::string_view token) {
    double v = -1;
    return token.find('.') != std::string_view::npos && parseNumber(token, v) && v >= 0 && v <= 1;
  });
}

bool isColorValue(std::string_view token) {
  double v = -1;
  return parseNumber(token, v) && v >= 0 && v <= 255 && v == double(std::int64_t(v));
}

// Seven numbers a line without names are Leica's x y z intensity r g b (PTS, and Cyclone's text
// exports) or CloudCompare's x y z r g b and a scalar field (its ASCII export without a header,
// the scalar often the intensity). Read in the wrong order every value after z is shifted, in
// silence. CloudCompare's order is taken when, over the first lines, columns 4-6 are always
// colour values (integers 0..255) and column 7 is at least once not one; else Leica's.
bool colorsBeforeAScalar(std::string_view body, char delimiter) {
  const char* p = body.data();
  const char* const end = p + body.size();
  bool seventh_not_a_color = false;
  for (int lines = 0; p < end && lines < 1024; ++lines) {
    const Line line = lineAt(p, end);
    p = line.next;
    if (isCommentOrBlank(line)) continue;
    const auto values = tokens(line, delimiter);
    if (values.size() != 7) break;
    for (std::size_t i = 3; i < 6; ++i) {
      if (!isColorValue(values[i])) return false;
    }
    if (!isColorValue(values[6])) seventh_not_a_color = true;
  }
  return seventh_not_a_color;
}

}  // namespace

Layout detectLayout(std::string_view text, const std::string& file,
                    const std::vector<std::string>& columns, bool pts) {
  Layout layout;
  layout.pts = pts || lower(fileExtensionOf(file)) == ".pts";
  const char* p = text.data();
  const char* end = p + text.size();
  if (text.starts_with("\xEF\xBB\xBF")) p += 3;  // UTF-8 byte order mark
  std::uint64_t line_number = 1;
  std::string last_comment;
  std::vector<std::string> header;
  bool seen_content = false;
  for (; p < end; ++line_number) {
    Line line = lineAt(p, end);
    if (isCommentOrBlank(line)) {
      std::string_view body(line.begin, std::size_t(line.end - line.begin));
      auto start = body.find_first_not_of(" \t#/");
      if (start != std::string_view::npos) last_comment = std::string(body.substr(start));
      p = line.next;
      continue;
    }
    char delimiter = delimiterOf(line);
    auto values = tokens(line, delimiter);
    if (!seen_content && values.size() == 1 && isInteger(values[0])) {
      layout.pts = true;  // a PTS point count
      seen_content = true;
      p = line.next;
      continue;
    }
    seen_content = true;
    bool numeric = std::all_of(values.begin(), values.end(), isNumber);
    if (!numeric && header.empty()) {  // a header line (ignored when --columns names them)
      for (auto v : values) header.emplace_back(v);
      p = line.next;
      continue;
    }
    if (!numeric) {
      failAt(file, line_number, "", "a line of numbers",
             quoteInput(std::string_view(line.begin, std::size_t(line.end - line.begin))));
    }
    // The first data line: it fixes the delimiter and the number of columns.
    layout.delimiter = delimiter;
    layout.body_offset = std::size_t(p - text.data());
    layout.body_line = line_number;
    std::vector<std::string> names;
    if (!columns.empty()) {
      names = columns;
    } else if (!header.empty()) {
      names = header;
      if (names.size() == 1 && values.size() > 1) {  // "x y z" over comma-separated data
        names.clear();
        std::string h = header[0];
        Line hl{h.data(), h.data() + h.size(), nullptr};
        for (auto t : tokens(hl, ' ')) names.emplace_back(t);
      }
    } else if (!last_comment.empty()) {
      Line cl{last_comment.data(), last_comment.data() + last_comment.size(), nullptr};
      auto names_in_comment = tokens(cl, delimiter);
      bool all_names = names_in_comment.size() == values.size() &&
                       std::none_of(names_in_comment.begin(), names_in_comment.end(), isNumber);
      if (all_names) {
        for (auto t : names_in_comment) names.emplace_back(t);
      }
    }
    if (names.empty() && values.size() == 6) {
      // Open3D's fixed layouts, named by the extension alone (open3d/io/file_format/
      // FilePointCloud*: .xyzn holds x y z nx ny nz, .xyzrgb x y z r g b with colours as
      // fractions 0..1 printed "%.10f"). Read as the common 6-column layout, normals would be
      // colours and fractional colours rounded to 0 or 1.
      const std::string extension = lower(fileExtensionOf(file));
      if (extension == ".xyzn") {
        names = {column_names::kX,  column_names::kY,  column_names::kZ,
                 column_names::kNx, column_names::kNy, column_names::kNz};
      } else if (extension == ".xyzrgb" && unitFractions(std::span(values).subspan(3))) {
        names = commonLayout(6);
        layout.color_scale = 255;
      }
    }
    if (names.empty() && values.size() == 7 && !layout.pts &&
        colorsBeforeAScalar(std::string_view(p, std::size_t(end - p)), delimiter)) {
      // CloudCompare's ASCII export without a header: X Y Z R G B, then the scalar field.
      names = {column_names::kX,        column_names::kY, column_names::kZ, "r", "g", "b",
               column_names::kIntensity};
    }
    if (names.empty()) names = commonLayout(values.size());
    if (names.empty()) {
      failAt(file, line_number, "",
             "3, 4, 6, 7 or 9 values a line (xyz, xyzi, xyzrgb, xyzirgb, "
             "xyzrgb+normals), or a header line naming the columns",
             std::to_string(values.size()) + " values",
             "name the columns with --columns, e.g. --columns x,y,z,r,g,b,_");
    }
    if (names.size() != values.size()) {
      failAt(file, line_number, "",
             std::to_string(names.size()) + " values a line, one per column name",
             std::to_string(values.size()) + " values",
             "the header line or --columns names a different number of columns");
    }
    bool has[3] = {false, false, false};
    std::vector<Target> taken;
    for (const std::string& name : names) {
      ColumnSpec spec{name, targetFor(name), 0};
      // Names match in any case: a second column for a model column already given (a LAS extra
      // bytes field "Intensity" beside "intensity", as a LAS file written to text has them) is
      // a scalar under its own name, not a second value overwriting the first.
      if (spec.target != Target::Scalar && spec.target != Target::Skip) {
        if (std::find(taken.begin(), taken.end(), spec.target) != taken.end()) {
          spec.target = Target::Scalar;
        } else {
          taken.push_back(spec.target);
        }
      }
      if (spec.target == Target::Scalar) {
        spec.scalar = layout.scalars.size();
        layout.scalars.emplace_back(name, knownScalarType(name));
      }
      if (spec.target == Target::X) has[0] = true;
      if (spec.target == Target::Y) has[1] = true;
      if (spec.target == Target::Z) has[2] = true;
      layout.columns.push_back(std::move(spec));
    }
    if (!has[0] || !has[1] || !has[2]) {
      failAt(file, line_number, "", "columns named x, y and z", "no x, y or z column",
             "name the columns with --columns, e.g. --columns x,y,z");
    }
    return layout;
  }
  if (!columns.empty() || !header.empty()) {
    layout.body_offset = text.size();  // a header and no points: an empty cloud
    std::vector<std::string> names = columns.empty() ? header : columns;
    for (const std::string& name : names) layout.columns.push_back({name, targetFor(name), 0});
    return layout;
  }
  failAt(file, line_number, "", "a line of at least three numbers", "no data",
         "the file is empty or holds only comments");
}

bool isSkippedLine(const Line& line, const Layout& layout) {
  if (isCommentOrBlank(line)) return true;
  if (!layout.pts) return false;
  // Later scans' counts in a concatenated PTS file: one integer alone on its line.
  const char* b = line.begin;
  const char* e = line.end;
  while (b < e && isBlank(*b)) ++b;
  while (e > b && isBlank(e[-1])) --e;
  return isInteger(std::string_view(b, std::size_t(e - b)));
}

bool looksLikeTextPoints(std::string_view text, bool cut) {
  for (char c : text) {
    auto u = static_cast<unsigned char>(c);
    if (u < 0x20 && c != '\n' && c != '\r' && c != '\t') return false;
  }
  const char* p = text.data();
  const char* end = p + text.size();
  for (int lines = 0; p < end && lines < 100; ++lines) {
    Line line = lineAt(p, end);
    // The last line of a cut window may be partial: only whole lines count.
    if (line.next == end && cut) break;
    p = line.next;
    if (isCommentOrBlank(line)) continue;
    auto values = tokens(line, delimiterOf(line));
    if (values.size() >= 3 && std::all_of(values.begin(), values.end(), isNumber)) return true;
  }
  return false;
}

bool Layout::has(Target target) const {
  for (const ColumnSpec& spec : columns) {
    if (spec.target == target) return true;
  }
  return false;
}

std::size_t Layout::lastPositionColumn() const {
  std::size_t last = 0;
  for (std::size_t i = 0; i < columns.size(); ++i) {
    const Target t = columns[i].target;
    if (t == Target::X || t == Target::Y || t == Target::Z) last = i;
  }
  return last;
}

[[noreturn]] void failAt(const std::string& file, std::uint64_t line, const std::string& property,
                         const std::string& expected, const std::string& found,
                         const std::string& hint) {
  throw InputError({.file = file,
                    .line = line,
                    .property = property,
                    .expected = expected,
                    .found = found,
                    .hint = hint});
}

}  // namespace parallax::text
