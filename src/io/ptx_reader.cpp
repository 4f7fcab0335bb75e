// Reading PTX files: a cursor walks the scans' headers and point lines, one valid point at a
// time; a first walk gives the exact bounds (so the quantization is exact before any point is
// stored), the count and the scans, a second stores the points. Text is parsed twice rather than
// held as doubles (24 bytes a point) between the walks.
#include "io/ptx_reader.h"

#include <fast_float/fast_float.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <optional>

#include "core/column_names.h"
#include "core/error.h"
#include "core/quantization.h"
#include "io/bytes_as_text.h"
#include "io/mapped_file.h"
#include "io/text_decoder.h"  // decimal-exact quantization of text positions

namespace parallax {
namespace {

struct PtxPoint {
  double x, y, z;  // transformed
  float intensity;
  Rgba8 color;
  std::uint16_t scan;
};

class PtxCursor {
 public:
  PtxCursor(std::string_view text, std::string file) : text_(text), file_(std::move(file)) {}

  // The next valid point; false at the end of the file. Throws InputError for malformed lines.
  bool next(PtxPoint& point) {
    while (true) {
      if (left_in_scan_ == 0) {
        if (!startScan()) return false;
        continue;
      }
      if (!nextLine()) {
        fail(line_ + 1, "point line",
             std::to_string(left_in_scan_) + " more point lines of scan " +
                 std::to_string(scans_.size() - 1) + " (columns * rows = " +
                 std::to_string(scans_.back().columns * scans_.back().rows) + ")",
             "the end of the file", "the file is truncated");
      }
      --left_in_scan_;
      static const char* const kNames[] = {
          column_names::kX,   column_names::kY,     column_names::kZ,   column_names::kIntensity,
          column_names::kRed, column_names::kGreen, column_names::kBlue};
      if (values_per_point_ == 0) {
        values_per_point_ = words_.size();
        if (values_per_point_ != 4 && values_per_point_ != 7) {
          fail(line_, "point line", "4 values (x y z intensity) or 7 (x y z intensity r g b)",
               std::to_string(words_.size()) + " values");
        }
      } else if (words_.size() != values_per_point_) {
        fail(line_, "point line",
             std::to_string(values_per_point_) + " values, as the first point line has",
             std::to_string(words_.size()));
      }
      double v[7];
      for (std::size_t i = 0; i < values_per_point_; ++i) v[i] = number(i, kNames[i]);
      if (v[0] == 0 && v[1] == 0 && v[2] == 0) continue;  // no return in that direction
      const auto& m = scans_.back().transform;
      if (identity_) {
        for (int a = 0; a < 3; ++a) {
          decimals_[a] = std::max(decimals_[a], decimalsOf(words_[std::size_t(a)]));
        }
      } else {
        decimals_[0] = decimals_[1] = decimals_[2] = text::kNotDecimal;
      }
      point.x = v[0] * m[0] + v[1] * m[4] + v[2] * m[8] + m[12];
      point.y = v[0] * m[1] + v[1] * m[5] + v[2] * m[9] + m[13];
      point.z = v[0] * m[2] + v[1] * m[6] + v[2] * m[10] + m[14];
      point.intensity = float(v[3]);
      point.color = {0, 0, 0, 255};
      if (values_per_point_ == 7) {
        for (int c = 0; c < 3; ++c) {
          if (!(v[4 + c] >= 0 && v[4 + c] <= 255)) {
            fail(line_, kNames[4 + c], "a colour value from 0 to 255",
                 std::string(words_[std::size_t(4 + c)]));
          }
        }
        point.color = {std::uint8_t(std::lround(v[4])), std::uint8_t(std::lround(v[5])),
                       std::uint8_t(std::lround(v[6])), 255};
      }
      point.scan = std::uint16_t(scans_.size() - 1);
      ++scans_.back().points;
      return true;
    }
  }

  bool hasColor() const { return values_per_point_ == 7; }
  // Most digits after the point of the positions as written, per axis (text::kNotDecimal when a
  // transform other than the identity moved them, or for exponents).
  const int* decimals() const { return decimals_; }
  std::vector<PtxScan>& scans() { return scans_; }
  std::size_t offset() const { return pos_; }

