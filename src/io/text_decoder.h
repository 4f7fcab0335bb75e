// Internal to the text reader (text_reader.h): the body of a text point file cut into blocks of
// whole lines, the parse of lines straight into columns (positions quantized as they are read,
// never held as doubles), and the choice of the quantization from what the positions look like.
//
// Positions need a quantization before the first one is stored. The whole-file read chooses it
// from a sample of lines taken while the lines are counted (planBlocks), decodes with it, and
// checks it against what the decode saw of every position (their exact bounds and decimals):
// equal, or only whole offsets apart (the integers are shifted, exactly), or, rarely, decoded
// again (the sample missed a longer decimal or a far outlier). The chunk reader, which cannot go
// back, first parses the positions alone to know them exactly.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "core/bounds.h"
#include "core/point_cloud.h"
#include "core/quantization.h"
#include "io/mapped_file.h"
#include "io/text_layout.h"

namespace parallax::text {

// Digits after the decimal point of a value not in plain decimal notation (an exponent, over 15
// significant digits): no decimal scale holds it.
constexpr int kNotDecimal = 10;

// What a parse saw of the positions: their exact bounds as written, and how they are written.
struct PositionStats {
  Bounds3 raw;
  int decimals[3] = {0, 0, 0};  // most digits after the point, per axis (kNotDecimal: see above)
  bool outside[3] = {false, false, false};  // a value fell outside the quantization (clamped)

  void merge(const PositionStats& other);
};

// One block of whole lines of the body, parsed by one task.
struct Block {
  std::size_t begin = 0, end = 0;  // byte range in the text
  std::uint64_t first_line = 0;    // 1-based number of its first line
  std::uint64_t first_point = 0;   // index of its first point in the file
  std::uint64_t points = 0;
  std::uint64_t lines = 0;
};

struct BodyPlan {
  std::vector<Block> blocks;
  std::uint64_t points = 0;
  PositionStats sample;  // of the sampled lines (every line when `exact`)
  bool exact = false;    // the sample is every point: its stats are the file's
};

// Cuts the body into blocks of about 1 MiB ending at line ends, counts each block's lines and
// points, and samples positions from about 4096 lines spread evenly over the body, all in one
// pass over the bytes (in parallel unless `parallel` is false). A small body (at most 64 Ki
// points) is parsed whole for its positions instead, so its stats are exact. Pages of `file`
// (when the bytes are mapped) are released as they are passed.
BodyPlan planBody(std::string_view text, const Layout& layout, const std::string& file_name,
                  const MappedFile* file, bool parallel);

struct ParseOutput {
  PointCloud* cloud = nullptr;                 // null: positions are parsed for their stats only
  std::uint64_t first_index = 0;               // where the first point goes in `cloud`
  const Quantization* quantization = nullptr;  // of the positions stored (with `cloud`)
  bool positions_only = false;  // x, y, z alone are parsed; the other columns are skipped unread
};

struct ParseResult {
  PositionStats stats;
  std::size_t end = 0;       // byte after the last line consumed
  std::uint64_t lines = 0;   // lines consumed
  std::uint64_t points = 0;  // points parsed
};

// Parses the lines of text[begin, end) (`begin` a line start numbered `first_line`) until
// `max_points` points are read or `end` is reached. Throws InputError naming `file`, the line and
// the column for a value that is not a number, a non-finite position, a wrong number of values.
ParseResult parseLines(std::string_view text, std::size_t begin, std::size_t end,
                       std::uint64_t first_line, std::uint64_t max_points, const Layout& layout,
                       const std::string& file, const ParseOutput& out);

// Columns for `count` points of `layout`, untouched (the parse's first write faults them in);
// source types as text gives them.
PointCloud allocateTextCloud(const Layout& layout, std::uint64_t count);

// The quantization of positions whose exact stats are `exact`: per axis, the decimal scale
// 10^-d (d = most decimals, at most 9) with offset 0 when the values fit, else a whole number at
// the centre; chooseQuantization's power-of-two scale when no decimal scale fits (text_reader.h).
Quantization exactTextQuantization(const PositionStats& exact);

// exactTextQuantization, with which axes got a decimal scale (for planRequantize).
struct SampledQuantization;
SampledQuantization exactTextChoice(const PositionStats& exact);

// A quantization chosen from a sample: the same decimal scale when the sample's values are
// decimal, with an offset that leaves room (16x the sampled half extent) for what the sample
// missed; else chooseQuantization with that margin. `decimal[axis]` says which kind each is.
struct SampledQuantization {
  Quantization quantization;
  bool decimal[3] = {false, false, false};
};
SampledQuantization sampledTextQuantization(const PositionStats& sample);

// What positions decoded with `used` need to be exact: nothing (`final` == used), a shift of
// whole offsets (`final` has other offsets, the same scales), or a new decode with `final`.
enum class Requantize { None, Shift, Decode };
struct RequantizePlan {
  Requantize action = Requantize::None;
  Quantization final;
};
RequantizePlan planRequantize(const SampledQuantization& used, const PositionStats& exact);

// Moves `cloud`'s integers from its quantization to `to`, whose scales are the same and whose
// offsets differ by whole multiples of them (planRequantize's Shift), exactly.
void shiftPositions(PointCloud& cloud, const Quantization& to, bool parallel);

}  // namespace parallax::text
