#include "io/text_decoder.h"

#include <fast_float/fast_float.h>
#include <tbb/parallel_for.h>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <stdexcept>

#include "core/column_names.h"
#include "core/error.h"
#include "io/decimal_parse.h"

namespace parallax::text {
namespace {

// Blocks of about 1 MiB: thousands of lines, so scheduling costs nothing, and small enough that
// a block's bytes are still in cache when its pages are released.
constexpr std::size_t kBlockBytes = std::size_t{1} << 20;
// Lines sampled for the quantization (as the PLY reader samples records).
constexpr std::size_t kSamples = 4096;
// Bodies of at most this many points are parsed whole for their positions' stats (a few ms).
constexpr std::uint64_t kExactPoints = 64 << 10;
// The sampled extent is widened this much around its centre for the points the sample missed.
constexpr double kSampleMargin = 16.0;

constexpr double kPowers[] = {1, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9};

template <class F>
void forEachIndex(bool parallel, std::size_t count, F&& body) {
  if (parallel) {
    tbb::parallel_for(std::size_t(0), count, body);
  } else {
    for (std::size_t i = 0; i < count; ++i) body(i);
  }
}

// Releases a block's pages and the 2 MiB before it: where the page cache holds the file in large
// folios, a fault maps a whole folio, behind the reader too (as ply::DecodeContext does).
void releaseBlock(const MappedFile* file, std::size_t begin, std::size_t end) {
  if (file == nullptr) return;
  constexpr std::size_t kLargeFolio = 2 << 20;
  const std::size_t from = begin > kLargeFolio ? begin - kLargeFolio : 0;
  file->releaseRead(from, end - from);
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

int axisOf(Target target) {
  return int(target) - int(Target::X);
}

bool isPosition(Target target) {
  return target == Target::X || target == Target::Y || target == Target::Z;
}

// The decimal choice for one axis (offset 0 when [lo, hi] fits, else a whole number at the
// centre); false when neither fits the int32 range at that scale.
bool decimalAxis(double lo, double hi, int decimals, double& scale, double& offset) {
  if (decimals < 0 || decimals > 9) return false;
  const double s = 1.0 / kPowers[decimals];
  for (double o : {0.0, std::nearbyint(0.5 * (lo + hi))}) {
    if ((lo - o) / s >= double(Quantization::kMin) + 1 &&
        (hi - o) / s <= double(Quantization::kMax) - 1) {
      scale = s;
      offset = o;
      return true;
    }
  }
  return false;
}

Quantization exactChoice(const PositionStats& exact, bool decimal[3]) {
  Quantization q = chooseQuantization(exact.raw);
  for (int axis = 0; axis < 3; ++axis) decimal[axis] = false;
  if (exact.raw.empty()) return q;
  for (int axis = 0; axis < 3; ++axis) {
    const auto a = std::size_t(axis);
    decimal[axis] = decimalAxis(exact.raw.min[a], exact.raw.max[a], exact.decimals[axis],
                                q.scale[a], q.offset[a]);
  }
  return q;
}

bool isValueStart(char c) {
  return (c >= '0' && c <= '9') || c == '-' || c == '+' || c == '.';
}

// The lines of [b, e) when every one starts with a digit, a sign or a point: then every line is a
// point (the usual body: no comment, blank line or leading blank), and they are counted 16 bytes
// a step instead of a line at a time. False for any other block: the line-by-line count decides
// (PTS bodies never come here: their count lines start with digits too).
bool countPlainLines(const char* b, const char* e, std::uint64_t& lines) {
  lines = 0;
  if (b == e) return true;
  if (!isValueStart(*b)) return false;
  std::uint64_t n = 0;
  const char* p = b;
#if defined(__SSE2__)
  const __m128i newline = _mm_set1_epi8('\n');
  const __m128i zero = _mm_set1_epi8('0'), nine = _mm_set1_epi8(9);
  const __m128i minus = _mm_set1_epi8('-'), plus = _mm_set1_epi8('+'), dot = _mm_set1_epi8('.');
  while (e - p >= 17) {
    __m128i sums = _mm_setzero_si128();
    // Up to 255 steps: each byte lane counts at most 255 line ends before it is folded.
    for (int step = 0; step < 255 && e - p >= 17; ++step, p += 16) {
      const __m128i here = _mm_loadu_si128(reinterpret_cast<const __m128i*>(p));
      const __m128i next = _mm_loadu_si128(reinterpret_cast<const __m128i*>(p + 1));
      const __m128i ends = _mm_cmpeq_epi8(here, newline);
      const __m128i offset = _mm_sub_epi8(next, zero);
      const __m128i digit = _mm_cmpeq_epi8(_mm_min_epu8(offset, nine), offset);
      const __m128i start =
          _mm_or_si128(_mm_or_si128(digit, _mm_cmpeq_epi8(next, minus)),
                       _mm_or_si128(_mm_cmpeq_epi8(next, plus), _mm_cmpeq_epi8(next, dot)));
      if (_mm_movemask_epi8(_mm_andnot_si128(start, ends)) != 0) return false;
      sums = _mm_sub_epi8(sums, ends);
    }
    const __m128i folded = _mm_sad_epu8(sums, _mm_setzero_si128());
    n += std::uint64_t(_mm_cvtsi128_si64(folded)) +
         std::uint64_t(_mm_cvtsi128_si64(_mm_unpackhi_epi64(folded, folded)));
  }
#endif
  for (; p < e; ++p) {
    if (*p != '\n') continue;
    ++n;
    if (p + 1 < e && !isValueStart(p[1])) return false;
  }
  if (e[-1] != '\n') ++n;  // the file's last line, without its line end
  lines = n;
  return true;
}

void extendAxis(Bounds3& bounds, int axis, double value) {
  const auto a = std::size_t(axis);
  bounds.min[a] = std::min(bounds.min[a], value);
  bounds.max[a] = std::max(bounds.max[a], value);
}

// Axes whose quantization is a decimal scale 10^-d with a whole offset: a value written with at
// most d decimals is stored as the integer of its digits less the offset in units, with no
// floating point at all (decimals[axis] = d; -1 elsewhere).
struct IntegerAxes {
  int decimals[3] = {-1, -1, -1};
  std::int64_t offset_units[3] = {0, 0, 0};
};

IntegerAxes integerAxes(const Quantization* q) {
  IntegerAxes axes;
  if (q == nullptr) return axes;
  for (int axis = 0; axis < 3; ++axis) {
    const auto a = std::size_t(axis);
    for (int d = 0; d <= 9; ++d) {
      if (q->scale[a] != 1.0 / kPowers[d]) continue;
      const double units = q->offset[a] * kPowers[d];
      if (std::nearbyint(q->offset[a]) == q->offset[a] && std::abs(units) < 0x1p62) {
        axes.decimals[axis] = d;
        axes.offset_units[axis] = std::int64_t(units);
      }
      break;
    }
  }
  return axes;
}

constexpr std::uint64_t kIntegerPowers[] = {1,      10,      100,      1000,      10000,
                                            100000, 1000000, 10000000, 100000000, 1000000000};

// Stores the position at `p` in stored[axis] from its digits when it has at most the axis's
// decimals and lands inside the grid (p then moves past it); false, p unmoved, for anything else:
// the double path parses it (and reports what is wrong, or marks it outside).
bool storeFromDigits(const char*& p, const char* end, char delimiter, const IntegerAxes& integer,
                     int axis, std::int32_t stored[3], PositionStats& stats) {
  std::uint64_t mantissa;
  bool negative;
  int fraction;
  const char* stop = decimal::parseDecimalParts(p, end, mantissa, negative, fraction);
  const int d = integer.decimals[axis];
  if (stop == nullptr || fraction > d || !endsNumber(stop, end, delimiter)) return false;
  // mantissa < 10^15 and 10^(d - fraction) <= 10^9: a product past 2^63 is far outside any int32
  // grid; it goes to the double path, which marks it outside.
  const std::uint64_t power = kIntegerPowers[d - fraction];
  if (mantissa > std::uint64_t(INT64_MAX) / power) return false;
  const auto units = std::int64_t(mantissa * power);
  const std::int64_t value = (negative ? -units : units) - integer.offset_units[axis];
  if (value < Quantization::kMin || value > Quantization::kMax) return false;
  stored[axis] = std::int32_t(value);
  stats.decimals[axis] = std::max(stats.decimals[axis], fraction);
  p = stop;
  return true;
}

}  // namespace

void PositionStats::merge(const PositionStats& other) {
  raw.extend(other.raw);
  for (int axis = 0; axis < 3; ++axis) {
    decimals[axis] = std::max(decimals[axis], other.decimals[axis]);
    outside[axis] = outside[axis] || other.outside[axis];
  }
}

ParseResult parseLines(std::string_view text, std::size_t begin, std::size_t end_byte,
                       std::uint64_t first_line, std::uint64_t max_points, const Layout& layout,
                       const std::string& file, const ParseOutput& out) {
  ParseResult result;
  const char* p = text.data() + begin;
  const char* const end = text.data() + end_byte;
  const char delimiter = layout.delimiter;
  const double color_scale = layout.color_scale;
  const std::size_t n = layout.columns.size();
  // Positions only: the line is left after its last x, y or z.
  const std::size_t needed = out.positions_only ? layout.lastPositionColumn() + 1 : n;
  PointCloud* cloud = out.positions_only ? nullptr : out.cloud;
  Int3* positions = out.cloud ? out.cloud->positions.data() : nullptr;
  Rgba8* colors = cloud && cloud->hasColors() ? cloud->colors.data() : nullptr;
  Float3* normals = cloud && cloud->hasNormals() ? cloud->normals.data() : nullptr;
  float* intensity = cloud && cloud->hasIntensity() ? cloud->intensity.data() : nullptr;
  std::uint8_t* classification =
      cloud && cloud->hasClassification() ? cloud->classification.data() : nullptr;
  const Quantization q = out.quantization ? *out.quantization : Quantization{};
  const IntegerAxes integer = integerAxes(out.cloud ? out.quantization : nullptr);
  // Positions stored from their digits (integer axes): their extremes, made world at the end.
  std::int32_t lowest[3] = {Quantization::kMax, Quantization::kMax, Quantization::kMax};
  std::int32_t highest[3] = {Quantization::kMin, Quantization::kMin, Quantization::kMin};
  bool any_integer = false;
  PositionStats& stats = result.stats;
  std::uint64_t line_number = first_line;
  std::size_t point = out.first_index;

  auto skipBlanks = [&] {
    while (p < end && (*p == ' ' || *p == '\t')) ++p;
  };
  // Before a line's first value, blanks as the line counter sees them (isBlank in text_layout.h:
  // a CR too), so that a line counted as a point is parsed as one ("\r0 1 2" holds 0 1 2).
  auto skipLeadingBlanks = [&] {
    while (p < end && (*p == ' ' || *p == '\t' || *p == '\r')) ++p;
  };
  auto skipLine = [&] {
    const void* nl = std::memchr(p, '\n', std::size_t(end - p));
    p = nl ? static_cast<const char*>(nl) + 1 : end;
    ++line_number;
    ++result.lines;
  };
  auto quantize = [&](int axis, double v) -> std::int32_t {
    const double r = std::nearbyint((v - q.offset[std::size_t(axis)]) / q.scale[std::size_t(axis)]);
    if (r >= double(Quantization::kMin) && r <= double(Quantization::kMax)) return std::int32_t(r);
    stats.outside[axis] = true;
    return r > 0 ? Quantization::kMax : Quantization::kMin;
  };

  while (p < end && result.points < max_points) {
    skipLeadingBlanks();
    if (p == end || *p == '\n' || *p == '#' || (*p == '/' && p + 1 < end && p[1] == '/')) {
      skipLine();
      continue;
    }
    if (layout.pts) {
      // A further scan's count in a concatenated PTS file: one integer alone (isSkippedLine).
      const char* c = p;
      while (c < end && *c >= '0' && *c <= '9') ++c;
      const char* d = c;
      while (d < end && (*d == ' ' || *d == '\t' || *d == '\r')) ++d;
      if (c > p && (d == end || *d == '\n')) {
        skipLine();
        continue;
      }
    }
    if (colors) colors[point] = Rgba8{0, 0, 0, 255};  // channels the file lacks
    if (normals) normals[point] = Float3{0, 0, 0};
    double xyz[3] = {0.0, 0.0, 0.0};
    std::int32_t stored[3] = {0, 0, 0};
    bool have_double[3] = {false, false, false};
    std::size_t column = 0;
    while (true) {
      if (column < needed) {
        const ColumnSpec& spec = layout.columns[column];
        const char* q0 = p;
        if (spec.target == Target::Skip || (out.positions_only && !isPosition(spec.target))) {
          while (!endsNumber(p, end, delimiter)) ++p;
        } else if (isPosition(spec.target) && integer.decimals[axisOf(spec.target)] >= 0 &&
                   storeFromDigits(p, end, delimiter, integer, axisOf(spec.target), stored,
                                   stats)) {
          // Stored exactly from its digits; p is past the number.
        } else {
          double v;
          int decimals = -1;
          const char* stop = decimal::parseSimpleDecimal(q0, end, v, decimals);
          if (stop == nullptr) {
            const char* f = q0 < end && *q0 == '+' ? q0 + 1 : q0;
            auto parsed = fast_float::from_chars(f, end, v);
            stop = parsed.ec == std::errc() && parsed.ptr != f ? parsed.ptr : nullptr;
            decimals = kNotDecimal;
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
              const int axis = axisOf(spec.target);
              if (!std::isfinite(v)) {
                failAt(file, line_number, spec.name, "a finite number",
                       quoteInput(std::string_view(q0, std::size_t(p - q0))));
              }
              xyz[axis] = v;
              have_double[axis] = true;
              stats.decimals[axis] = std::max(stats.decimals[axis], decimals);
              break;
            }
            case Target::R:
              colors[point].r = roundToInteger<std::uint8_t>(v * color_scale);
              break;
            case Target::G:
              colors[point].g = roundToInteger<std::uint8_t>(v * color_scale);
              break;
            case Target::B:
              colors[point].b = roundToInteger<std::uint8_t>(v * color_scale);
              break;
            case Target::A:
              colors[point].a = roundToInteger<std::uint8_t>(v * color_scale);
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
              cloud->scalars[spec.scalar].setFromDouble(point, v);
              break;
            case Target::Skip:
              break;
          }
        }
      } else if (out.positions_only) {
        break;  // the rest of the line is not looked at
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
    const std::uint64_t this_line = line_number;
    skipLine();
    if (out.positions_only ? column < needed : column != n) {
      failAt(file, this_line, "", std::to_string(n) + " values", std::to_string(column) + " values",
             "every data line needs one value per column");
    }
    if (positions == nullptr ||
        integer.decimals[0] + integer.decimals[1] + integer.decimals[2] == -3) {
      // The double path: positions for their stats only, or a quantization with no integer axis.
      stats.raw.extend(xyz[0], xyz[1], xyz[2]);
      if (positions) {
        positions[point] = {quantize(0, xyz[0]), quantize(1, xyz[1]), quantize(2, xyz[2])};
      }
    } else {
      for (int axis = 0; axis < 3; ++axis) {
        if (have_double[axis]) {
          stored[axis] = quantize(axis, xyz[axis]);
          extendAxis(stats.raw, axis, xyz[axis]);
        } else {
          lowest[axis] = std::min(lowest[axis], stored[axis]);
          highest[axis] = std::max(highest[axis], stored[axis]);
          any_integer = true;
        }
      }
      positions[point] = {stored[0], stored[1], stored[2]};
    }
    ++point;
    ++result.points;
  }
  if (any_integer) {
    // The extremes of the positions stored from their digits, as world values (on the grid).
    for (int axis = 0; axis < 3; ++axis) {
      if (lowest[axis] > highest[axis]) continue;
      extendAxis(stats.raw, axis, q.toWorld(axis, lowest[axis]));
      extendAxis(stats.raw, axis, q.toWorld(axis, highest[axis]));
    }
  }
  result.end = std::size_t(p - text.data());
  return result;
}

BodyPlan planBody(std::string_view text, const Layout& layout, const std::string& file_name,
                  const MappedFile* file, bool parallel) {
  BodyPlan plan;
  std::vector<Block>& blocks = plan.blocks;
  for (std::size_t at = layout.body_offset; at < text.size();) {
    std::size_t stop = std::min(text.size(), at + kBlockBytes);
    if (stop < text.size()) {
      const void* nl = std::memchr(text.data() + stop, '\n', text.size() - stop);
      stop = nl ? std::size_t(static_cast<const char*>(nl) - text.data()) + 1 : text.size();
    }
    blocks.push_back({.begin = at, .end = stop});
    at = stop;
  }
  const std::size_t body_bytes = text.size() - std::min(text.size(), layout.body_offset);
  const std::size_t stride = std::max<std::size_t>(1, body_bytes / kSamples);
  std::vector<PositionStats> samples(blocks.size());
  forEachIndex(parallel, blocks.size(), [&](std::size_t b) {
    Block& block = blocks[b];
    const char* p = text.data() + block.begin;
    const char* end = text.data() + block.end;
    if (!layout.pts && countPlainLines(p, end, block.lines)) {
      block.points = block.lines;
    } else {
      block.lines = 0;
      while (p < end) {
        const Line line = lineAt(p, end);
        ++block.lines;
        if (!isSkippedLine(line, layout)) ++block.points;
        p = line.next;
      }
    }
    // The lines after the sample grid's points in this block (its pages are in cache now).
    const std::size_t from = block.begin - layout.body_offset;
    std::size_t last = block.begin;
    for (std::size_t g = layout.body_offset + (from + stride - 1) / stride * stride; g < block.end;
         g += stride) {
      std::size_t start = g;
      if (g != block.begin) {
        const void* nl = std::memchr(text.data() + g, '\n', block.end - g);
        if (nl == nullptr) break;
        start = std::size_t(static_cast<const char*>(nl) - text.data()) + 1;
      }
      if (start >= block.end || (start < last && start != block.begin)) continue;
      try {
        const ParseResult one =
            parseLines(text, start, block.end, 0, 1, layout, file_name, {.positions_only = true});
        samples[b].merge(one.stats);
        last = one.end;
      } catch (const InputError&) {
        // Reported with its line by the full parse.
      }
    }
    releaseBlock(file, block.begin, block.end);
  });
  std::uint64_t line = layout.body_line;
  for (Block& block : blocks) {
    block.first_point = plan.points;
    block.first_line = line;
    plan.points += block.points;
    line += block.lines;
  }
  if (plan.points <= kExactPoints) {
    // Small: every position, so the stats are the file's. Errors are the full parse's to report.
    plan.exact = true;
    for (const Block& block : blocks) {
      try {
        plan.sample.merge(parseLines(text, block.begin, block.end, block.first_line, block.points,
                                     layout, file_name, {.positions_only = true})
                              .stats);
      } catch (const InputError&) {
      }
    }
    return plan;
  }
  for (const PositionStats& s : samples) plan.sample.merge(s);
  return plan;
}

PointCloud allocateTextCloud(const Layout& layout, std::uint64_t count) {
  PointCloud cloud;
  cloud.count = count;
  cloud.positions = Column<Int3>(count);
  if (layout.has(Target::R) || layout.has(Target::G) || layout.has(Target::B) ||
      layout.has(Target::A)) {
    cloud.colors = Column<Rgba8>(count);
    cloud.source.has_alpha = layout.has(Target::A);
  }
  if (layout.has(Target::Nx) || layout.has(Target::Ny) || layout.has(Target::Nz)) {
    cloud.normals = Column<Float3>(count);
  }
  if (layout.has(Target::Intensity)) cloud.intensity = Column<float>(count);
  if (layout.has(Target::Classification)) cloud.classification = Column<std::uint8_t>(count);
  for (const auto& [name, type] : layout.scalars) {
    cloud.scalars.push_back({name, type, ByteBuffer(count * scalarSize(type))});
  }
  cloud.source.position = ScalarType::Float64;
  cloud.source.intensity = ScalarType::Float32;
  static const char* const kModelNames[] = {"",
                                            column_names::kX,
                                            column_names::kY,
                                            column_names::kZ,
                                            column_names::kRed,
                                            column_names::kGreen,
                                            column_names::kBlue,
                                            column_names::kAlpha,
                                            column_names::kNx,
                                            column_names::kNy,
                                            column_names::kNz,
                                            column_names::kIntensity,
                                            column_names::kClassification};
  for (const ColumnSpec& spec : layout.columns) {
    if (spec.target == Target::Skip) continue;
    cloud.source.order.push_back(spec.target == Target::Scalar ? spec.name
                                                               : kModelNames[int(spec.target)]);
  }
  return cloud;
}

Quantization exactTextQuantization(const PositionStats& exact) {
  bool decimal[3];
  return exactChoice(exact, decimal);
}

SampledQuantization exactTextChoice(const PositionStats& exact) {
  SampledQuantization chosen;
  chosen.quantization = exactChoice(exact, chosen.decimal);
  return chosen;
}

SampledQuantization sampledTextQuantization(const PositionStats& sample) {
  SampledQuantization chosen;
  chosen.quantization = chooseQuantization(sample.raw, kSampleMargin);
  if (sample.raw.empty()) return chosen;
  for (int axis = 0; axis < 3; ++axis) {
    const auto a = std::size_t(axis);
    const double lo = sample.raw.min[a], hi = sample.raw.max[a];
    const double center = 0.5 * (lo + hi), half = 0.5 * (hi - lo) * kSampleMargin;
    Quantization& q = chosen.quantization;
    chosen.decimal[axis] =
        decimalAxis(center - half, center + half, sample.decimals[axis], q.scale[a], q.offset[a]) ||
        decimalAxis(lo, hi, sample.decimals[axis], q.scale[a], q.offset[a]);
  }
  return chosen;
}

RequantizePlan planRequantize(const SampledQuantization& used, const PositionStats& exact) {
  RequantizePlan plan;
  bool decimal[3];
  plan.final = exactChoice(exact, decimal);
  const Quantization& q = used.quantization;
  if (exact.raw.empty()) {
    plan.final = q;
    return plan;
  }
  bool shift = false;
  for (int axis = 0; axis < 3; ++axis) {
    const auto a = std::size_t(axis);
    if (exact.outside[axis]) {
      plan.action = Requantize::Decode;
      return plan;
    }
    if (decimal[axis]) {
      // The exact decimal scale holds every value; the sampled one must be the same scale with a
      // whole offset, so that the integers differ by a whole number.
      if (!used.decimal[axis] || q.scale[a] != plan.final.scale[a] ||
          std::nearbyint(q.offset[a]) != q.offset[a]) {
        plan.action = Requantize::Decode;
        return plan;
      }
      shift = shift || q.offset[a] != plan.final.offset[a];
    } else {
      if (used.decimal[axis]) {  // the sample looked decimal; the file is not
        plan.action = Requantize::Decode;
        return plan;
      }
      // Both binary scales: the sampled one holds every point (nothing outside), keep it, as
      // the PLY reader keeps its sampled quantization.
      plan.final.scale[a] = q.scale[a];
      plan.final.offset[a] = q.offset[a];
    }
  }
  plan.action = shift ? Requantize::Shift : Requantize::None;
  return plan;
}

void shiftPositions(PointCloud& cloud, const Quantization& to, bool parallel) {
  std::int64_t delta[3];
  for (int axis = 0; axis < 3; ++axis) {
    const auto a = std::size_t(axis);
    delta[axis] = std::llround((cloud.quantization.offset[a] - to.offset[a]) / to.scale[a]);
  }
  constexpr std::size_t kStep = std::size_t{1} << 16;
  const std::size_t pieces = (cloud.count + kStep - 1) / kStep;
  Int3* p = cloud.positions.data();
  forEachIndex(parallel, pieces, [&](std::size_t piece) {
    const std::size_t stop = std::min<std::size_t>(cloud.count, (piece + 1) * kStep);
    for (std::size_t i = piece * kStep; i < stop; ++i) {
      p[i] = {std::int32_t(p[i].x + delta[0]), std::int32_t(p[i].y + delta[1]),
              std::int32_t(p[i].z + delta[2])};
    }
  });
  cloud.quantization = to;
}

}  // namespace parallax::text