 private:
  [[noreturn]] void fail(std::uint64_t line, const std::string& property,
                         const std::string& expected, const std::string& found,
                         const std::string& hint = "") const {
    throw InputError(
        {.file = file_,
         .line = line,
         .element = scans_.empty() ? "scan 0" : "scan " + std::to_string(scans_.size() - 1),
         .property = property,
         .expected = expected,
         .found = found,
         .hint = hint});
  }

  // The next line's words into words_; false at the end of the text.
  bool nextLine() {
    if (pos_ >= text_.size()) return false;
    const char* begin = text_.data() + pos_;
    const char* end = text_.data() + text_.size();
    const char* newline =
        static_cast<const char*>(std::memchr(begin, '\n', std::size_t(end - begin)));
    const char* line_end = newline ? newline : end;
    pos_ = newline ? std::size_t(newline + 1 - text_.data()) : text_.size();
    ++line_;
    words_.clear();
    const char* p = begin;
    while (p < line_end) {
      while (p < line_end && (*p == ' ' || *p == '\t' || *p == '\r')) ++p;
      const char* start = p;
      while (p < line_end && *p != ' ' && *p != '\t' && *p != '\r') ++p;
      if (p > start) words_.emplace_back(start, std::size_t(p - start));
    }
    return true;
  }

  static int decimalsOf(std::string_view word) {
    const std::size_t point = word.find('.');
    if (word.find_first_of("eE") != std::string_view::npos) return text::kNotDecimal;
    if (point == std::string_view::npos) return 0;
    // Trailing zeros say nothing of the value (scanners print 637012.240000): not counted.
    std::size_t last = word.size();
    while (last > point + 1 && word[last - 1] == '0') --last;
    const std::size_t digits = last - point - 1;
    return digits > 9 ? text::kNotDecimal : int(digits);
  }

  double number(std::size_t i, const std::string& property) const {
    const std::string_view word = words_[i];
    double value = 0;
    auto result = fast_float::from_chars(word.data(), word.data() + word.size(), value);
    if (result.ec != std::errc() || result.ptr != word.data() + word.size() ||
        !std::isfinite(value)) {
      fail(line_, property, "a finite number", quoteInput(word));
    }
    return value;
  }

  // A header line of `count` numbers named `property`.
  void headerLine(std::size_t count, const std::string& property, double* out) {
    if (!nextLine()) {
      fail(line_ + 1, property, std::to_string(count) + " numbers", "the end of the file",
           "the file is truncated");
    }
    if (words_.size() != count) {
      fail(line_, property, std::to_string(count) + " numbers",
           std::to_string(words_.size()) + " values");
    }
    for (std::size_t i = 0; i < count; ++i) out[i] = number(i, property);
  }

  std::uint64_t wholeNumber(const std::string& property) {
    double value = 0;
    headerLine(1, property, &value);
    if (!(value >= 0 && value <= 1e12) || value != std::floor(value)) {
      fail(line_, property, "a whole number of points", std::string(words_[0]));
    }
    return std::uint64_t(value);
  }

  // Reads the next scan's header; false at the end of the file (blank lines only).
  bool startScan() {
    // Blank lines between scans and at the end.
    while (true) {
      const std::size_t save_pos = pos_;
      const std::uint64_t save_line = line_;
      if (!nextLine()) return false;
      if (!words_.empty()) {
        pos_ = save_pos, line_ = save_line;
        break;
      }
    }
    if (scans_.size() == std::numeric_limits<std::uint16_t>::max() + std::size_t(1)) {
      fail(line_ + 1, "columns", "at most 65536 scans", "more");
    }
    PtxScan scan;
    scan.first_line = line_ + 1;
    scans_.push_back(scan);
    PtxScan& s = scans_.back();
    s.columns = wholeNumber("columns");
    s.rows = wholeNumber("rows");
    headerLine(3, "scanner position", s.position.data());
    headerLine(3, "scanner x axis", s.axes[0].data());
    headerLine(3, "scanner y axis", s.axes[1].data());
    headerLine(3, "scanner z axis", s.axes[2].data());
    for (int row = 0; row < 4; ++row) {
      headerLine(4, "transform row " + std::to_string(row + 1), s.transform.data() + 4 * row);
    }
    left_in_scan_ = s.columns * s.rows;
    identity_ = s.transform == PtxScan{}.transform;
    return true;
  }

