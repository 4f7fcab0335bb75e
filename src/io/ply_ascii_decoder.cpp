// Ascii PLY bodies: range planning at line boundaries, and a single-pass line parser.
//
// One record per line (what every writer does). Planning counts line ends in parallel blocks, so
// each range knows its first record and line number and ranges parse independently. Common
// layouts go through AsciiFastDecoder (ply_ascii_fast_decoder.h); the general LineParser here
// takes every line it leaves, and every layout it does not support. Numbers: decimal_parse.h,
// then fast_float for what it declines. No locale, no allocation.
#include <fast_float/fast_float.h>
#include <tbb/parallel_for.h>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>

#include "core/error.h"
#include "io/ascii_chars.h"
#include "io/decimal_parse.h"
#include "io/ply_ascii_fast_decoder.h"
#include "io/ply_decoder.h"

namespace parallax::ply {
namespace {

std::uint64_t countLineEnds(const char* begin, const char* end) {
  std::uint64_t lines = 0;
#if defined(__SSE2__)
  // 16 bytes a step: each compare gives -1 per line end, summed in byte lanes for up to 255 steps
  // and then folded with psadbw (std::count does not vectorise like this at -O2, and the baseline
  // x86-64 target has no popcnt instruction).
  const __m128i newline = _mm_set1_epi8('\n');
  while (end - begin >= 16) {
    __m128i sums = _mm_setzero_si128();
    for (int step = 0; step < 255 && end - begin >= 16; ++step, begin += 16) {
      __m128i block = _mm_loadu_si128(reinterpret_cast<const __m128i*>(begin));
      sums = _mm_sub_epi8(sums, _mm_cmpeq_epi8(block, newline));
    }
    __m128i folded = _mm_sad_epu8(sums, _mm_setzero_si128());
    lines += std::uint64_t(_mm_cvtsi128_si64(folded)) +
             std::uint64_t(_mm_cvtsi128_si64(_mm_unpackhi_epi64(folded, folded)));
  }
#endif
  return lines + std::uint64_t(std::count(begin, end, '\n'));
}

const char* nextLineStart(const char* p, const char* end) {
  const void* found = std::memchr(p, '\n', std::size_t(end - p));
  return found ? static_cast<const char*>(found) + 1 : end;
}

// Inclusive value limits of each integer type, for range checks.
void integerLimits(ScalarType type, double& lo, double& hi) {
  switch (type) {
    case ScalarType::Int8:
      lo = -128, hi = 127;
      return;
    case ScalarType::UInt8:
      lo = 0, hi = 255;
      return;
    case ScalarType::Int16:
      lo = -32768, hi = 32767;
      return;
    case ScalarType::UInt16:
      lo = 0, hi = 65535;
      return;
    case ScalarType::Int32:
      lo = -2147483648.0, hi = 2147483647.0;
      return;
    case ScalarType::UInt32:
      lo = 0, hi = 4294967295.0;
      return;
    default:
      lo = -std::numeric_limits<double>::max(), hi = std::numeric_limits<double>::max();
  }
}

class LineParser {
 public:
  LineParser(const DecodeContext& context, const PointLayout& layout, const char* end)
      : context_(context), layout_(layout), end_(end) {}

  // Parses the record at `p` (one line); returns the start of the next line.
  const char* parse(const char* p, std::uint64_t line, PointCloud& cloud, std::uint64_t index,
                    double xyz[3]) {
    line_ = line;
    std::size_t values = 0;
    for (const auto& plan : layout_.properties) {
      if (plan.is_list) {
        double items = parseNumber(p, plan, plan.list_count_type, values, "list count");
        ++values;
        if (items < 0) fail(plan, "a list count of 0 or more", std::to_string(std::int64_t(items)));
        for (std::uint64_t k = 0; k < std::uint64_t(items); ++k) {
          skipBlanks(p);
          if (p == end_ || *p == '\n') {
            fail(plan, "a list of " + std::to_string(std::uint64_t(items)) + " items",
                 std::to_string(k) + " before the end of the line");
          }
          parseNumber(p, plan, plan.type, values, "list item");
        }
        continue;
      }
      double value = parseNumber(p, plan, plan.type, values, "");
      ++values;
      int axis = int(plan.target) - int(Target::X);
      if (axis >= 0 && axis < 3) {
        if (!std::isfinite(value)) {
          failNonFinite(plan, value);
        }
        xyz[axis] = value;
      } else {
        storeAttribute(cloud, plan, index, value);
      }
    }
    skipBlanks(p);
    if (p != end_ && *p != '\n') failTooManyValues(values, p);
    return p == end_ ? p : p + 1;
  }

 private:
  void skipBlanks(const char*& p) const {
    while (p != end_ && isBlank(*p)) ++p;
  }

