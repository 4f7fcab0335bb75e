// Binary PLY bodies (little and big endian): range planning and decoding.
//
// Fixed-size records (no list property, the common case) are decoded one property at a time over
// a range that fits in L2: a typed, strided loop per property, chosen before the loop, so the hot
// loops have no per-value dispatch. Records with lists are walked one by one.
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <type_traits>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "core/error.h"
#include "io/ply_decoder.h"

namespace parallax::ply {
namespace {

template <class T, bool kSwap>
inline T load(const std::byte* p) {
  if constexpr (!kSwap || sizeof(T) == 1) {
    T value;
    std::memcpy(&value, p, sizeof(T));
    return value;
  } else {
    using Bits =
        std::conditional_t<sizeof(T) == 2, std::uint16_t,
                           std::conditional_t<sizeof(T) == 4, std::uint32_t, std::uint64_t>>;
    Bits bits;
    std::memcpy(&bits, p, sizeof(T));
    if constexpr (sizeof(T) == 2) bits = __builtin_bswap16(bits);
    if constexpr (sizeof(T) == 4) bits = __builtin_bswap32(bits);
    if constexpr (sizeof(T) == 8) bits = __builtin_bswap64(bits);
    return std::bit_cast<T>(bits);
  }
}

// Calls fn.template operator()<T, kSwap>() for the C++ type of `type`.
template <class Fn>
void dispatch(ScalarType type, bool swap, Fn&& fn) {
  auto go = [&]<class T>() {
    if (swap) {
      fn.template operator()<T, true>();
    } else {
      fn.template operator()<T, false>();
    }
  };
  switch (type) {
    case ScalarType::Int8:
      go.template operator()<std::int8_t>();
      break;
    case ScalarType::UInt8:
      go.template operator()<std::uint8_t>();
      break;
    case ScalarType::Int16:
      go.template operator()<std::int16_t>();
      break;
    case ScalarType::UInt16:
      go.template operator()<std::uint16_t>();
      break;
    case ScalarType::Int32:
      go.template operator()<std::int32_t>();
      break;
    case ScalarType::UInt32:
      go.template operator()<std::uint32_t>();
      break;
    case ScalarType::Float32:
      go.template operator()<float>();
      break;
    case ScalarType::Float64:
      go.template operator()<double>();
      break;
  }
}

double loadAsDouble(ScalarType type, bool swap, const std::byte* p) {
  double value = 0.0;
  dispatch(type, swap, [&]<class T, bool kSwap>() { value = double(load<T, kSwap>(p)); });
  return value;
}

bool needsSwap(PlyFormat format) {
  return (format == PlyFormat::BinaryBigEndian) != (std::endian::native == std::endian::big);
}

template <class T>
inline std::uint8_t colorFromValue(T v) {
  if constexpr (std::is_same_v<T, std::uint8_t>) {
    return v;
  } else if constexpr (std::is_floating_point_v<T>) {
    return colorFromUnit(double(v));
  } else if constexpr (sizeof(T) == 2) {
    return colorFrom16(double(v));
  } else {
    return colorFrom8(double(v));
  }
}

[[noreturn]] void failTruncated(const DecodeContext& context, const PlyElement& element,
                                std::uint64_t record, std::size_t needed_end) {
  throw InputError(
      {.file = context.file,
       .byte_offset = context.bytes.size(),
       .element = element.name,
       .expected = std::to_string(element.count) + " records (record " + std::to_string(record) +
                   " needs bytes up to " + std::to_string(needed_end) + ")",
       .found = "the end of the file at byte " + std::to_string(context.bytes.size()),
       .hint = "the file is truncated, or its header announces more records than it holds"});
}

[[noreturn]] void failNonFinite(const DecodeContext& context, const PropertyPlan& plan,
                                std::size_t offset, std::uint64_t record) {
  throw InputError({.file = context.file,
                    .byte_offset = offset,
                    .element = context.layout.element_name,
                    .property = plan.name,
                    .expected = "a finite coordinate",
                    .found = "NaN or infinity in record " + std::to_string(record),
                    .hint = "remove invalid points first (e.g. PDAL filters.range)"});
}

// Size of the record at `pos` of an element with lists; throws at a bad list count or the end.
std::size_t walkRecord(const DecodeContext& context, const PlyElement& element, bool swap,
                       std::size_t pos, std::uint64_t record) {
  const std::size_t size = context.bytes.size();
  std::size_t start = pos;
  for (const auto& property : element.properties) {
    if (!property.is_list) {
      pos += scalarSize(property.type);
      if (pos > size) failTruncated(context, element, record, pos);
      continue;
    }
    std::size_t count_size = scalarSize(property.list_count_type);
    if (pos + count_size > size) failTruncated(context, element, record, pos + count_size);
    double items = loadAsDouble(property.list_count_type, swap, context.bytes.data() + pos);
    std::size_t left = size - pos - count_size;
    if (items < 0 || items > double(left / scalarSize(property.type))) {
      throw InputError({.file = context.file,
                        .byte_offset = pos,
                        .element = element.name,
                        .property = property.name,
                        .expected = "a list count from 0 to " +
                                    std::to_string(left / scalarSize(property.type)) +
                                    " (what the file has left)",
                        .found = std::to_string(std::int64_t(items)),
                        .hint = "record " + std::to_string(record) + " is damaged"});
    }
    pos += count_size + std::size_t(items) * scalarSize(property.type);
  }
  return pos - start;
}

// The byte after element `element` that starts at `pos`, which is not kept but checked: its count
// against the bytes left (lists counted empty) before anything is walked, then fixed-size records
// by size and records with lists one by one (a walk bounded by the file's size).
std::size_t skipElement(const DecodeContext& context, const PlyElement& element, bool swap,
                        std::size_t pos) {
  std::size_t left = context.bytes.size() - std::min(pos, context.bytes.size());
  std::size_t min_size = element.minimumRecordSize();
  if (min_size > 0 && element.count > left / min_size) {
    failTruncated(context, element, left / min_size, pos + (left / min_size + 1) * min_size);
  }
  if (!element.hasLists()) return pos + element.count * min_size;
  for (std::uint64_t r = 0; r < element.count; ++r)
    pos += walkRecord(context, element, swap, pos, r);
  return pos;
}

// Byte offset of the point element, past the elements before it.
std::size_t locatePointElement(const DecodeContext& context, int point_element, bool swap) {
  std::size_t pos = context.header.body_offset;
  for (int e = 0; e < point_element; ++e) {
    pos = skipElement(context, context.header.elements[std::size_t(e)], swap, pos);
  }
  return pos;
}

// x, y and z of one type, in one pass: load, track bounds, quantize. Everything the loop reads
// or writes is a local or a restrict pointer, so nothing is reloaded or stored back per record
// (bounds and the finite flag through references were spilled to memory every iteration).
template <class T, bool kSwap>
bool quantizeSameTypePositions(const std::byte* __restrict base, std::size_t stride,
                               const std::size_t (&at)[3], std::size_t n, const double (&offset)[3],
                               const double (&inverse)[3], Int3* __restrict dst, double (&lo)[3],
                               double (&hi)[3]) {
  const std::size_t at_x = at[0], at_y = at[1], at_z = at[2];
  const double offset_x = offset[0], offset_y = offset[1], offset_z = offset[2];
  const double inverse_x = inverse[0], inverse_y = inverse[1], inverse_z = inverse[2];
  double lo_x = lo[0], lo_y = lo[1], lo_z = lo[2];
  double hi_x = hi[0], hi_y = hi[1], hi_z = hi[2];
  int finite = 1;  // an int: combined with & below, which keeps the loop free of branches
  for (std::size_t i = 0; i < n; ++i) {
    const std::byte* record = base + i * stride;
    const double x = double(load<T, kSwap>(record + at_x));
    const double y = double(load<T, kSwap>(record + at_y));
    const double z = double(load<T, kSwap>(record + at_z));
    // 0 for NaN and infinity
    finite &= int(std::abs(x) <= 1.7976931348623157e308) &
              int(std::abs(y) <= 1.7976931348623157e308) &
              int(std::abs(z) <= 1.7976931348623157e308);
    lo_x = x < lo_x ? x : lo_x, hi_x = x > hi_x ? x : hi_x;
    lo_y = y < lo_y ? y : lo_y, hi_y = y > hi_y ? y : hi_y;
    lo_z = z < lo_z ? z : lo_z, hi_z = z > hi_z ? z : hi_z;
    dst[i] = Int3{quantizeClamped(x, offset_x, inverse_x), quantizeClamped(y, offset_y, inverse_y),
                  quantizeClamped(z, offset_z, inverse_z)};
  }
  lo[0] = lo_x, lo[1] = lo_y, lo[2] = lo_z;
  hi[0] = hi_x, hi[1] = hi_y, hi[2] = hi_z;
  return finite != 0;
}

#if defined(__SSE2__)
// quantizeSameTypePositions for the layout nearly every file has: x, y, z adjacent, in that order,
// as float or double in the machine's byte order. One record's three values go through SSE2 as
// a pair (x, y) and a single (z), without branches: the scalar loop compiled to compares and
// jumps for its clamps and bounds (perf, 20 M points: 8 ns a record, most of a read's user
// time). The loop across records cannot be vectorised instead: the records' stride is the
// file's, and SSE2 has no gather. The results are the scalar loop's bit for bit: min/max keep
// its operand order (so a NaN picks the same side), and cvtpd2dq rounds to nearest even as its
// 1.5 * 2^52 addition does. Non-finite values are found by a sum of v - v, which is +0 for every
// finite v and NaN from the first NaN or infinity on.
template <class T>
bool quantizeAdjacentPositions(const std::byte* __restrict base, std::size_t stride,
                               std::size_t at_x, std::size_t n, const double (&offset)[3],
                               const double (&inverse)[3], Int3* __restrict dst, double (&lo)[3],
                               double (&hi)[3]) {
  static_assert(std::is_same_v<T, float> || std::is_same_v<T, double>);
  const __m128d offset_xy = _mm_setr_pd(offset[0], offset[1]);
  const __m128d inverse_xy = _mm_setr_pd(inverse[0], inverse[1]);
  const __m128d offset_z = _mm_set_sd(offset[2]), inverse_z = _mm_set_sd(inverse[2]);
  const __m128d int_min = _mm_set1_pd(-2147483648.0), int_max = _mm_set1_pd(2147483647.0);
  __m128d lo_xy = _mm_setr_pd(lo[0], lo[1]), hi_xy = _mm_setr_pd(hi[0], hi[1]);
  __m128d lo_z = _mm_set_sd(lo[2]), hi_z = _mm_set_sd(hi[2]);
  __m128d not_finite = _mm_setzero_pd();
  for (std::size_t i = 0; i < n; ++i) {
    const std::byte* record = base + i * stride + at_x;
    __m128d xy, z;  // z alone in the low half; the high half 0, never stored
    if constexpr (std::is_same_v<T, float>) {
      std::int64_t xy_bits;
      std::int32_t z_bits;
      std::memcpy(&xy_bits, record, 8);
      std::memcpy(&z_bits, record + 8, 4);
      xy = _mm_cvtps_pd(_mm_castsi128_ps(_mm_cvtsi64_si128(xy_bits)));
      z = _mm_cvtss_sd(_mm_setzero_pd(), _mm_castsi128_ps(_mm_cvtsi32_si128(z_bits)));
    } else {
      double z_value;
      std::memcpy(&z_value, record + 16, 8);
      xy = _mm_loadu_pd(reinterpret_cast<const double*>(record));
      z = _mm_set_sd(z_value);
    }
    not_finite = _mm_add_pd(not_finite, _mm_add_pd(_mm_sub_pd(xy, xy), _mm_sub_pd(z, z)));
    lo_xy = _mm_min_pd(xy, lo_xy), hi_xy = _mm_max_pd(xy, hi_xy);
    lo_z = _mm_min_sd(z, lo_z), hi_z = _mm_max_sd(z, hi_z);
    __m128d q_xy = _mm_mul_pd(_mm_sub_pd(xy, offset_xy), inverse_xy);
    __m128d q_z = _mm_mul_sd(_mm_sub_sd(z, offset_z), inverse_z);
    q_xy = _mm_min_pd(_mm_max_pd(q_xy, int_min), int_max);
    q_z = _mm_min_sd(_mm_max_sd(q_z, int_min), int_max);
    const __m128i xy_int = _mm_cvtpd_epi32(q_xy);
    const std::int64_t xy_out = _mm_cvtsi128_si64(xy_int);
    const std::int32_t z_out = _mm_cvtsd_si32(q_z);
    std::memcpy(reinterpret_cast<std::byte*>(dst + i), &xy_out, 8);
    std::memcpy(reinterpret_cast<std::byte*>(dst + i) + 8, &z_out, 4);
  }
  lo[0] = _mm_cvtsd_f64(lo_xy), lo[1] = _mm_cvtsd_f64(_mm_unpackhi_pd(lo_xy, lo_xy));
  hi[0] = _mm_cvtsd_f64(hi_xy), hi[1] = _mm_cvtsd_f64(_mm_unpackhi_pd(hi_xy, hi_xy));
  lo[2] = _mm_cvtsd_f64(lo_z), hi[2] = _mm_cvtsd_f64(hi_z);
  return _mm_movemask_pd(_mm_cmpord_pd(not_finite, not_finite)) == 3;
}
#endif

// x, y and z of fixed-size records in one pass: load, track bounds, quantize. `base` holds the
// `n` records of `range` (the mapped file, or a copy read into a buffer).
void decodeFixedPositions(const DecodeContext& context, const std::byte* base,
                          const RecordRange& range, std::size_t n, bool swap, PointCloud& cloud,
                          std::uint64_t first_index, RangeStats& stats) {
  const PointLayout& layout = context.layout;
  const PropertyPlan* plans[3];
  for (int axis = 0; axis < 3; ++axis) {
    plans[axis] = &layout.properties[std::size_t(layout.position_index[axis])];
  }
  const std::size_t stride = layout.record_size;
  const Quantization& q = cloud.quantization;
  const double offset[3] = {q.offset[0], q.offset[1], q.offset[2]};
  const double inverse[3] = {1.0 / q.scale[0], 1.0 / q.scale[1], 1.0 / q.scale[2]};
  const std::size_t at[3] = {plans[0]->byte_offset, plans[1]->byte_offset, plans[2]->byte_offset};
  Int3* dst = cloud.positions.data() + first_index;
  double lo[3] = {stats.raw_bounds.min[0], stats.raw_bounds.min[1], stats.raw_bounds.min[2]};
  double hi[3] = {stats.raw_bounds.max[0], stats.raw_bounds.max[1], stats.raw_bounds.max[2]};
  bool finite = true;
  ScalarType type = plans[0]->type;
  if (plans[1]->type == type && plans[2]->type == type) {
    // The common case: one type for all three; the loop is specialised for it.
    dispatch(type, swap, [&]<class T, bool kSwap>() {
#if defined(__SSE2__)
      if constexpr (!kSwap && (std::is_same_v<T, float> || std::is_same_v<T, double>)) {
        if (at[1] == at[0] + sizeof(T) && at[2] == at[1] + sizeof(T)) {
          finite =
              quantizeAdjacentPositions<T>(base, stride, at[0], n, offset, inverse, dst, lo, hi);
          return;
        }
      }
#endif
      finite =
          quantizeSameTypePositions<T, kSwap>(base, stride, at, n, offset, inverse, dst, lo, hi);
    });
  } else {
    // Mixed types (rare): through double, one value at a time.
    for (std::size_t i = 0; i < n; ++i) {
      const std::byte* record = base + i * stride;
      std::int32_t out[3];
      for (int axis = 0; axis < 3; ++axis) {
        double v = loadAsDouble(plans[axis]->type, swap, record + at[axis]);
        finite &= std::abs(v) <= 1.7976931348623157e308;
        lo[axis] = std::min(lo[axis], v);
        hi[axis] = std::max(hi[axis], v);
        out[axis] = quantizeClamped(v, offset[axis], inverse[axis]);
      }
      dst[i] = Int3{out[0], out[1], out[2]};
    }
  }
  if (!finite) {
    for (std::size_t i = 0; i < n; ++i) {
      for (int axis = 0; axis < 3; ++axis) {
        const std::byte* value = base + i * stride + at[axis];
        if (!std::isfinite(loadAsDouble(plans[axis]->type, swap, value))) {
          failNonFinite(context, *plans[axis], range.begin + std::size_t(value - base),
                        range.first_record + i);
        }
      }
    }
  }
  for (int axis = 0; axis < 3; ++axis) {
    stats.raw_bounds.min[axis] = lo[axis];
    stats.raw_bounds.max[axis] = hi[axis];
  }
}

// Properties that sit side by side in every record, in the model's order and type, are copied
// as one value a record instead of one pass a property: the normals of nearly every file (three
// native floats, 12 bytes a Float3) and 8-bit colours (r g b, and alpha after them, 4 bytes a
// Rgba8). -1 where the layout has no such run.
struct AdjacentRuns {
  std::ptrdiff_t normals = -1;  // byte offset of nx, followed by ny and nz
  std::ptrdiff_t colors = -1;   // byte offset of red, followed by green, blue (and alpha)
  bool alpha = false;           // colors: the byte after blue is alpha
};

AdjacentRuns findAdjacentRuns(const PointLayout& layout, bool swap) {
  const PropertyPlan* by_target[int(Target::Skip) + 1] = {};
  for (const auto& plan : layout.properties) by_target[int(plan.target)] = &plan;
  auto adjacent = [&](Target first, int count, ScalarType type) -> std::ptrdiff_t {
    const PropertyPlan* head = by_target[int(first)];
    if (head == nullptr) return -1;
    for (int k = 0; k < count; ++k) {
      const PropertyPlan* plan = by_target[int(first) + k];
      if (plan == nullptr || plan->type != type ||
          plan->byte_offset != head->byte_offset + std::size_t(k) * scalarSize(type)) {
        return -1;
      }
    }
    return std::ptrdiff_t(head->byte_offset);
  };
  AdjacentRuns runs;
  if (!swap) runs.normals = adjacent(Target::NormalX, 3, ScalarType::Float32);
  const PropertyPlan* alpha = by_target[int(Target::Alpha)];
  runs.alpha = alpha != nullptr && adjacent(Target::Red, 4, ScalarType::UInt8) >= 0;
  // Without alpha in the run, an alpha elsewhere (or of another type) keeps its own loop.
  if (runs.alpha || alpha == nullptr) runs.colors = adjacent(Target::Red, 3, ScalarType::UInt8);
  return runs;
}

// The elements after the point element are not kept either, but a file too short to hold them
// is truncated, and its points are suspect too.
void checkFollowingElements(const DecodeContext& context, int point_element, bool swap,
                            std::size_t pos) {
  const auto& elements = context.header.elements;
  for (std::size_t e = std::size_t(point_element) + 1; e < elements.size(); ++e) {
    pos = skipElement(context, elements[e], swap, pos);
  }
}

}  // namespace

std::vector<RecordRange> planBinaryRanges(const DecodeContext& context, std::size_t target_bytes) {
  const int point_element = context.header.pointElement();
  const PlyElement& element = context.header.elements[std::size_t(point_element)];
  const bool swap = needsSwap(context.header.format);
  std::size_t pos = locatePointElement(context, point_element, swap);
  std::size_t left = context.bytes.size() - std::min(pos, context.bytes.size());
  const std::size_t min_size = context.layout.min_record_size;
  if (element.count > left / min_size) {
    failTruncated(context, element, left / min_size, pos + (left / min_size + 1) * min_size);
  }
  std::vector<RecordRange> ranges;
  if (context.layout.fixed_size) {
    std::uint64_t per_range = std::max<std::uint64_t>(1, target_bytes / context.layout.record_size);
    for (std::uint64_t first = 0; first < element.count; first += per_range) {
      ranges.push_back({first, std::min(per_range, element.count - first),
                        pos + first * context.layout.record_size, 0});
    }
    pos += element.count * context.layout.record_size;
  } else {
    // Records with lists must be walked to be found. Ranges are cut by size and also every
    // count/4096 records, because their first records are the sample the quantization is
    // chosen from.
    const std::uint64_t max_records = std::max<std::uint64_t>(1, element.count / 4096);
    RecordRange current{0, 0, pos, 0};
    std::size_t range_start = pos;
    for (std::uint64_t r = 0; r < element.count; ++r) {
      if (pos - range_start >= target_bytes || current.count >= max_records) {
        ranges.push_back(current);
        current = {r, 0, pos, 0};
        range_start = pos;
      }
      pos += walkRecord(context, element, swap, pos, r);
      ++current.count;
    }
    if (current.count > 0) ranges.push_back(current);
  }
  checkFollowingElements(context, point_element, swap, pos);
  return ranges;
}

RangeStats decodeBinaryRange(const DecodeContext& context, const RecordRange& range,
                             std::uint64_t count, PointCloud& cloud, std::uint64_t first_index) {
  const PointLayout& layout = context.layout;
  const bool swap = needsSwap(context.header.format);
  const std::byte* base = context.bytes.data() + range.begin;
  RangeStats stats;
  if (!layout.fixed_size) {
    // Records with lists: one at a time, property by property.
    const PlyElement& element = context.header.elements[std::size_t(context.header.pointElement())];
    std::size_t pos = range.begin;
    for (std::uint64_t r = 0; r < count; ++r) {
      std::size_t record_size = walkRecord(context, element, swap, pos, range.first_record + r);
      const std::byte* p = context.bytes.data() + pos;
      double xyz[3] = {};
      for (const auto& plan : layout.properties) {
        if (plan.is_list) {
          double items = loadAsDouble(plan.list_count_type, swap, p);
          p += scalarSize(plan.list_count_type) + std::size_t(items) * scalarSize(plan.type);
          continue;
        }
        double value = loadAsDouble(plan.type, swap, p);
        p += scalarSize(plan.type);
        int axis = int(plan.target) - int(Target::X);
        if (axis >= 0 && axis < 3) {
          xyz[axis] = value;
        } else {
          storeAttribute(cloud, plan, first_index + r, value);
        }
      }
      Int3& q = cloud.positions[first_index + r];
      std::int32_t* out[3] = {&q.x, &q.y, &q.z};
      for (int axis = 0; axis < 3; ++axis) {
        *out[axis] = quantizeClamped(xyz[axis], cloud.quantization.offset[axis],
                                     1.0 / cloud.quantization.scale[axis]);
      }
      for (int axis = 0; axis < 3; ++axis) {
        if (!std::isfinite(xyz[axis])) {
          const auto& plan = layout.properties[std::size_t(layout.position_index[axis])];
          failNonFinite(context, plan, pos, range.first_record + r);
        }
      }
      stats.raw_bounds.extend(xyz[0], xyz[1], xyz[2]);
      pos += record_size;
    }
    stats.end = pos;
    return stats;
  }

  return decodeFixedRecords(context, base, range, count, cloud, first_index);
}

RangeStats decodeFixedRecords(const DecodeContext& context, const std::byte* records,
                              const RecordRange& range, std::uint64_t count, PointCloud& cloud,
                              std::uint64_t first_index) {
  const PointLayout& layout = context.layout;
  const bool swap = needsSwap(context.header.format);
  const std::byte* base = records;
  RangeStats stats;
  const std::size_t stride = layout.record_size;
  const std::size_t n = count;
  stats.end = range.begin + n * stride;
  decodeFixedPositions(context, base, range, n, swap, cloud, first_index, stats);
  const AdjacentRuns runs = findAdjacentRuns(layout, swap);
  // A colour run writes every channel, alpha included; the rest of the defaults are the normals'.
  if (runs.colors < 0 || (layout.has_normals && runs.normals < 0)) {
    fillMissingChannels(layout, cloud, first_index, n);
  }
  if (runs.normals >= 0) {
    const std::byte* src = base + runs.normals;
    Float3* dst = cloud.normals.data() + first_index;
    for (std::size_t i = 0; i < n; ++i) std::memcpy(&dst[i], src + i * stride, sizeof(Float3));
  }
  if (runs.colors >= 0) {
    const std::byte* src = base + runs.colors;
    Rgba8* dst = cloud.colors.data() + first_index;
    if (runs.alpha) {
      for (std::size_t i = 0; i < n; ++i) std::memcpy(&dst[i], src + i * stride, sizeof(Rgba8));
    } else {
      // One 4-byte load and store a record, alpha set over the byte after blue (byte loads and
      // stores were 4 of each, and most of this loop's time). That byte is read past the record
      // when blue ends it: the last record then takes the bytewise loop, as the buffer or the
      // mapping may end right after it.
      const std::size_t by_word =
          std::size_t(runs.colors) + 4 <= stride ? n : std::max<std::size_t>(n, 1) - 1;
      for (std::size_t i = 0; i < by_word; ++i) {
        std::uint32_t bytes;
        std::memcpy(&bytes, src + i * stride, 4);
        const std::uint32_t rgba =
            std::endian::native == std::endian::little ? bytes | 0xff000000u : bytes | 0x000000ffu;
        std::memcpy(&dst[i], &rgba, 4);
      }
      for (std::size_t i = by_word; i < n; ++i) {
        const std::byte* c = src + i * stride;
        dst[i] = {std::uint8_t(c[0]), std::uint8_t(c[1]), std::uint8_t(c[2]), 255};
      }
    }
  }
  for (const auto& plan : layout.properties) {
    const std::byte* src = base + plan.byte_offset;
    switch (plan.target) {
      case Target::X:
      case Target::Y:
      case Target::Z:
        break;  // decoded together, below
      case Target::Red:
      case Target::Green:
      case Target::Blue:
      case Target::Alpha: {
        if (runs.colors >= 0 && (plan.target != Target::Alpha || runs.alpha)) break;  // above
        std::uint8_t* dst = &cloud.colors[first_index].r + (int(plan.target) - int(Target::Red));
        dispatch(plan.type, swap, [=]<class T, bool kSwap>() {
          // Captured by value: stores through uint8_t* may alias anything, and would otherwise
          // force n, stride and src to be reloaded every iteration.
          for (std::size_t i = 0; i < n; ++i) {
            dst[i * 4] = colorFromValue(load<T, kSwap>(src + i * stride));
          }
        });
        break;
      }
      case Target::NormalX:
      case Target::NormalY:
      case Target::NormalZ: {
        if (runs.normals >= 0) break;  // above
        float* dst = &cloud.normals[first_index].x + (int(plan.target) - int(Target::NormalX));
        dispatch(plan.type, swap, [=]<class T, bool kSwap>() {
          for (std::size_t i = 0; i < n; ++i) {
            if constexpr (std::is_same_v<T, float>) {
              dst[i * 3] = load<T, kSwap>(src + i * stride);
            } else {
              dst[i * 3] = narrowToFloat(double(load<T, kSwap>(src + i * stride)));
            }
          }
        });
        break;
      }
      case Target::Scalar: {
        std::byte* dst = cloud.scalars[std::size_t(plan.scalar_index)].data.data();
        dispatch(plan.type, swap, [=]<class T, bool kSwap>() {
          T* out = reinterpret_cast<T*>(dst) + first_index;
          for (std::size_t i = 0; i < n; ++i) out[i] = load<T, kSwap>(src + i * stride);
        });
        break;
      }
      case Target::Intensity: {
        float* dst = cloud.intensity.data() + first_index;
        dispatch(plan.type, swap, [=]<class T, bool kSwap>() {
          for (std::size_t i = 0; i < n; ++i) {
            dst[i] = narrowToFloat(double(load<T, kSwap>(src + i * stride)));
          }
        });
        break;
      }
      case Target::Classification: {
        std::uint8_t* dst = cloud.classification.data() + first_index;
        dispatch(plan.type, swap, [=]<class T, bool kSwap>() {
          for (std::size_t i = 0; i < n; ++i) {
            // storeAttribute's rule, typed: rounded, clamped to 0..255
            const double value = double(load<T, kSwap>(src + i * stride));
            dst[i] = value > 0.0 ? std::uint8_t(std::min(value + 0.5, 255.0)) : 0;
          }
        });
        break;
      }
      case Target::Skip:
        break;
    }
  }
  return stats;
}

}  // namespace parallax::ply
