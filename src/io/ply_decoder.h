// Internal to the PLY reader: the body of a PLY file cut into ranges of records, and the
// decoders that turn one range into columns. Ranges are independent, so they decode in parallel.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "core/point_cloud.h"
#include "io/mapped_file.h"
#include "io/ply_header.h"
#include "io/ply_property_map.h"

namespace parallax::ply {

struct DecodeContext {
  std::span<const std::byte> bytes;  // the whole file
  const std::string& file;
  const PlyHeader& header;
  const PointLayout& layout;
  // When the bytes are a mapped file: pages read are released as passes go (see MappedFile).
  const MappedFile* mapping = nullptr;

  // Releases [begin, end) and the 2 MiB before it: where the page cache holds a file in large
  // folios, a fault maps the whole folio, behind the reader too, so pages released by the range
  // before come back mapped.
  void releaseRead(std::size_t begin, std::size_t end) const {
    constexpr std::size_t kLargeFolio = 2 << 20;
    begin = begin > kLargeFolio ? begin - kLargeFolio : 0;
    if (mapping != nullptr && end > begin) mapping->releaseRead(begin, end - begin);
  }
};

// Records [first_record, first_record + count) of the point element, starting at byte `begin`.
// `first_line` is the 1-based line of the first record in an ascii body (0 when unknown).
struct RecordRange {
  std::uint64_t first_record = 0;
  std::uint64_t count = 0;
  std::size_t begin = 0;
  std::uint64_t first_line = 0;
};

// What a range held, from the raw coordinates before quantization. (A NaN or infinite coordinate
// is an InputError at its record: it has no place in bounds nor in an int32.)
struct RangeStats {
  Bounds3 raw_bounds;
  std::size_t end = 0;  // the byte after the last record decoded
};

// Cuts the point element into ranges of about `target_bytes` of input each. Checks first that the
// file can hold what the header announces (skipping the elements before the point element, with
// every count checked against the bytes left), so nothing is allocated on a lying header.
// Throws InputError for a truncated body, a bad list count, or (ascii) too few lines.
std::vector<RecordRange> planRanges(const DecodeContext& context, std::size_t target_bytes,
                                    bool parallel);

// Decodes the first `count` records of `range` into `cloud` at `first_index` (count <= range
// count), quantizing positions with cloud.quantization (clamped when out of range: the caller
// checks the returned bounds). Throws InputError with the byte offset or line of a bad value.
RangeStats decodeRange(const DecodeContext& context, const RecordRange& range, std::uint64_t count,
                       PointCloud& cloud, std::uint64_t first_index);

// Bounds of a sample of at most `max_samples` records spread over the element (malformed sampled
// records are skipped here: the full decode reports them with their position).
Bounds3 sampleBounds(const DecodeContext& context, const std::vector<RecordRange>& ranges,
                     std::size_t max_samples);
// What the readers sample (the whole read and the preview choose the same quantization): 4096
// records, the bounds widened 16-fold so that points the sample missed still fit.
inline constexpr std::size_t kQuantizationSamples = 4096;
inline constexpr double kQuantizationSampleMargin = 16.0;

// Checks what follows the point element of an ascii body, from byte `end` (just after its last
// record) and line `line`: every record of the elements after it, then nothing but blanks.
// Throws InputError for a malformed or missing record, or data past the last element (a count
// smaller than the data).
void checkAsciiTail(const DecodeContext& context, std::size_t end, std::uint64_t line);

// The format-specific halves behind the three functions above.
std::vector<RecordRange> planBinaryRanges(const DecodeContext& context, std::size_t target_bytes);
std::vector<RecordRange> planAsciiRanges(const DecodeContext& context, std::size_t target_bytes,
                                         bool parallel);
RangeStats decodeBinaryRange(const DecodeContext& context, const RecordRange& range,
                             std::uint64_t count, PointCloud& cloud, std::uint64_t first_index);
// The fixed-size binary decode (layout.fixed_size) of `count` records of `range` whose bytes are
// at `records` (the mapped file at range.begin, or a copy of them read into a buffer); offsets in
// errors are the file's. Writes the defaults of the channels the file lacks for these points.
RangeStats decodeFixedRecords(const DecodeContext& context, const std::byte* records,
                              const RecordRange& range, std::uint64_t count, PointCloud& cloud,
                              std::uint64_t first_index);
RangeStats decodeAsciiRange(const DecodeContext& context, const RecordRange& range,
                            std::uint64_t count, PointCloud& cloud, std::uint64_t first_index);

// Rounds to the nearest integer (ties to even) and clamps to int32 without undefined behaviour;
// NaN gives INT32_MIN. The magic-number form avoids a libm call in the hot loops, and the clamps
// are selects (maxsd, minsd), not branches, so the loops that call it stay branch-free.
inline std::int32_t quantizeClamped(double world, double offset, double inverse_scale) {
  double q = (world - offset) * inverse_scale;
  // Written as x86's maxsd and minsd compare (strict, the constant when q is NaN), so that the
  // compiler may use them: with >= or <= it must keep branches for the sign of zero.
  q = q > -2147483648.0 ? q : -2147483648.0;  // NaN too
  q = q < 2147483647.0 ? q : 2147483647.0;
  constexpr double kRound = 6755399441055744.0;  // 1.5 * 2^52
  return std::int32_t((q + kRound) - kRound);
}

}  // namespace parallax::ply
