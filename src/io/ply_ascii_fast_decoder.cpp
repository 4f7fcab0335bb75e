// The fast path for ascii point records: destinations resolved before the loop, typed loops per
// run of properties of one kind, SSE2/SWAR number parsing. See ply_ascii_fast_decoder.h for what it
// takes and what it leaves to the general parser.
#include "io/ply_ascii_fast_decoder.h"

#include <bit>
#include <cassert>
#include <cstring>

#include "io/ascii_chars.h"
#include "io/ply_decoder.h"
#include "io/short_decimal.h"

namespace parallax::ply {
namespace {

[[gnu::noinline]] const char* skipBlanks(const char* q, const char* last_start) {
  while (q <= last_start && isBlank(*q)) ++q;
  return q;
}

// One past the first ' ' or '\n' among the 16 bytes at `q` (past q + 16 when there is none).
// When the field at q is a number followed by one of them, that is where the next field (or
// line) starts. It is found from the bytes alone, not from the number's parse, so that the chain
// of dependent work from one field to the next is one load and a few ALU operations: the parses
// of successive fields then overlap in the CPU. (Waiting for each parse to know where the next
// field starts made a chain of about 30 cycles per value, the bottleneck.)
[[gnu::always_inline]] inline const char* pastDelimiter(const char* q) {
#if defined(PARALLAX_SHORT_DECIMAL_SSE2)
  const __m128i raw = _mm_loadu_si128(reinterpret_cast<const __m128i*>(q));
  const __m128i ends = _mm_or_si128(_mm_cmpeq_epi8(raw, _mm_set1_epi8(' ')),
                                    _mm_cmpeq_epi8(raw, _mm_set1_epi8('\n')));
  return q + std::countr_zero(unsigned(_mm_movemask_epi8(ends)) | (1u << 17)) + 1;
#else
  int i = 0;
  while (i < 16 && q[i] != ' ' && q[i] != '\n') ++i;
  return q + (i < 16 ? i : 17) + 1;
#endif
}

// Bit i set when line[i] is ' ' or '\n', for i < 64 (64 bytes readable). Computed once for
// about seven fields from four loads, so that the fields' ends come from bit scans: the chain
// from field to field shrinks to a bit scan and a bit clear.
[[gnu::always_inline]] inline std::uint64_t delimiterMask64(const char* line) {
#if defined(PARALLAX_SHORT_DECIMAL_SSE2)
  auto mask16 = [](const char* at) {
    const __m128i raw = _mm_loadu_si128(reinterpret_cast<const __m128i*>(at));
    const __m128i ends = _mm_or_si128(_mm_cmpeq_epi8(raw, _mm_set1_epi8(' ')),
                                      _mm_cmpeq_epi8(raw, _mm_set1_epi8('\n')));
    return std::uint64_t(unsigned(_mm_movemask_epi8(ends)));
  };
  return mask16(line) | mask16(line + 16) << 16 | mask16(line + 32) << 32 | mask16(line + 48) << 48;
#else
  std::uint64_t mask = 0;
  for (int i = 0; i < 64; ++i) mask |= std::uint64_t(line[i] == ' ' || line[i] == '\n') << i;
  return mask;
#endif
}

// A delimiter mask reads 64 bytes, and the fields it covers read ahead from there.
constexpr std::ptrdiff_t kMaskReach = 64 + decimal::kShortNumberReadAhead;

// Each parses the number at q (kShortNumberReadAhead bytes readable) into `destination` and
// returns the byte after it, or nullptr when the number is not one it takes whole. The caller
// checks what follows.
[[gnu::always_inline]] inline const char* parseFloat32(const char* q, std::byte* destination) {
  decimal::ShortDecimal number;
  const char* stop = decimal::scanShortDecimal(q, number);
  float value;
  // nearestFloat declines a value next to a float midpoint: the general parser then parses the
  // text again as a float.
  if (stop == nullptr || !decimal::nearestFloat(number, value)) return nullptr;
  std::memcpy(destination, &value, sizeof value);
  return stop;
}

[[gnu::always_inline]] inline const char* parseFloat64(const char* q, std::byte* destination) {
  decimal::ShortDecimal number;
  const char* stop = decimal::scanShortDecimal(q, number);
  if (stop == nullptr) return nullptr;
  const double value = decimal::exactDouble(number);
  std::memcpy(destination, &value, sizeof value);
  return stop;
}

[[gnu::always_inline]] inline const char* parseUInt8(const char* q, std::byte* destination) {
  std::uint32_t value;
  const char* stop = decimal::parseShortUnsigned(q, value);
  if (stop == nullptr || value > 255) return nullptr;
  // A uchar colour, classification or scalar is stored as it is (toColor, the classification
  // rounding and setFromDouble are the identity on 0..255).
  *destination = std::byte(value);
  return stop;
}

// One field: the number at `at` (past blanks) parsed by `parse` into `destination`, `at` moved
// to the start of the next field, or of the next line after a '\n' (counted in `line_ends`).
// Where the field ends comes from `delimiters`, the delimiterMask64 of the 64 bytes at `base`,
// consumed a bit a field (one delimiter per field, across line ends too) and refilled at the
// field's start when empty; any irregularity (runs of blanks, tabs, "\r\n") puts it out of step
// with the fields, and it is emptied. Near the end of the bytes, pastDelimiter instead.
// False when the field is not one the fast path takes whole.
template <const char* (*parse)(const char*, std::byte*)>
[[gnu::always_inline]] inline bool parseField(const char*& at, const char* last_start,
                                              const char* end, const char*& base,
                                              std::uint64_t& delimiters, std::byte* destination,
                                              int& line_ends) {
  const char* q = at;
  if (isBlank(*q)) [[unlikely]] {
    q = skipBlanks(q, last_start);
    delimiters = 0;
  }
  if (q > last_start) return false;
  if (delimiters == 0 && end - q >= kMaskReach) {
    base = q;
    delimiters = delimiterMask64(q);
  }
  const char* after;
  if (delimiters != 0) [[likely]] {
    after = base + std::countr_zero(delimiters) + 1;
    delimiters &= delimiters - 1;
  } else {
    after = pastDelimiter(q);
  }
  const char* stop = parse(q, destination);
  if (stop == nullptr) return false;
  if (stop + 1 != after) [[unlikely]] {
    // Not one ' ' or '\n' right after the number: another blank ('\t', '\r'), or no delimiter.
    if (!isDelimiter(*stop)) return false;
    after = stop;
    delimiters = 0;
  }
  line_ends += after[-1] == '\n';
  at = after;
  return true;
}

}  // namespace

bool AsciiFastDecoder::supports(const PointLayout& layout) {
  const ScalarType position = layout.properties[std::size_t(layout.position_index[0])].type;
  if (position != ScalarType::Float32 && position != ScalarType::Float64) return false;
  for (const auto& plan : layout.properties) {
    if (plan.is_list) return false;
    switch (plan.target) {
      case Target::X:
      case Target::Y:
      case Target::Z:
        if (plan.type != position) return false;
        break;
      case Target::Red:
      case Target::Green:
      case Target::Blue:
      case Target::Alpha:
      case Target::Classification:
        if (plan.type != ScalarType::UInt8) return false;
        break;
      case Target::NormalX:
      case Target::NormalY:
      case Target::NormalZ:
      case Target::Intensity:
        if (plan.type != ScalarType::Float32) return false;
        break;
      case Target::Scalar:
        if (plan.type != ScalarType::Float32 && plan.type != ScalarType::Float64 &&
            plan.type != ScalarType::UInt8) {
          return false;
        }
        break;
      case Target::Skip:
        return false;
    }
  }
  return true;
}

AsciiFastDecoder::AsciiFastDecoder(const PointLayout& layout, PointCloud& cloud)
    : quantization_(cloud.quantization), positions_(cloud.positions.data()) {
  assert(supports(layout) && "AsciiFastDecoder needs a layout it supports");
  double_positions_ =
      layout.properties[std::size_t(layout.position_index[0])].type == ScalarType::Float64;
  auto bytes = [](auto* column) { return reinterpret_cast<std::byte*>(column); };
  for (const auto& plan : layout.properties) {
    const Kind kind = plan.type == ScalarType::Float32   ? Kind::Float32
                      : plan.type == ScalarType::Float64 ? Kind::Float64
                                                         : Kind::UInt8;
    Slot slot{nullptr, 0};
    switch (plan.target) {
      case Target::X:
      case Target::Y:
      case Target::Z: {
        const int axis = int(plan.target) - int(Target::X);
        slot.base = double_positions_ ? bytes(&position64_[axis]) : bytes(&position32_[axis]);
        break;
      }
      case Target::Red:
      case Target::Green:
      case Target::Blue:
      case Target::Alpha:
        slot = {bytes(cloud.colors.data()) + (int(plan.target) - int(Target::Red)), sizeof(Rgba8)};
        break;
      case Target::NormalX:
      case Target::NormalY:
      case Target::NormalZ:
        slot = {bytes(cloud.normals.data()) +
                    sizeof(float) * std::size_t(int(plan.target) - int(Target::NormalX)),
                sizeof(Float3)};
        break;
      case Target::Intensity:
        slot = {bytes(cloud.intensity.data()), sizeof(float)};
        break;
      case Target::Classification:
        slot = {bytes(cloud.classification.data()), 1};
        break;
      case Target::Scalar: {
        ScalarColumn& column = cloud.scalars[std::size_t(plan.scalar_index)];
        slot = {column.data.data(), scalarSize(column.type)};
        break;
      }
      case Target::Skip:
        break;
    }
    if (runs_.empty() || runs_.back().kind != kind) runs_.push_back({kind, slots_.size(), 0});
    ++runs_.back().slot_count;
    slots_.push_back(slot);
  }
}

std::uint64_t AsciiFastDecoder::decode(const char*& p, const char* end, std::uint64_t count,
                                       std::uint64_t first_index, Bounds3& raw_bounds) {
  return double_positions_ ? decodeRecords<double>(p, end, count, first_index, raw_bounds)
                           : decodeRecords<float>(p, end, count, first_index, raw_bounds);
}

template <class Position>
std::uint64_t AsciiFastDecoder::decodeRecords(const char*& p, const char* end, std::uint64_t count,
                                              std::uint64_t first_index, Bounds3& raw_bounds) {
  if (end - p < decimal::kShortNumberReadAhead) return 0;
  // A value must start at or before this byte (the number parsers read ahead).
  const char* const last_start = end - decimal::kShortNumberReadAhead;
  const char* base = p;
  std::uint64_t delimiters = 0;
  const Position* position;
  if constexpr (sizeof(Position) == sizeof(double)) {
    position = position64_;
  } else {
    position = position32_;
  }
  const Quantization& q = quantization_;
  const double inverse[3] = {1.0 / q.scale[0], 1.0 / q.scale[1], 1.0 / q.scale[2]};
  const Slot* const slots = slots_.data();
  // In registers for the loop; written back on every way out.
  const char* line = p;
  Bounds3 bounds = raw_bounds;
  struct WriteBack {
    const char*& p;
    const char*& line;
    Bounds3& raw_bounds;
    Bounds3& bounds;
    ~WriteBack() { p = line, raw_bounds = bounds; }
  } write_back{p, line, raw_bounds, bounds};
  for (std::uint64_t r = 0; r < count; ++r) {
    const std::uint64_t index = first_index + r;
    const char* at = line;
    // One typed loop per run of properties of one kind: the kind is not looked at per value.
    int line_ends = 0;
    for (const Run& run : runs_) {
      const Slot* slot = slots + run.first_slot;
      const Slot* const run_end = slot + run.slot_count;
      switch (run.kind) {
        case Kind::Float32:
          for (; slot != run_end; ++slot) {
            std::byte* destination = slot->base + index * slot->stride;
            if (!parseField<parseFloat32>(at, last_start, end, base, delimiters, destination,
                                          line_ends)) {
              return r;
            }
          }
          break;
        case Kind::Float64:
          for (; slot != run_end; ++slot) {
            std::byte* destination = slot->base + index * slot->stride;
            if (!parseField<parseFloat64>(at, last_start, end, base, delimiters, destination,
                                          line_ends)) {
              return r;
            }
          }
          break;
        case Kind::UInt8:
          for (; slot != run_end; ++slot) {
            std::byte* destination = slot->base + index * slot->stride;
            if (!parseField<parseUInt8>(at, last_start, end, base, delimiters, destination,
                                        line_ends)) {
              return r;
            }
          }
          break;
      }
    }
    // The line end: nearly always the '\n' right after the last value (the delimiter mask then
    // goes on into the next line). Else blanks ("\r\n" included) then '\n', or the end of the
    // bytes. A '\n' after any other value: too few values, for the general parser to report.
    const bool ended = at[-1] == '\n';
    if (line_ends != int(ended)) return r;
    if (!ended) [[unlikely]] {
      delimiters = 0;
      while (at != end && isBlank(*at)) ++at;
      if (at != end) {
        if (*at != '\n') return r;  // more values than properties: the general parser reports it
        ++at;
      }
    }
    const double x = position[0], y = position[1], z = position[2];
    bounds.extend(x, y, z);
    positions_[index] = {quantizeClamped(x, q.offset[0], inverse[0]),
                         quantizeClamped(y, q.offset[1], inverse[1]),
                         quantizeClamped(z, q.offset[2], inverse[2])};
    line = at;
  }
  return count;
}

}  // namespace parallax::ply