  std::string_view text_;
  std::string file_;
  std::size_t pos_ = 0;
  std::uint64_t line_ = 0;
  std::vector<std::string_view> words_;
  std::vector<PtxScan> scans_;
  std::uint64_t left_in_scan_ = 0;
  std::size_t values_per_point_ = 0;  // 4 or 7, from the first point line
  bool identity_ = true;              // the scan's transform is the identity
  int decimals_[3] = {0, 0, 0};
};

// What a first walk learns.
struct PtxSurvey {
  std::vector<PtxScan> scans;
  std::uint64_t points = 0;
  text::PositionStats stats;  // exact bounds and decimals of the positions
  bool color = false;

  // Positions written in decimals and not transformed keep a decimal scale (their digits
  // exactly, as the text reader does); others a power-of-two scale over the exact bounds.
  Quantization quantization() const { return text::exactTextQuantization(stats); }
};

PtxSurvey survey(std::string_view text, const std::string& name) {
  PtxCursor cursor(text, name);
  PtxSurvey out;
  PtxPoint p;
  while (cursor.next(p)) {
    ++out.points;
    out.stats.raw.extend(p.x, p.y, p.z);
  }
  for (int a = 0; a < 3; ++a) out.stats.decimals[a] = cursor.decimals()[a];
  out.scans = std::move(cursor.scans());
  out.color = cursor.hasColor();
  if (out.scans.empty()) {
    throw InputError({.file = name,
                      .line = 1,
                      .element = "scan 0",
                      .property = "columns",
                      .expected = "a PTX scan (columns, rows, scanner pose, transform, points)",
                      .found = "an empty file"});
  }
  return out;
}

PointCloud allocate(const PtxSurvey& s, std::uint64_t count, const Quantization& q) {
  PointCloud cloud;
  cloud.count = count;
  cloud.quantization = q;
  cloud.positions = Column<Int3>(count);
  cloud.intensity = Column<float>(count);
  if (s.color) cloud.colors = Column<Rgba8>(count);
  cloud.scalars.push_back({.name = column_names::kScanIndex,
                           .type = ScalarType::UInt16,
                           .data = ByteBuffer(count * sizeof(std::uint16_t))});
  cloud.source.position = ScalarType::Float64;
  // Leica's PTX intensity is a float in 0..1: LAS gets it on 0..65535, not rounded to 0 or 1.
  cloud.source.intensity_full_scale = 1.0;
  cloud.source.order = {column_names::kX, column_names::kY, column_names::kZ,
                        column_names::kIntensity};
  if (s.color)
    cloud.source.order.insert(cloud.source.order.end(),
                              {column_names::kRed, column_names::kGreen, column_names::kBlue});
  cloud.source.order.push_back(column_names::kScanIndex);
  return cloud;
}

void store(PointCloud& cloud, std::size_t i, const PtxPoint& p) {
  const Quantization& q = cloud.quantization;
  cloud.positions[i] = {q.toQuantized(0, p.x), q.toQuantized(1, p.y), q.toQuantized(2, p.z)};
  cloud.intensity[i] = p.intensity;
  if (cloud.hasColors()) cloud.colors[i] = p.color;
  cloud.scalars[0].as<std::uint16_t>()[i] = p.scan;
}

PointCloud readPtxText(std::string_view text, const std::string& name,
                       const PtxReadOptions& options) {
  PtxSurvey s = survey(text, name);
  PointCloud cloud = allocate(s, s.points, s.quantization());
  PtxCursor cursor(text, name);
  PtxPoint p;
  std::size_t i = 0;
  std::size_t reported = 0;
  while (i < s.points && cursor.next(p)) {
    store(cloud, i++, p);
    if (options.progress && (i & 0xFFFF) == 0) {
      options.progress->advance(cursor.offset() - reported);
      reported = cursor.offset();
    }
  }
  if (options.progress) options.progress->advance(text.size() - reported);
  cloud.computeBounds();
  if (options.scans) *options.scans = std::move(s.scans);
  return cloud;
}

}  // namespace

PointCloud readPtx(const std::filesystem::path& path, const PtxReadOptions& options) {
  const MappedFile file(path);
  return readPtxText(bytesAsText(file.bytes()), path.string(), options);
}

PointCloud readPtxFromMemory(std::span<const std::byte> bytes, const std::string& name,
                             const PtxReadOptions& options) {
  return readPtxText(bytesAsText(bytes), name, options);
}

std::vector<PtxScan> readPtxScans(const std::filesystem::path& path) {
  const MappedFile file(path);
  return survey(bytesAsText(file.bytes()), path.string()).scans;
}

struct PtxChunkReader::State {
  MappedFile file;
  PtxSurvey survey;
  Quantization quantization;
  std::optional<PtxCursor> cursor;
  std::uint64_t done = 0;
  explicit State(const std::filesystem::path& path) : file(path) {}
};

PtxChunkReader::PtxChunkReader(const std::filesystem::path& path, const Quantization* quantization)
    : state_(std::make_unique<State>(path)) {
  State& s = *state_;
  s.survey = survey(bytesAsText(s.file.bytes()), path.string());
  s.quantization = quantization ? *quantization : s.survey.quantization();
  s.cursor.emplace(bytesAsText(s.file.bytes()), path.string());
}

PtxChunkReader::~PtxChunkReader() = default;
PtxChunkReader::PtxChunkReader(PtxChunkReader&&) noexcept = default;

const std::vector<PtxScan>& PtxChunkReader::scans() const {
  return state_->survey.scans;
}

std::uint64_t PtxChunkReader::pointCount() const {
  return state_->survey.points;
}

const Quantization& PtxChunkReader::quantization() const {
  return state_->quantization;
}

bool PtxChunkReader::next(PointCloud& chunk, std::size_t max_points) {
  State& s = *state_;
  const std::uint64_t count = std::min<std::uint64_t>(max_points, s.survey.points - s.done);
  chunk = allocate(s.survey, count, s.quantization);
  if (count == 0) return false;
  PtxPoint p;
  for (std::uint64_t i = 0; i < count; ++i) {
    s.cursor->next(p);  // the survey counted these points
    for (int axis = 0; axis < 3; ++axis) {
      const double v = axis == 0 ? p.x : axis == 1 ? p.y : p.z;
      if (!s.quantization.fits(axis, v)) {
        throw InputError({.file = s.file.path(),
                          .element = "point " + std::to_string(s.done + i),
                          .property = std::string(1, char('x' + axis)),
                          .expected = "a position within the quantization given",
                          .found = std::to_string(v)});
      }
    }
    store(chunk, std::size_t(i), p);
  }
  s.done += count;
  chunk.computeBounds();
  return true;
}

bool looksLikePtx(std::span<const std::byte> bytes) {
  const std::string_view text = bytesAsText(bytes.first(std::min<std::size_t>(bytes.size(), 4096)));
  std::size_t pos = 0;
  static constexpr std::size_t kWords[] = {1, 1, 3, 3, 3, 3, 4, 4, 4, 4};
  for (std::size_t expected : kWords) {
    const std::size_t newline = text.find('\n', pos);
    if (newline == std::string_view::npos) return false;
    const std::string_view line = text.substr(pos, newline - pos);
    pos = newline + 1;
    std::size_t words = 0;
    bool in_word = false;
    for (char c : line) {
      const bool blank = c == ' ' || c == '\t' || c == '\r';
      if (!blank && !(std::isdigit((unsigned char)c) || c == '-' || c == '+' || c == '.' ||
                      c == 'e' || c == 'E')) {
        return false;
      }
      if (!blank && !in_word) ++words;
      in_word = !blank;
    }
    if (words != expected) return false;
  }
  return true;
}

}  // namespace parallax
