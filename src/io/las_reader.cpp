#include "io/las_reader.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cstring>
#include <mutex>

#include "core/error.h"
#include "io/mapped_file.h"

namespace parallax {
namespace {

template <class T>
T load(const std::byte* p) {
  T value;
  std::memcpy(&value, p, sizeof value);
  return value;
}

// How one scalar column is filled from the record.
struct FieldDecoder {
  enum class Kind { Bits, Copy, Int64ToDouble, UInt64ToDouble, Scaled };
  Kind kind = Kind::Copy;
  std::size_t offset = 0;   // in the record
  std::size_t size = 0;     // Copy: bytes of one value
  int shift = 0, mask = 0;  // Bits
  int data_type = 0;        // Scaled: the extra bytes base type 1-10
  double scale = 1.0, add = 0.0;
};

struct DecodePlan {
  std::size_t record_length = 0;
  bool extended = false;  // formats 6-10
  std::optional<std::size_t> color_offset;
  bool colors_8bit = true;
  std::vector<FieldDecoder> fields;  // one per scalar column, in order
  std::vector<std::pair<std::string, ScalarType>> columns;
};

void addBits(DecodePlan& plan, const char* name, std::size_t offset, int shift, int mask) {
  plan.fields.push_back(
      {.kind = FieldDecoder::Kind::Bits, .offset = offset, .shift = shift, .mask = mask});
  plan.columns.emplace_back(name, ScalarType::UInt8);
}
void addCopy(DecodePlan& plan, std::string name, ScalarType type, std::size_t offset) {
  plan.fields.push_back(
      {.kind = FieldDecoder::Kind::Copy, .offset = offset, .size = scalarSize(type)});
  plan.columns.emplace_back(std::move(name), type);
}

DecodePlan makePlan(const LasHeader& header) {
  using namespace las_names;
  DecodePlan plan;
  const int format = header.point_format;
  plan.record_length = header.record_length;
  plan.extended = lasFormatIsExtended(format);
  std::size_t gps = plan.extended ? 22 : 20;
  std::size_t after_gps = lasFormatHasGpsTime(format) ? gps + 8 : gps;
  if (lasFormatHasColor(format)) plan.color_offset = after_gps;
  if (plan.extended) {
    addBits(plan, kReturnNumber, 14, 0, 15);
    addBits(plan, kNumberOfReturns, 14, 4, 15);
    addBits(plan, kClassificationFlags, 15, 0, 15);
    addBits(plan, kScannerChannel, 15, 4, 3);
    addBits(plan, kScanDirectionFlag, 15, 6, 1);
    addBits(plan, kEdgeOfFlightLine, 15, 7, 1);
    addCopy(plan, kUserData, ScalarType::UInt8, 17);
    addCopy(plan, kScanAngle, ScalarType::Int16, 18);
    addCopy(plan, kPointSourceId, ScalarType::UInt16, 20);
  } else {
    addBits(plan, kReturnNumber, 14, 0, 7);
    addBits(plan, kNumberOfReturns, 14, 3, 7);
    addBits(plan, kScanDirectionFlag, 14, 6, 1);
    addBits(plan, kEdgeOfFlightLine, 14, 7, 1);
    addBits(plan, kClassificationFlags, 15, 5, 7);
    addCopy(plan, kScanAngleRank, ScalarType::Int8, 16);
    addCopy(plan, kUserData, ScalarType::UInt8, 17);
    addCopy(plan, kPointSourceId, ScalarType::UInt16, 18);
  }
  if (lasFormatHasGpsTime(format)) addCopy(plan, kGpsTime, ScalarType::Float64, gps);
  std::size_t end = after_gps + (lasFormatHasColor(format) ? 6 : 0);
  if (lasFormatHasNir(format)) {
    addCopy(plan, kNir, ScalarType::UInt16, end);
    end += 2;
  }
  if (lasFormatHasWavePacket(format)) {
    // LAS 1.4 R15 Table 13: index, offset, size, location, x(t), y(t), z(t): 29 bytes.
    addCopy(plan, "wave_packet_descriptor_index", ScalarType::UInt8, end);
    plan.fields.push_back({.kind = FieldDecoder::Kind::UInt64ToDouble, .offset = end + 1});
    plan.columns.emplace_back("wave_packet_offset", ScalarType::Float64);
    addCopy(plan, "wave_packet_size", ScalarType::UInt32, end + 9);
    addCopy(plan, "return_point_waveform_location", ScalarType::Float32, end + 13);
    addCopy(plan, "waveform_dx", ScalarType::Float32, end + 17);
    addCopy(plan, "waveform_dy", ScalarType::Float32, end + 21);
    addCopy(plan, "waveform_dz", ScalarType::Float32, end + 25);
  }
  for (const LasExtraBytes& extra : header.extra_bytes) {
    int base = extra.data_type <= 10 ? extra.data_type : (extra.data_type - 1) % 10 + 1;
    if (extra.scaled) {
      plan.fields.push_back({.kind = FieldDecoder::Kind::Scaled,
                             .offset = extra.record_offset,
                             .data_type = base,
                             .scale = extra.scale,
                             .add = extra.offset});
      plan.columns.emplace_back(extra.name, ScalarType::Float64);
    } else if (extra.is_64bit_int) {
      plan.fields.push_back({.kind = base == 7 ? FieldDecoder::Kind::UInt64ToDouble
                                               : FieldDecoder::Kind::Int64ToDouble,
                             .offset = extra.record_offset});
      plan.columns.emplace_back(extra.name, ScalarType::Float64);
    } else {
      addCopy(plan, extra.name, extra.type, extra.record_offset);
    }
  }
  return plan;
}

// The 8-bit rule (see las_reader.h): a strided sample settles most files at once (one value of
// 256 or more decides); otherwise every colour is checked, in parallel, stopping at the first.
bool colorsAre8Bit(const std::byte* records, std::uint64_t count, std::size_t record_length,
                   std::size_t color_offset, bool parallel) {
  auto big = [&](std::uint64_t i) {
    const std::byte* p = records + i * record_length + color_offset;
    return (load<std::uint16_t>(p) | load<std::uint16_t>(p + 2) | load<std::uint16_t>(p + 4)) > 255;
  };
  std::uint64_t stride = std::max<std::uint64_t>(1, count / 4096);
  for (std::uint64_t i = 0; i < count; i += stride) {
    if (big(i)) return false;
  }
  std::atomic<bool> found{false};
  auto scan = [&](const tbb::blocked_range<std::uint64_t>& range) {
    if (found.load(std::memory_order_relaxed)) return;
    for (std::uint64_t i = range.begin(); i != range.end(); ++i) {
      if (big(i)) {
        found = true;
        return;
      }
    }
  };
  tbb::blocked_range<std::uint64_t> all(0, count, 1 << 16);
  if (parallel) {
    tbb::parallel_for(all, scan);
  } else {
    scan(all);
  }
  return !found;
}

template <class F>
void withExtraType(int data_type, F f) {
  switch (data_type) {
    case 1:
      f(std::uint8_t{});
      break;
    case 2:
      f(std::int8_t{});
      break;
    case 3:
      f(std::uint16_t{});
      break;
    case 4:
      f(std::int16_t{});
      break;
    case 5:
      f(std::uint32_t{});
      break;
    case 6:
      f(std::int32_t{});
      break;
    case 7:
      f(std::uint64_t{});
      break;
    case 8:
      f(std::int64_t{});
      break;
    case 9:
      f(float{});
      break;
    default:
      f(double{});
      break;
  }
}

// Integer bounds of the positions, gathered while decoding (saves a pass over them).
struct IntBox {
  Int3 lo{INT32_MAX, INT32_MAX, INT32_MAX};
  Int3 hi{INT32_MIN, INT32_MIN, INT32_MIN};

