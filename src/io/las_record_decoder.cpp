#include "io/las_record_decoder.h"

#include <algorithm>
#include <cstring>

#include "core/byte_order.h"
#include "core/color_depth.h"
#include "core/column_names.h"
#include "io/las_reader.h"
#include "io/laz/chunk_codec.h"

namespace parallax {
namespace {

// Builds the plan, leaving out the columns `selection` does not want and noting, for each column
// kept, the LAZ field group (laz::fields) its bytes come from.
class PlanBuilder {
 public:
  PlanBuilder(LasDecodePlan& plan, const AttributeSelection& selection)
      : plan_(plan), selection_(selection) {}

  bool wants(const std::string& name, std::uint32_t group) {
    if (!selection_.wants(name)) return false;
    plan_.laz_fields |= group;
    return true;
  }
  void bits(const char* name, std::uint32_t group, std::size_t offset, int shift, int mask) {
    if (!wants(name, group)) return;
    plan_.fields.push_back(
        {.kind = LasFieldDecoder::Kind::Bits, .offset = offset, .shift = shift, .mask = mask});
    plan_.columns.emplace_back(name, ScalarType::UInt8);
  }
  void copy(const std::string& name, std::uint32_t group, ScalarType type, std::size_t offset) {
    if (!wants(name, group)) return;
    plan_.fields.push_back(
        {.kind = LasFieldDecoder::Kind::Copy, .offset = offset, .size = scalarSize(type)});
    plan_.columns.emplace_back(name, type);
  }
  void other(const std::string& name, std::uint32_t group, LasFieldDecoder field, ScalarType type) {
    if (!wants(name, group)) return;
    plan_.fields.push_back(field);
    plan_.columns.emplace_back(name, type);
  }