  [[gnu::always_inline]] double parseNumber(const char*& p, const PropertyPlan& plan,
                                            ScalarType type, std::size_t index, const char* what) {
    skipBlanks(p);
    if (p == end_ || *p == '\n') failMissingValue(plan, index, what);
    double value = 0.0;
    int fraction = 0;
    const char* stop = decimal::parseSimpleDecimal(p, end_, value, fraction);
    // A float property means the float nearest to the text. Rounding the nearest double to float
    // gives it except when that double sits next to a midpoint between two floats (or outside the
    // normal range): then the text is parsed again as a float.
    if (stop != nullptr && type == ScalarType::Float32 && !decimal::roundsSafelyToFloat(value)) {
      stop = nullptr;
    }
    if (stop == nullptr) {
      stop = parseGeneral(p, type, value);
    } else if (type == ScalarType::Float32) {
      value = double(narrowToFloat(value));
    }
    // Integer properties accept whole numbers in any spelling ("255", "255.000000", "2.55e2"):
    // some writers print every value as a float.
    if (!isFloatingPoint(type) && stop != p && value != std::trunc(value)) stop = p;
    if (stop == p || (stop != end_ && !isDelimiter(*stop))) {
      failNotANumber(plan, type, p);
    }
    if (!isFloatingPoint(type)) {
      double lo, hi;
      integerLimits(type, lo, hi);
      if (value < lo || value > hi) failOutOfRange(plan, type, p, stop);
    }
    p = stop;
    return value;
  }

  [[noreturn, gnu::noinline, gnu::cold]] void failTooManyValues(std::size_t values, const char* p) {
    const char* token_end = p;
    while (token_end != end_ && *token_end != '\n' && !isBlank(*token_end)) ++token_end;
    failLine("", "", std::to_string(values) + " values, one per property",
             "more: " + quoteInput(std::string_view(p, std::size_t(token_end - p))));
  }

  // The error paths, kept out of line so the parsing loop stays small.
  [[noreturn, gnu::noinline, gnu::cold]] void failMissingValue(const PropertyPlan& plan,
                                                               std::size_t index,
                                                               const char* what) {
    failLine(plan.name, "", std::to_string(expectedValues()) + " values, one per property",
             std::to_string(index) + " (the line ends before this " +
                 (what[0] ? std::string(what) : std::string("value")) + ")");
  }

  [[noreturn, gnu::noinline, gnu::cold]] void failNotANumber(const PropertyPlan& plan,
                                                             ScalarType type, const char* p) {
    const char* token_end = p;
    while (token_end != end_ && *token_end != '\n' && !isBlank(*token_end)) ++token_end;
    failLine(plan.name, "",
             isFloatingPoint(type) ? std::string("a number")
                                   : "an integer (" + std::string(scalarName(type)) + ")",
             quoteInput(std::string_view(p, std::size_t(token_end - p))));
  }

  [[noreturn, gnu::noinline, gnu::cold]] void failOutOfRange(const PropertyPlan& plan,
                                                             ScalarType type, const char* p,
                                                             const char* stop) {
    double lo, hi;
    integerLimits(type, lo, hi);
    failLine(plan.name, "",
             "a value of type " + std::string(scalarName(type)) + " (" +
                 std::to_string(std::int64_t(lo)) + " to " + std::to_string(std::int64_t(hi)) + ")",
             std::string(p, std::size_t(stop - p)));
  }

  // Exponents, long mantissas, inf and nan: fast_float, which (like strtod) takes no '+'.
  const char* parseGeneral(const char* p, ScalarType type, double& value) const {
    const char* start = p;
    if (p != end_ && *p == '+' && p + 1 != end_ && p[1] != '-' && p[1] != '+') ++p;
    if (type == ScalarType::Float32) {
      float narrow = 0.0f;
      auto result = fast_float::from_chars(p, end_, narrow);
      bool parsed = result.ec == std::errc() || result.ec == std::errc::result_out_of_range;
      value = narrow;
      return parsed ? result.ptr : start;
    }
    auto result = fast_float::from_chars(p, end_, value);
    bool parsed = result.ec == std::errc() || result.ec == std::errc::result_out_of_range;
    return parsed ? result.ptr : start;
  }

  std::size_t expectedValues() const { return layout_.properties.size(); }

  [[noreturn, gnu::noinline, gnu::cold]] void failNonFinite(const PropertyPlan& plan,
                                                            double value) {
    fail(plan, "a finite coordinate", std::to_string(value),
         "remove invalid points first (e.g. PDAL filters.range)");
  }

  [[noreturn, gnu::noinline, gnu::cold]] void fail(const PropertyPlan& plan, std::string expected,
                                                   std::string found, std::string hint = "") {
    failLine(plan.name, std::move(hint), std::move(expected), std::move(found));
  }