  void merge(const IntBox& b) {
    lo = {std::min(lo.x, b.lo.x), std::min(lo.y, b.lo.y), std::min(lo.z, b.lo.z)};
    hi = {std::max(hi.x, b.hi.x), std::max(hi.y, b.hi.y), std::max(hi.z, b.hi.z)};
  }
  Bounds3 world(const Quantization& q) const {
    Bounds3 bounds;
    if (lo.x > hi.x) return bounds;
    bounds.extend(q.toWorld(0, lo.x), q.toWorld(1, lo.y), q.toWorld(2, lo.z));
    bounds.extend(q.toWorld(0, hi.x), q.toWorld(1, hi.y), q.toWorld(2, hi.z));
    return bounds;
  }
};

template <std::size_t kSize>
void copyField(const std::byte* src, std::size_t stride, std::size_t n, std::byte* dst) {
  for (std::size_t i = 0; i < n; ++i) std::memcpy(dst + i * kSize, src + i * stride, kSize);
}

// Decodes records [0, n) at `records` into `out` from index `at`. Column by column over blocks
// that stay in cache: each loop is a plain strided gather the compiler keeps tight.
void decodeRange(const std::byte* records, std::size_t n, const DecodePlan& plan, PointCloud& out,
                 std::size_t at, IntBox& box) {
  // Small enough that a block of records (up to 67 bytes each) stays in L1 while every column
  // gathers from it.
  constexpr std::size_t kBlock = 512;
  const std::size_t stride = plan.record_length;
  for (std::size_t b = 0; b < n; b += kBlock) {
    const std::size_t m = std::min(kBlock, n - b);
    const std::byte* r = records + b * stride;
    const std::size_t o = at + b;
    copyField<12>(r, stride, m, reinterpret_cast<std::byte*>(out.positions.data() + o));
    {
      const Int3* p = out.positions.data() + o;
      Int3 lo = box.lo, hi = box.hi;
      for (std::size_t i = 0; i < m; ++i) {
        lo = {std::min(lo.x, p[i].x), std::min(lo.y, p[i].y), std::min(lo.z, p[i].z)};
        hi = {std::max(hi.x, p[i].x), std::max(hi.y, p[i].y), std::max(hi.z, p[i].z)};
      }
      box.lo = lo, box.hi = hi;
    }
    float* intensity = out.intensity.data() + o;
    for (std::size_t i = 0; i < m; ++i)
      intensity[i] = float(load<std::uint16_t>(r + i * stride + 12));
    std::uint8_t* cls = out.classification.data() + o;
    if (plan.extended) {
      for (std::size_t i = 0; i < m; ++i) cls[i] = std::uint8_t(r[i * stride + 16]);
    } else {
      for (std::size_t i = 0; i < m; ++i) cls[i] = std::uint8_t(r[i * stride + 15]) & 31;
    }
    if (plan.color_offset) {
      const std::byte* c = r + *plan.color_offset;
      Rgba8* rgba = out.colors.data() + o;
      if (plan.colors_8bit) {
        for (std::size_t i = 0; i < m; ++i) {
          const std::byte* p = c + i * stride;
          rgba[i] = {std::uint8_t(load<std::uint16_t>(p)), std::uint8_t(load<std::uint16_t>(p + 2)),
                     std::uint8_t(load<std::uint16_t>(p + 4)), 255};
        }
      } else {
        auto to8 = [](std::uint16_t v) { return std::uint8_t((unsigned(v) + 128) / 257); };
        for (std::size_t i = 0; i < m; ++i) {
          const std::byte* p = c + i * stride;
          rgba[i] = {to8(load<std::uint16_t>(p)), to8(load<std::uint16_t>(p + 2)),
                     to8(load<std::uint16_t>(p + 4)), 255};
        }
      }
    }
    for (std::size_t f = 0; f < plan.fields.size(); ++f) {
      const FieldDecoder& field = plan.fields[f];
      ScalarColumn& column = out.scalars[f];
      const std::byte* src = r + field.offset;
      switch (field.kind) {
        case FieldDecoder::Kind::Bits: {
          // Locals, so that the stores through `dst` (a uint8_t*, which may alias anything) do
          // not force a reload of the shift and mask each point.
          const unsigned shift = unsigned(field.shift), mask = unsigned(field.mask);
          std::uint8_t* dst = column.as<std::uint8_t>() + o;
          for (std::size_t i = 0; i < m; ++i) {
            dst[i] = std::uint8_t((unsigned(src[i * stride]) >> shift) & mask);
          }
          break;
        }
        case FieldDecoder::Kind::Copy: {
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
        case FieldDecoder::Kind::Int64ToDouble: {
          double* dst = column.as<double>() + o;
          for (std::size_t i = 0; i < m; ++i) dst[i] = double(load<std::int64_t>(src + i * stride));
          break;
        }
        case FieldDecoder::Kind::UInt64ToDouble: {
          double* dst = column.as<double>() + o;
          for (std::size_t i = 0; i < m; ++i)
            dst[i] = double(load<std::uint64_t>(src + i * stride));
          break;
        }
        case FieldDecoder::Kind::Scaled: {
          double* dst = column.as<double>() + o;
          const double scale = field.scale, add = field.add;
          withExtraType(field.data_type, [&](auto zero) {
            using T = decltype(zero);
            for (std::size_t i = 0; i < m; ++i) {
              dst[i] = double(load<T>(src + i * stride)) * scale + add;
            }
          });
          break;
        }
      }
    }
  }
}

// A cloud with every column of the plan allocated (untouched) for `count` points.
PointCloud allocateCloud(const LasHeader& header, const DecodePlan& plan, std::size_t count) {
  PointCloud cloud;
  cloud.count = count;
  cloud.quantization = header.quantization;
  cloud.positions = Column<Int3>(count);
  cloud.intensity = Column<float>(count);
  cloud.classification = Column<std::uint8_t>(count);
  if (plan.color_offset) cloud.colors = Column<Rgba8>(count);
  for (const auto& [name, type] : plan.columns) {
    cloud.scalars.push_back({name, type, ByteBuffer(count * scalarSize(type))});
  }
  cloud.source.position = ScalarType::Float64;
  cloud.source.intensity = ScalarType::UInt16;
  cloud.source.classification = ScalarType::UInt8;
  cloud.source.color = plan.colors_8bit ? ScalarType::UInt8 : ScalarType::UInt16;
  return cloud;
}

DecodePlan planFor(const LasHeader& header, std::span<const std::byte> bytes, bool parallel) {
  DecodePlan plan = makePlan(header);
  if (plan.color_offset) {
    plan.colors_8bit = colorsAre8Bit(bytes.data() + header.point_data_offset, header.point_count,
                                     header.record_length, *plan.color_offset, parallel);
  }
  return plan;
}

PointCloud readAll(std::span<const std::byte> bytes, const std::string& name,
                   const LasReadOptions& options) {
  LasHeader header = parseLasHeader(bytes, name);
  DecodePlan plan = planFor(header, bytes, options.parallel);
  const std::size_t count = header.point_count;
  PointCloud cloud = allocateCloud(header, plan, count);
  const std::byte* records = bytes.data() + header.point_data_offset;
  IntBox box;
  std::mutex box_mutex;
  auto body = [&](const tbb::blocked_range<std::size_t>& range) {
    IntBox local;
    decodeRange(records + range.begin() * plan.record_length, range.size(), plan, cloud,
                range.begin(), local);
    if (options.progress) options.progress->advance(range.size());
    std::lock_guard lock(box_mutex);
    box.merge(local);
  };
  tbb::blocked_range<std::size_t> all(0, count, 1 << 16);
  if (options.parallel) {
    tbb::parallel_for(all, body);
  } else {
    body(all);
  }
  cloud.bounds = box.world(cloud.quantization);
  return cloud;
}

}  // namespace

PointCloud readLas(const std::filesystem::path& path, const LasReadOptions& options) {
  MappedFile file(path);
  return readAll(file.bytes(), path.string(), options);
}

PointCloud readLasFromMemory(std::span<const std::byte> bytes, const std::string& name,
                             const LasReadOptions& options) {
  return readAll(bytes, name, options);
}

struct LasChunkReader::State {
  MappedFile file;
  LasHeader header;
  DecodePlan plan;
  std::uint64_t next = 0;
};

LasChunkReader::LasChunkReader(const std::filesystem::path& path) {
  MappedFile file(path);
  LasHeader header = parseLasHeader(file.bytes(), path.string());
  DecodePlan plan = planFor(header, file.bytes(), true);
  state_ = std::make_unique<State>(State{std::move(file), std::move(header), std::move(plan), 0});
}
LasChunkReader::~LasChunkReader() = default;
LasChunkReader::LasChunkReader(LasChunkReader&&) noexcept = default;

const LasHeader& LasChunkReader::header() const {
  return state_->header;
}
std::uint64_t LasChunkReader::pointCount() const {
  return state_->header.point_count;
}
const Quantization& LasChunkReader::quantization() const {
  return state_->header.quantization;
}

bool LasChunkReader::next(PointCloud& chunk, std::size_t max_points) {
  assert(max_points > 0 && "LasChunkReader::next needs a positive chunk size");
  State& s = *state_;
  std::size_t n = std::size_t(std::min<std::uint64_t>(max_points, s.header.point_count - s.next));
  chunk = allocateCloud(s.header, s.plan, n);
  if (n == 0) return false;
  const std::byte* records =
      s.file.bytes().data() + s.header.point_data_offset + s.next * s.plan.record_length;
  s.file.adviseSequential(std::size_t(records - s.file.bytes().data()), n * s.plan.record_length);
  IntBox box;
  std::mutex box_mutex;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1 << 16),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      IntBox local;
                      decodeRange(records + range.begin() * s.plan.record_length, range.size(),
                                  s.plan, chunk, range.begin(), local);
                      std::lock_guard lock(box_mutex);
                      box.merge(local);
                    });
  s.next += n;
  chunk.bounds = box.world(chunk.quantization);
  return true;
}

}  // namespace parallax