 private:
  LasDecodePlan& plan_;
  const AttributeSelection& selection_;
};

LasDecodePlan makePlanImpl(const LasHeader& header, const AttributeSelection& selection) {
  using namespace las_names;
  namespace f = laz::fields;
  LasDecodePlan plan;
  PlanBuilder add(plan, selection);
  const int format = header.point_format;
  plan.record_length = header.record_length;
  plan.extended = lasFormatIsExtended(format);
  plan.intensity = add.wants(column_names::kIntensity, f::kIntensity);
  plan.classification = add.wants(column_names::kClassification, f::kClassification);
  std::size_t gps = plan.extended ? 22 : 20;
  std::size_t after_gps = lasFormatHasGpsTime(format) ? gps + 8 : gps;
  if (lasFormatHasColor(format) && add.wants(column_names::kRed, f::kRgb))
    plan.color_offset = after_gps;
  if (plan.extended) {
    // Returns and the scanner channel share POINT14's first layer with the positions: always
    // decoded (group 0).
    add.bits(kReturnNumber, 0, 14, 0, 15);
    add.bits(kNumberOfReturns, 0, 14, 4, 15);
    add.bits(kClassificationFlags, f::kFlags, 15, 0, 15);
    add.bits(kScannerChannel, 0, 15, 4, 3);
    add.bits(kScanDirectionFlag, f::kFlags, 15, 6, 1);
    add.bits(kEdgeOfFlightLine, f::kFlags, 15, 7, 1);
    add.copy(kUserData, f::kUserData, ScalarType::UInt8, 17);
    add.copy(kScanAngle, f::kScanAngle, ScalarType::Int16, 18);
    add.copy(kPointSourceId, f::kPointSource, ScalarType::UInt16, 20);
  } else {
    add.bits(kReturnNumber, 0, 14, 0, 7);
    add.bits(kNumberOfReturns, 0, 14, 3, 7);
    add.bits(kScanDirectionFlag, f::kFlags, 14, 6, 1);
    add.bits(kEdgeOfFlightLine, f::kFlags, 14, 7, 1);
    add.bits(kClassificationFlags, f::kFlags, 15, 5, 7);
    add.copy(kScanAngleRank, f::kScanAngle, ScalarType::Int8, 16);
    add.copy(kUserData, f::kUserData, ScalarType::UInt8, 17);
    add.copy(kPointSourceId, f::kPointSource, ScalarType::UInt16, 18);
  }
  if (lasFormatHasGpsTime(format)) add.copy(kGpsTime, f::kGpsTime, ScalarType::Float64, gps);
  std::size_t end = after_gps + (lasFormatHasColor(format) ? 6 : 0);
  if (lasFormatHasNir(format)) {
    add.copy(kNir, f::kNir, ScalarType::UInt16, end);
    end += 2;
  }
  if (lasFormatHasWavePacket(format)) {
    // LAS 1.4 R15 Table 13: index, offset, size, location, x(t), y(t), z(t): 29 bytes.
    const std::uint32_t w = f::kWavePacket;
    add.copy(kWavePacketDescriptorIndex, w, ScalarType::UInt8, end);
    add.other(kWavePacketOffset, w,
              {.kind = LasFieldDecoder::Kind::UInt64ToDouble, .offset = end + 1},
              ScalarType::Float64);
    add.copy(kWavePacketSize, w, ScalarType::UInt32, end + 9);
    add.copy(kReturnPointWaveformLocation, w, ScalarType::Float32, end + 13);
    add.copy(kWaveformDx, w, ScalarType::Float32, end + 17);
    add.copy(kWaveformDy, w, ScalarType::Float32, end + 21);
    add.copy(kWaveformDz, w, ScalarType::Float32, end + 25);
  }
  const std::optional<std::array<std::size_t, 3>> normal_extras =
      lasNormalExtraBytes(header.extra_bytes);
  if (normal_extras && add.wants(column_names::kNx, f::kExtraBytes)) {
    LasDecodePlan::NormalFields normals;
    for (std::size_t axis = 0; axis < 3; ++axis) {
      const LasExtraBytes& extra = header.extra_bytes[(*normal_extras)[axis]];
      normals.offset[axis] = extra.record_offset;
      normals.is_double[axis] = extra.data_type == 10;
    }
    plan.normals = normals;
  }
  for (std::size_t index = 0; index < header.extra_bytes.size(); ++index) {
    const LasExtraBytes& extra = header.extra_bytes[index];
    if (normal_extras &&
        std::find(normal_extras->begin(), normal_extras->end(), index) != normal_extras->end()) {
      continue;  // the normals, above
    }
    int base = extra.data_type <= 10 ? extra.data_type : (extra.data_type - 1) % 10 + 1;
    const std::uint32_t e = f::kExtraBytes;
    if (extra.scaled) {
      add.other(extra.name, e,
                {.kind = LasFieldDecoder::Kind::Scaled,
                 .offset = extra.record_offset,
                 .data_type = base,
                 .scale = extra.scale,
                 .add = extra.offset},
                ScalarType::Float64);
    } else if (extra.is_64bit_int) {
      add.other(extra.name, e,
                {.kind = base == 7 ? LasFieldDecoder::Kind::UInt64ToDouble
                                   : LasFieldDecoder::Kind::Int64ToDouble,
                 .offset = extra.record_offset},
                ScalarType::Float64);
    } else {
      add.copy(extra.name, e, extra.type, extra.record_offset);
    }
  }
  // Bytes after those no extra bytes VLR describes: one column a byte, so that they are written
  // back (las_header.h, lasUndescribedByteName).
  for (std::size_t at = lasDescribedRecordEnd(header); at < header.record_length; ++at) {
    add.copy(lasUndescribedByteName(at), f::kExtraBytes, ScalarType::UInt8, at);
  }
  // Everything asked: every layer too (the records handed out are then whole, undescribed extra
  // bytes included).
  if (selection.all()) plan.laz_fields = laz::fields::kAll;
  return plan;
}

template <std::size_t kSize>
void copyField(const std::byte* src, std::size_t stride, std::size_t n, std::byte* dst) {
  for (std::size_t i = 0; i < n; ++i) std::memcpy(dst + i * kSize, src + i * stride, kSize);
}

void storeColors(const std::byte* c, std::size_t stride, std::size_t m, bool colors_8bit,
                 Rgba8* rgba) {
  if (colors_8bit) {
    for (std::size_t i = 0; i < m; ++i) {
      const std::byte* p = c + i * stride;
      rgba[i] = {std::uint8_t(loadLE<std::uint16_t>(p)), std::uint8_t(loadLE<std::uint16_t>(p + 2)),
                 std::uint8_t(loadLE<std::uint16_t>(p + 4)), 255};
    }
  } else {
    for (std::size_t i = 0; i < m; ++i) {
      const std::byte* p = c + i * stride;
      rgba[i] = {colorTo8Bits(loadLE<std::uint16_t>(p)), colorTo8Bits(loadLE<std::uint16_t>(p + 2)),
                 colorTo8Bits(loadLE<std::uint16_t>(p + 4)), 255};
    }
  }
}

// One bit field of one byte a record: the shift a template argument, since a shift by a
// register (x86's shr %cl, several micro-ops) was most of a LAS read's decode (perf, format 2:
// the five bit-field columns 27 % of decodeLasRecords).
template <unsigned kShift>
void copyBits(const std::byte* src, std::size_t stride, std::size_t m, unsigned mask,
              std::uint8_t* __restrict dst) {
  for (std::size_t i = 0; i < m; ++i) {
    dst[i] = std::uint8_t((unsigned(src[i * stride]) >> kShift) & mask);
  }
}

void copyBitsShifted(const std::byte* src, std::size_t stride, std::size_t m, unsigned shift,
                     unsigned mask, std::uint8_t* dst) {
  switch (shift) {
    case 0:
      return copyBits<0>(src, stride, m, mask, dst);
    case 1:
      return copyBits<1>(src, stride, m, mask, dst);
    case 2:
      return copyBits<2>(src, stride, m, mask, dst);
    case 3:
      return copyBits<3>(src, stride, m, mask, dst);
    case 4:
      return copyBits<4>(src, stride, m, mask, dst);
    case 5:
      return copyBits<5>(src, stride, m, mask, dst);
    case 6:
      return copyBits<6>(src, stride, m, mask, dst);
    default:
      return copyBits<7>(src, stride, m, mask, dst);
  }
}

bool anyAbove255(const std::byte* c, std::size_t stride, std::size_t m) {
  unsigned all = 0;
  for (std::size_t i = 0; i < m; ++i) {
    const std::byte* p = c + i * stride;
    all |= unsigned(loadLE<std::uint16_t>(p)) | loadLE<std::uint16_t>(p + 2) |
           loadLE<std::uint16_t>(p + 4);
  }
  return all > 255;
}

}  // namespace

LasDecodePlan makeLasDecodePlan(const LasHeader& header, const AttributeSelection& selection) {
  return makePlanImpl(header, selection);
}

void LasDecodeStats::merge(const LasDecodeStats& b) {
  lo = {std::min(lo.x, b.lo.x), std::min(lo.y, b.lo.y), std::min(lo.z, b.lo.z)};
  hi = {std::max(hi.x, b.hi.x), std::max(hi.y, b.hi.y), std::max(hi.z, b.hi.z)};
  color_above_255 = color_above_255 || b.color_above_255;
}

Bounds3 LasDecodeStats::world(const Quantization& q) const {
  Bounds3 bounds;
  if (lo.x > hi.x) return bounds;
  bounds.extend(q.toWorld(0, lo.x), q.toWorld(1, lo.y), q.toWorld(2, lo.z));
  bounds.extend(q.toWorld(0, hi.x), q.toWorld(1, hi.y), q.toWorld(2, hi.z));
  return bounds;
}

// Decodes records [0, n) at `records` into `out` from index `at`. Column by column over blocks
// that stay in cache: each loop is a plain strided gather the compiler keeps tight.
void decodeLasRecords(const std::byte* records, std::size_t n, const LasDecodePlan& plan,
                      PointCloud& out, std::size_t at, LasDecodeStats& box) {
  // Small enough that a block of records (up to 67 bytes each) stays in L1 while every column
  // gathers from it.
  constexpr std::size_t kBlock = 512;
  const std::size_t stride = plan.record_length;
  for (std::size_t b = 0; b < n; b += kBlock) {
    const std::size_t m = std::min(kBlock, n - b);
    const std::byte* r = records + b * stride;
    const std::size_t o = at + b;
    {
      // Copied and bounded in one pass (a second pass read the positions back).
      Int3* __restrict p = out.positions.data() + o;
      Int3 lo = box.lo, hi = box.hi;
      for (std::size_t i = 0; i < m; ++i) {
        Int3 v;
        std::memcpy(&v, r + i * stride, sizeof v);
        p[i] = v;
        lo = {std::min(lo.x, v.x), std::min(lo.y, v.y), std::min(lo.z, v.z)};
        hi = {std::max(hi.x, v.x), std::max(hi.y, v.y), std::max(hi.z, v.z)};
      }
      box.lo = lo, box.hi = hi;
    }
    if (plan.intensity) {
      float* intensity = out.intensity.data() + o;
      for (std::size_t i = 0; i < m; ++i)
        intensity[i] = float(loadLE<std::uint16_t>(r + i * stride + 12));
    }
    if (plan.classification) {
      std::uint8_t* cls = out.classification.data() + o;
      if (plan.extended) {
        for (std::size_t i = 0; i < m; ++i) cls[i] = std::uint8_t(r[i * stride + 16]);
      } else {
        for (std::size_t i = 0; i < m; ++i) cls[i] = std::uint8_t(r[i * stride + 15]) & 31;
      }
    }
    if (plan.color_offset) {
      const std::byte* c = r + *plan.color_offset;
      if (!box.color_above_255) box.color_above_255 = anyAbove255(c, stride, m);
      storeColors(c, stride, m, plan.colors_8bit, out.colors.data() + o);
      copyField<6>(c, stride, m, reinterpret_cast<std::byte*>(out.stored_colors.data() + o));
    }
    if (plan.normals && plan.normals->adjacentFloats()) {
      // NormalX, NormalY, NormalZ side by side (as PDAL and CloudCompare write them, and
      // Parallax too): one 12-byte copy a record, not three passes of 4 bytes.
      const std::byte* src = r + plan.normals->offset[0];
      Float3* normals = out.normals.data() + o;
      for (std::size_t i = 0; i < m; ++i) std::memcpy(&normals[i], src + i * stride, 12);
    } else if (plan.normals) {
      float* normals = &out.normals[o].x;
      for (std::size_t axis = 0; axis < 3; ++axis) {
        const std::byte* src = r + plan.normals->offset[axis];
        if (plan.normals->is_double[axis]) {
          for (std::size_t i = 0; i < m; ++i)
            normals[3 * i + axis] = float(loadLE<double>(src + i * stride));
        } else {
          for (std::size_t i = 0; i < m; ++i)
            normals[3 * i + axis] = loadLE<float>(src + i * stride);
        }
      }
    }
    for (std::size_t f = 0; f < plan.fields.size(); ++f) {
      const LasFieldDecoder& field = plan.fields[f];
      ScalarColumn& column = out.scalars[f];
      const std::byte* src = r + field.offset;
      switch (field.kind) {
        case LasFieldDecoder::Kind::Bits:
          copyBitsShifted(src, stride, m, unsigned(field.shift), unsigned(field.mask),
                          column.as<std::uint8_t>() + o);
          break;
        case LasFieldDecoder::Kind::Copy: {
          std::byte* dst = column.data.data() + o * field.size;
          switch (field.size) {
            case 1:
              copyField<1>(src, stride, m, dst);
              break;
            case 2:
              copyField<2>(src, stride, m, dst);
              break;
            case 4:
              copyField<4>(src, stride, m, dst);
              break;
            default:
              copyField<8>(src, stride, m, dst);
              break;
          }
          break;
        }
        case LasFieldDecoder::Kind::Int64ToDouble: {
          double* dst = column.as<double>() + o;
          for (std::size_t i = 0; i < m; ++i)
            dst[i] = double(loadLE<std::int64_t>(src + i * stride));
          break;
        }
        case LasFieldDecoder::Kind::UInt64ToDouble: {
          double* dst = column.as<double>() + o;
          for (std::size_t i = 0; i < m; ++i)
            dst[i] = double(loadLE<std::uint64_t>(src + i * stride));
          break;
        }
        case LasFieldDecoder::Kind::Scaled: {
          double* dst = column.as<double>() + o;
          const double scale = field.scale, add = field.add;
          withExtraDataType(field.data_type, [&](auto zero) {
            using T = decltype(zero);
            for (std::size_t i = 0; i < m; ++i) {
              dst[i] = double(loadLE<T>(src + i * stride)) * scale + add;
            }
          });
          break;
        }
      }
    }
  }
}

void decodeLasColors(const std::byte* records, std::size_t n, const LasDecodePlan& plan,
                     PointCloud& out, std::size_t at) {
  if (!plan.color_offset) return;
  storeColors(records + *plan.color_offset, plan.record_length, n, plan.colors_8bit,
              out.colors.data() + at);
}

bool lasColorsAbove255(const std::byte* records, std::size_t n, const LasDecodePlan& plan) {
  return plan.color_offset && anyAbove255(records + *plan.color_offset, plan.record_length, n);
}

// A cloud with every column of the plan allocated (untouched) for `count` points.
PointCloud allocateLasCloud(const LasHeader& header, const LasDecodePlan& plan, std::size_t count) {
  PointCloud cloud;
  cloud.count = count;
  cloud.quantization = header.quantization;
  cloud.positions = Column<Int3>(count);
  if (plan.intensity) cloud.intensity = Column<float>(count);
  if (plan.classification) cloud.classification = Column<std::uint8_t>(count);
  if (plan.color_offset) {
    cloud.colors = Column<Rgba8>(count);
    cloud.stored_colors = Column<Rgb16>(count);
  }
  if (plan.normals) {
    cloud.normals = Column<Float3>(count);
    const bool all_double =
        std::all_of(plan.normals->is_double.begin(), plan.normals->is_double.end(),
                    [](bool is_double) { return is_double; });
    cloud.source.normal = all_double ? ScalarType::Float64 : ScalarType::Float32;
  }
  for (const auto& [name, type] : plan.columns) {
    cloud.scalars.push_back({name, type, ByteBuffer(count * scalarSize(type))});
  }
  cloud.source.position = ScalarType::Float64;
  cloud.source.intensity = ScalarType::UInt16;
  cloud.source.classification = ScalarType::UInt8;
  cloud.source.color = plan.colors_8bit ? ScalarType::UInt8 : ScalarType::UInt16;
  return cloud;
}

}  // namespace parallax
