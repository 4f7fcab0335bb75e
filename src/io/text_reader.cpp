#include "io/text_reader.h"

#include <fast_float/fast_float.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <exception>
#include <limits>

#include "core/error.h"
#include "io/decimal_parse.h"
#include "io/las_reader.h"
#include "io/mapped_file.h"

namespace parallax {
namespace {

enum class Target { Skip, X, Y, Z, R, G, B, A, Nx, Ny, Nz, Intensity, Classification, Scalar };

struct ColumnSpec {
  std::string name;
  Target target = Target::Skip;
  std::size_t scalar = 0;  // index into cloud.scalars for Target::Scalar
};

struct Layout {
  char delimiter = ' ';  // ',' ';' or ' ' (any run of blanks)
  bool pts = false;
  std::vector<ColumnSpec> columns;
  std::vector<std::pair<std::string, ScalarType>> scalars;
  std::size_t body_offset = 0;
  std::uint64_t body_line = 1;
};

bool isBlank(char c) {
  return c == ' ' || c == '\t' || c == '\r';
}

std::string lower(std::string_view text) {
  std::string out(text);
  for (char& c : out) c = char(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

// A line without its end ('\n' and a '\r' before it).
struct Line {
  const char* begin;
  const char* end;
  const char* next;  // start of the following line
};

Line lineAt(const char* p, const char* end) {
  const char* nl = static_cast<const char*>(std::memchr(p, '\n', std::size_t(end - p)));
  const char* stop = nl ? nl : end;
  const char* content_end = stop;
  if (content_end > p && content_end[-1] == '\r') --content_end;
  return {p, content_end, nl ? nl + 1 : end};
}

bool isCommentOrBlank(const Line& line) {
  const char* p = line.begin;
  while (p < line.end && isBlank(*p)) ++p;
  if (p == line.end) return true;
  return *p == '#' || (*p == '/' && p + 1 < line.end && p[1] == '/');
}

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
      {"x", Target::X},
      {"y", Target::Y},
      {"z", Target::Z},
      {"r", Target::R},
      {"g", Target::G},
      {"b", Target::B},
      {"a", Target::A},
      {"red", Target::R},
      {"green", Target::G},
      {"blue", Target::B},
      {"alpha", Target::A},
      {"nx", Target::Nx},
      {"ny", Target::Ny},
      {"nz", Target::Nz},
      {"normal_x", Target::Nx},
      {"normal_y", Target::Ny},
      {"normal_z", Target::Nz},
      {"intensity", Target::Intensity},
      {"i", Target::Intensity},
      {"classification", Target::Classification},
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
      return {"x", "y", "z"};
    case 4:
      return {"x", "y", "z", "intensity"};
    case 6:
      return {"x", "y", "z", "r", "g", "b"};
    case 7:
      return {"x", "y", "z", "intensity", "r", "g", "b"};
    case 9:
      return {"x", "y", "z", "r", "g", "b", "nx", "ny", "nz"};
    default:
      return {};
  }
}

[[noreturn]] void failAt(const std::string& file, std::uint64_t line, const std::string& property,
                         const std::string& expected, const std::string& found,
                         const std::string& hint = "") {
  throw InputError({.file = file,
                    .line = line,
                    .property = property,
                    .expected = expected,
                    .found = found,
                    .hint = hint});
}

Layout detectLayout(std::string_view text, const std::string& file,
                    const TextReadOptions& options) {
  Layout layout;
  layout.pts = options.pts || lower(std::filesystem::path(file).extension().string()) == ".pts";
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
    if (!options.columns.empty()) {
      names = options.columns;
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
    for (const std::string& name : names) {
      ColumnSpec spec{name, targetFor(name), 0};
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
  if (!options.columns.empty() || !header.empty()) {
    layout.body_offset = text.size();  // a header and no points: an empty cloud
    std::vector<std::string> names = options.columns.empty() ? header : options.columns;
    for (const std::string& name : names) layout.columns.push_back({name, targetFor(name), 0});
    return layout;
  }
  failAt(file, line_number, "", "a line of at least three numbers", "no data",
         "the file is empty or holds only comments");
}

// One block of whole lines, parsed by one task.
struct Block {
  std::size_t begin = 0, end = 0;  // byte range in the text
  std::uint64_t first_line = 0;    // 1-based number of its first line
  std::uint64_t first_point = 0;
  std::uint64_t points = 0;
  std::uint64_t lines = 0;
  Bounds3 bounds;
  int decimals[3] = {0, 0, 0};
  bool exponent = false;
};

bool skippedLine(const Line& line, const Layout& layout) {
  if (isCommentOrBlank(line)) return true;
  if (!layout.pts) return false;
  // Later scans' counts in a concatenated PTS file: one integer alone on its line.
  const char* b = line.begin;
  const char* e = line.end;
  while (b < e && isBlank(*b)) ++b;
  while (e > b && isBlank(e[-1])) --e;
  return isInteger(std::string_view(b, std::size_t(e - b)));
}

bool endsNumber(const char* p, const char* end, char delimiter) {
  return p == end || *p == ' ' || *p == '\t' || *p == '\r' || *p == '\n' || *p == delimiter;
}

// The token starting at `p`, for messages: up to the next blank, delimiter or line end.
std::string_view tokenAt(const char* p, const char* end, char delimiter) {
  const char* e = p;
  while (!endsNumber(e, end, delimiter)) ++e;
  return {p, std::size_t(e - p)};
}

// One pass over the block's bytes: no line is searched twice and no token is copied. fast_float
// reads each number where it stands (it stops at the first character that cannot continue a
// number), and the character after it must end the value.
void parseBlock(std::string_view text, const Layout& layout, const std::string& file, Block& block,
                double* world, PointCloud& cloud) {
  const char* p = text.data() + block.begin;
  const char* const end = text.data() + block.end;
  const char delimiter = layout.delimiter;
  const std::size_t n = layout.columns.size();
  Rgba8* colors = cloud.colors.data();
  Float3* normals = cloud.normals.data();
  float* intensity = cloud.intensity.data();
  std::uint8_t* classification = cloud.classification.data();
  std::uint64_t line_number = block.first_line;
  std::size_t point = block.first_point;
  auto skipBlanks = [&] {
    while (p < end && (*p == ' ' || *p == '\t')) ++p;
  };
  auto skipLine = [&] {
    const void* nl = std::memchr(p, '\n', std::size_t(end - p));
    p = nl ? static_cast<const char*>(nl) + 1 : end;
  };
  for (; p < end; ++line_number) {
    skipBlanks();
    if (p == end || *p == '\n' || *p == '\r' || *p == '#' ||
        (*p == '/' && p + 1 < end && p[1] == '/')) {
      skipLine();
      continue;
    }
    if (layout.pts) {
      // A further scan's count in a concatenated PTS file: one integer alone (as in pass 1).
      const char* c = p;
      while (c < end && *c >= '0' && *c <= '9') ++c;
      const char* d = c;
      while (d < end && (*d == ' ' || *d == '\t' || *d == '\r')) ++d;
      if (c > p && (d == end || *d == '\n')) {
        skipLine();
        continue;
      }
    }
    // Held here until the line is known to be a point (a PTS count line is not).
    double xyz[3] = {0.0, 0.0, 0.0};
    std::size_t column = 0;
    while (true) {
      if (column < n) {
        const ColumnSpec& spec = layout.columns[column];
        const char* q = p;
        if (spec.target == Target::Skip) {
          while (!endsNumber(p, end, delimiter)) ++p;
        } else {
          double v;
          int decimals = -1;
          const char* stop = decimal::parseSimpleDecimal(q, end, v, decimals);
          if (stop == nullptr) {
            if (q < end && *q == '+') ++q;
            auto result = fast_float::from_chars(q, end, v);
            stop = result.ec == std::errc() && result.ptr != q ? result.ptr : nullptr;
            decimals = 10;  // unknown: no decimal quantization
            if (stop != nullptr) {
              for (const char* c = q; c < stop; ++c) {
                if (*c == 'e' || *c == 'E') block.exponent = true;
              }
            }
          }
          if (stop == nullptr || !endsNumber(stop, end, delimiter)) {
            failAt(file, line_number, spec.name, "a number",
                   quoteInput(tokenAt(p, end, delimiter)));
          }
          p = stop;
          switch (spec.target) {
            case Target::X:
            case Target::Y:
            case Target::Z: {
              int axis = int(spec.target) - int(Target::X);
              if (!std::isfinite(v)) {
                failAt(file, line_number, spec.name, "a finite number",
                       quoteInput(std::string_view(q, std::size_t(p - q))));
              }
              xyz[axis] = v;
              block.decimals[axis] = std::max(block.decimals[axis], decimals);
              break;
            }
            case Target::R:
              colors[point].r = roundToInteger<std::uint8_t>(v);
              break;
            case Target::G:
              colors[point].g = roundToInteger<std::uint8_t>(v);
              break;
            case Target::B:
              colors[point].b = roundToInteger<std::uint8_t>(v);
              break;
            case Target::A:
              colors[point].a = roundToInteger<std::uint8_t>(v);
              break;
            case Target::Nx:
              normals[point].x = float(v);
              break;
            case Target::Ny:
              normals[point].y = float(v);
              break;
            case Target::Nz:
              normals[point].z = float(v);
              break;
            case Target::Intensity:
              intensity[point] = float(v);
              break;
            case Target::Classification:
              classification[point] = roundToInteger<std::uint8_t>(v);
              break;
            case Target::Scalar:
              cloud.scalars[spec.scalar].setFromDouble(point, v);
              break;
            case Target::Skip:
              break;
          }
        }
      } else {
        while (!endsNumber(p, end, delimiter)) ++p;  // an extra value: counted for the message
      }
      ++column;
      skipBlanks();
      if (p == end || *p == '\n' || *p == '\r') break;
      if (delimiter != ' ') {
        if (*p != delimiter) break;  // cannot happen: every value ends at one of these
        ++p;
        skipBlanks();
        if (p == end || *p == '\n' || *p == '\r') break;  // a trailing delimiter
      }
    }
    skipLine();
    if (column != n) {
      failAt(file, line_number, "", std::to_string(n) + " values",
             std::to_string(column) + " values", "every data line needs one value per column");
    }
    std::copy_n(xyz, 3, world + 3 * point);
    block.bounds.extend(xyz[0], xyz[1], xyz[2]);
    ++point;
  }
}

// Decimal quantization (see text_reader.h), else chooseQuantization per axis.
Quantization chooseTextQuantization(const Bounds3& bounds, const int decimals[3], bool exponent) {
  Quantization q = chooseQuantization(bounds);
  if (bounds.empty() || exponent) return q;
  static constexpr double kPowers[] = {1, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9};
  for (int axis = 0; axis < 3; ++axis) {
    if (decimals[axis] > 9) continue;
    double scale = 1.0 / kPowers[decimals[axis]];
    // Offset 0 when the values fit (the integers are then the written digits), else a whole
    // number at the centre.
    const double lo = bounds.min[std::size_t(axis)], hi = bounds.max[std::size_t(axis)];
    for (double offset : {0.0, std::nearbyint(0.5 * (lo + hi))}) {
      if ((lo - offset) / scale >= double(Quantization::kMin) + 1 &&
          (hi - offset) / scale <= double(Quantization::kMax) - 1) {
        q.scale[std::size_t(axis)] = scale;
        q.offset[std::size_t(axis)] = offset;
        break;
      }
    }
  }
  return q;
}

PointCloud readAll(std::string_view text, const std::string& file, const TextReadOptions& options) {
  Layout layout = detectLayout(text, file, options);
  // Blocks of about 1 MiB ending at line ends.
  constexpr std::size_t kBlockBytes = std::size_t{1} << 20;
  std::vector<Block> blocks;
  for (std::size_t at = layout.body_offset; at < text.size();) {
    std::size_t stop = std::min(text.size(), at + kBlockBytes);
    if (stop < text.size()) {
      const void* nl = std::memchr(text.data() + stop, '\n', text.size() - stop);
      stop = nl ? std::size_t(static_cast<const char*>(nl) - text.data()) + 1 : text.size();
    }
    blocks.push_back({.begin = at, .end = stop});
    at = stop;
  }
  auto run = [&](auto body) {
    if (options.parallel) {
      tbb::parallel_for(std::size_t(0), blocks.size(), body);
    } else {
      for (std::size_t b = 0; b < blocks.size(); ++b) body(b);
    }
  };
  // Pass 1: lines and points per block, for line numbers and output positions.
  run([&](std::size_t b) {
    Block& block = blocks[b];
    const char* p = text.data() + block.begin;
    const char* end = text.data() + block.end;
    while (p < end) {
      Line line = lineAt(p, end);
      ++block.lines;
      if (!skippedLine(line, layout)) ++block.points;
      p = line.next;
    }
  });
  std::uint64_t count = 0, line = layout.body_line;
  for (Block& block : blocks) {
    block.first_point = count;
    block.first_line = line;
    count += block.points;
    line += block.lines;
  }

  PointCloud cloud;
  cloud.count = count;
  cloud.positions = Column<Int3>(count);
  Column<double> world(3 * count);
  bool has[int(Target::Scalar) + 1] = {};
  for (const ColumnSpec& spec : layout.columns) has[int(spec.target)] = true;
  if (has[int(Target::R)] || has[int(Target::G)] || has[int(Target::B)] || has[int(Target::A)]) {
    cloud.colors = Column<Rgba8>(count);
    cloud.source.has_alpha = has[int(Target::A)];
  }
  if (has[int(Target::Nx)] || has[int(Target::Ny)] || has[int(Target::Nz)]) {
    cloud.normals = Column<Float3>(count);
  }
  if (has[int(Target::Intensity)]) cloud.intensity = Column<float>(count);
  if (has[int(Target::Classification)]) cloud.classification = Column<std::uint8_t>(count);
  for (const auto& [name, type] : layout.scalars) {
    cloud.scalars.push_back({name, type, ByteBuffer(count * scalarSize(type))});
  }
  cloud.source.position = ScalarType::Float64;
  cloud.source.intensity = ScalarType::Float32;

  // Pass 2: parse. Columns a line may leave unset (a missing g, say) are pre-filled in the block.
  std::vector<std::exception_ptr> errors(blocks.size());
  run([&](std::size_t b) {
    Block& block = blocks[b];
    std::size_t first = block.first_point, n = block.points;
    if (cloud.hasColors()) std::fill_n(cloud.colors.data() + first, n, Rgba8{0, 0, 0, 255});
    if (cloud.hasNormals()) std::fill_n(cloud.normals.data() + first, n, Float3{0, 0, 0});
    try {
      parseBlock(text, layout, file, block, world.data(), cloud);
    } catch (...) {
      errors[b] = std::current_exception();
    }
    if (options.progress) options.progress->advance(block.end - block.begin);
  });
  for (const auto& error : errors) {
    if (error) std::rethrow_exception(error);  // the first in the file
  }

  Bounds3 bounds;
  int decimals[3] = {0, 0, 0};
  bool exponent = false;
  for (const Block& block : blocks) {
    bounds.extend(block.bounds);
    for (int a = 0; a < 3; ++a) decimals[a] = std::max(decimals[a], block.decimals[a]);
    exponent |= block.exponent;
  }
  cloud.quantization = chooseTextQuantization(bounds, decimals, exponent);
  const Quantization& q = cloud.quantization;
  run([&](std::size_t b) {
    const Block& block = blocks[b];
    for (std::size_t i = block.first_point; i < block.first_point + block.points; ++i) {
      const double* xyz = world.data() + 3 * i;
      cloud.positions[i] = {q.toQuantized(0, xyz[0]), q.toQuantized(1, xyz[1]),
                            q.toQuantized(2, xyz[2])};
    }
  });
  cloud.computeBounds();
  return cloud;
}

}  // namespace

PointCloud readText(const std::filesystem::path& path, const TextReadOptions& options) {
  MappedFile file(path);
  auto bytes = file.bytes();
  return readAll(std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()),
                 path.string(), options);
}

PointCloud readTextFromMemory(std::span<const std::byte> bytes, const std::string& name,
                              const TextReadOptions& options) {
  return readAll(std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()), name,
                 options);
}

bool looksLikeTextPoints(std::span<const std::byte> bytes) {
  std::string_view text(reinterpret_cast<const char*>(bytes.data()),
                        std::min<std::size_t>(bytes.size(), 64 << 10));
  for (char c : text) {
    auto u = static_cast<unsigned char>(c);
    if (u < 0x20 && c != '\n' && c != '\r' && c != '\t') return false;
  }
  const char* p = text.data();
  const char* end = p + text.size();
  for (int lines = 0; p < end && lines < 100; ++lines) {
    Line line = lineAt(p, end);
    // The last line of a cut window may be partial: only whole lines count.
    if (line.next == end && bytes.size() > text.size()) break;
    p = line.next;
    if (isCommentOrBlank(line)) continue;
    auto values = tokens(line, delimiterOf(line));
    if (values.size() >= 3 && std::all_of(values.begin(), values.end(), isNumber)) return true;
  }
  return false;
}

}  // namespace parallax
