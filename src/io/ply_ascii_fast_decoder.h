// Internal to the PLY reader: the fast path for ascii point records of the common shapes.
//
// Which properties go where, and how each is parsed, is resolved once per range, before the
// loop: a destination pointer and stride per property, and runs of properties of one kind
// (float, double, uchar) that are parsed by a loop typed for that kind. Numbers are parsed by
// short_decimal.h (SSE2 or SWAR, few branches, exact).
//
// It takes a line only when it can take it whole: every value "[-]digits[.digits]" (integers:
// digits only) followed by blanks or the line end, the right number of values, and (float
// properties) a value that rounds to float without a second parse. Any other line is left to the
// general LineParser (ply_ascii_decoder.cpp), which either decodes it (exponents, long
// mantissas, "+1", "255.0", float midpoints) or reports it with its line and property, so values
// and errors are exactly the general parser's.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/bounds.h"
#include "core/point_cloud.h"
#include "io/ply_property_map.h"

namespace parallax::ply {

class AsciiFastDecoder {
 public:
  // True when every property of `layout` is a scalar the fast path stores: positions all float
  // or all double; normals and intensity float; colours and classification uchar; extra scalar
  // columns float, double or uchar. (Lists, other integer types, double normals: the general
  // parser.)
  static bool supports(const PointLayout& layout);

  // `cloud` has the columns of `layout` (allocatePointCloud) and must outlive the decoder.
  // Requires supports(layout).
  AsciiFastDecoder(const PointLayout& layout, PointCloud& cloud);
  // The slots of positions point into the decoder itself.
  AsciiFastDecoder(const AsciiFastDecoder&) = delete;
  AsciiFastDecoder& operator=(const AsciiFastDecoder&) = delete;

  // Decodes up to `count` records, one a line, from `p` into points first_index, first_index + 1,
  // ..., quantized with the cloud's quantization (clamped, as decodeAsciiRange does), their raw
  // positions added to `raw_bounds`. Returns how many it decoded; `p` is then the start of the
  // line after them: when fewer than `count`, the line it does not take. `end` is the end of the
  // file's bytes (never read past).
  std::uint64_t decode(const char*& p, const char* end, std::uint64_t count,
                       std::uint64_t first_index, Bounds3& raw_bounds);

 private:
  enum class Kind : std::uint8_t { Float32, Float64, UInt8 };
  struct Slot {
    std::byte* base;     // value of point i at base + i * stride
    std::size_t stride;  // 0 for positions: they go to the decoder's scratch, then quantized
  };
  struct Run {
    Kind kind;
    std::size_t first_slot;
    std::size_t slot_count;
  };

  template <class Position>
  std::uint64_t decodeRecords(const char*& p, const char* end, std::uint64_t count,
                              std::uint64_t first_index, Bounds3& raw_bounds);

  std::vector<Slot> slots_;  // in file order
  std::vector<Run> runs_;    // consecutive slots of one kind
  bool double_positions_ = false;
  float position32_[3] = {};
  double position64_[3] = {};
  const Quantization& quantization_;
  Int3* positions_;
};

}  // namespace parallax::ply