  [[noreturn, gnu::noinline, gnu::cold]] void failLine(const std::string& property,
                                                       std::string hint, std::string expected,
                                                       std::string found) {
    InputErrorInfo info{.file = context_.file,
                        .element = layout_.element_name,
                        .property = property,
                        .expected = std::move(expected),
                        .found = std::move(found),
                        .hint = std::move(hint)};
    if (line_ != 0) info.line = line_;
    throw InputError(std::move(info));
  }

  const DecodeContext& context_;
  const PointLayout& layout_;
  const char* end_;
  std::uint64_t line_ = 0;
};

[[noreturn]] void failShortElement(const DecodeContext& context, const PlyElement& element,
                                   std::uint64_t records, std::uint64_t line) {
  throw InputError({.file = context.file,
                    .line = line,
                    .element = element.name,
                    .expected = std::to_string(element.count) + " lines",
                    .found = "the end of the file after " + std::to_string(records),
                    .hint = "the file is truncated, or its header's count is wrong"});
}

// Past the records of `element` (one a line) from `p`, each checked against its properties and
// none kept; `line` advances with them.
const char* skipAsciiElement(const DecodeContext& context, const PlyElement& element, const char* p,
                             std::uint64_t& line) {
  const char* end = reinterpret_cast<const char*>(context.bytes.data()) + context.bytes.size();
  PointLayout skipping = skippingLayout(element);
  LineParser parser(context, skipping, end);
  PointCloud nothing;
  for (std::uint64_t r = 0; r < element.count; ++r, ++line) {
    if (p == end) failShortElement(context, element, r, line);
    double unused[3];
    p = parser.parse(p, line, nothing, 0, unused);
  }
  return p;
}

// Byte offset of element `index` in an ascii body, past the elements before it, whose records
// (one a line) are each checked against their properties; `line` is set to its first line.
std::size_t locateAsciiElement(const DecodeContext& context, int index, std::uint64_t& line) {
  const char* text = reinterpret_cast<const char*>(context.bytes.data());
  const char* p = text + context.header.body_offset;
  line = context.header.body_line;
  for (int e = 0; e < index; ++e) {
    p = skipAsciiElement(context, context.header.elements[std::size_t(e)], p, line);
  }
  return std::size_t(p - text);
}

}  // namespace

std::vector<RecordRange> planAsciiRanges(const DecodeContext& context, std::size_t target_bytes,
                                         bool parallel) {
  const char* text = reinterpret_cast<const char*>(context.bytes.data());
  const char* end = text + context.bytes.size();
  const int point_element = context.header.pointElement();

  std::uint64_t line = 0;
  const char* p = text + locateAsciiElement(context, point_element, line);
  const PlyElement& element = context.header.elements[std::size_t(point_element)];
  // Each record has at least one character per value plus a separator: a count the rest of the
  // file cannot hold is refused before anything is counted or allocated.
  const std::size_t left = std::size_t(end - p);
  const std::uint64_t min_line = 2 * context.layout.properties.size();
  if (element.count > (left + 1) / min_line) {
    throw InputError({.file = context.file,
                      .line = line,
                      .element = element.name,
                      .expected = std::to_string(element.count) + " lines of at least " +
                                  std::to_string(min_line) + " bytes",
                      .found = std::to_string(left) + " bytes left in the file",
                      .hint = "the file is truncated, or its header's count is wrong"});
  }

  // Blocks of about target_bytes, cut after a line end.
  // Pages are given back kReleaseBlocks blocks at a time: each release is a system call and a
  // TLB flush on every core (one a block was about 15 us each, 1 500 a 377 MB file, half of them
  // in this serial loop), and a batch keeps at most a few MB more mapped.
  constexpr std::size_t kReleaseBlocks = 8;
  std::vector<const char*> starts;
  for (const char* s = p; s < end;) {
    starts.push_back(s);
    const char* next = s + std::min<std::size_t>(target_bytes, std::size_t(end - s));
    s = next == end ? end : nextLineStart(next, end);
    // One touch per block can map a whole large page-cache folio (up to 2 MiB), not just 64 KiB:
    // give back what the search mapped before moving on.
    if (starts.size() % kReleaseBlocks == 0 || s == end) {
      context.releaseRead(
          std::size_t(starts[(starts.size() - 1) / kReleaseBlocks * kReleaseBlocks] - text),
          std::size_t(s - text));
    }
  }
  std::vector<std::uint64_t> lines(starts.size());
  auto count_block = [&](std::size_t b) {
    const char* block_end = b + 1 < starts.size() ? starts[b + 1] : end;
    lines[b] = countLineEnds(starts[b], block_end);
    // A last line without its line end still holds a record.
    if (block_end == end && block_end > starts[b] && block_end[-1] != '\n') ++lines[b];
    // (A block of the batch still being counted on another core just faults its pages again.)
    if (b % kReleaseBlocks == kReleaseBlocks - 1 || block_end == end) {
      context.releaseRead(std::size_t(starts[b - b % kReleaseBlocks] - text),
                          std::size_t(block_end - text));
    }
  };
  if (parallel) {
    tbb::parallel_for(std::size_t(0), starts.size(), count_block);
  } else {
    for (std::size_t b = 0; b < starts.size(); ++b) count_block(b);
  }

  std::vector<RecordRange> ranges;
  std::uint64_t first = 0;
  for (std::size_t b = 0; b < starts.size() && first < element.count; ++b) {
    std::uint64_t take = std::min(lines[b], element.count - first);
    if (take > 0) {
      ranges.push_back({first, take, std::size_t(starts[b] - text), line + first});
    }
    first += lines[b];
  }
  if (first < element.count) {
    throw InputError({.file = context.file,
                      .line = line + first,
                      .element = element.name,
                      .expected = std::to_string(element.count) + " lines, one per record",
                      .found = "the end of the file after " + std::to_string(first),
                      .hint = "the file is truncated, or its header's count is wrong"});
  }
  return ranges;
}

void checkAsciiTail(const DecodeContext& context, std::size_t end, std::uint64_t line) {
  const char* text = reinterpret_cast<const char*>(context.bytes.data());
  const char* stop = text + context.bytes.size();
  const int point_element = context.header.pointElement();
  const PlyElement& points = context.header.elements[std::size_t(point_element)];
  if (points.count == 0) {
    // Nothing was decoded: the point element starts where the elements before it ended.
    end = locateAsciiElement(context, point_element, line);
  }
  const char* p = text + std::max(end, context.header.body_offset);
  for (std::size_t e = std::size_t(point_element) + 1; e < context.header.elements.size(); ++e) {
    p = skipAsciiElement(context, context.header.elements[e], p, line);
  }
  const PlyElement& last = context.header.elements.back();
  for (; p < stop; ++p) {
    if (*p == '\n') {
      ++line;
    } else if (!isBlank(*p)) {
      const char* data_end = p;
      while (data_end < stop && *data_end != '\n' && *data_end != '\r') ++data_end;
      throw InputError(
          {.file = context.file,
           .line = line,
           .element = last.name,
           .expected = "the end of the file after " + std::to_string(last.count) + " records",
           .found = "more data: " + quoteInput(std::string_view(p, std::size_t(data_end - p))),
           .hint = "the header's element count is smaller than the data"});
    }
  }
}

RangeStats decodeAsciiRange(const DecodeContext& context, const RecordRange& range,
                            std::uint64_t count, PointCloud& cloud, std::uint64_t first_index) {
  const char* text = reinterpret_cast<const char*>(context.bytes.data());
  const char* end = text + context.bytes.size();
  const char* p = text + range.begin;
  LineParser parser(context, context.layout, end);
  RangeStats stats;
  const Quantization& q = cloud.quantization;
  const double inverse[3] = {1.0 / q.scale[0], 1.0 / q.scale[1], 1.0 / q.scale[2]};
  Bounds3& bounds = stats.raw_bounds;
  // The fast path takes the lines it can take whole; each line it leaves goes to the general
  // parser, which decodes it or reports it. Where it takes none (8 refusals in a row: a file of
  // exponents, say), the general parser alone does the rest of the range.
  std::optional<AsciiFastDecoder> fast;
  if (AsciiFastDecoder::supports(context.layout)) fast.emplace(context.layout, cloud);
  int refused_in_a_row = 0;
  for (std::uint64_t r = 0; r < count; ++r) {
    if (fast) {
      const std::uint64_t decoded = fast->decode(p, end, count - r, first_index + r, bounds);
      r += decoded;
      if (r == count) break;
      refused_in_a_row = decoded > 0 ? 1 : refused_in_a_row + 1;
      if (refused_in_a_row == 8) fast.reset();
    }
    double xyz[3];
    std::uint64_t line = range.first_line == 0 ? 0 : range.first_line + r;
    p = parser.parse(p, line, cloud, first_index + r, xyz);
    bounds.extend(xyz[0], xyz[1], xyz[2]);
    cloud.positions[first_index + r] = {quantizeClamped(xyz[0], q.offset[0], inverse[0]),
                                        quantizeClamped(xyz[1], q.offset[1], inverse[1]),
                                        quantizeClamped(xyz[2], q.offset[2], inverse[2])};
  }
  stats.end = std::size_t(p - text);
  return stats;
}

}  // namespace parallax::ply
