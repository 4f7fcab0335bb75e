#include "lod/potree_record_reader.h"

#include <bit>
#include <cassert>
#include <cmath>
#include <cstring>
#include <string_view>

#include "core/byte_order.h"
#include "core/color_depth.h"
#include "core/column_names.h"
#include "io/las_reader.h"

namespace parallax {
namespace {

static_assert(std::endian::native == std::endian::little,
              "octree.bin is little endian; the decoder copies values as they are");

double loadAsDouble(const std::byte* p, PotreeType type) {
  switch (type) {
    case PotreeType::Int8:
      return loadLE<std::int8_t>(p);
    case PotreeType::UInt8:
      return loadLE<std::uint8_t>(p);
    case PotreeType::Int16:
      return loadLE<std::int16_t>(p);
    case PotreeType::UInt16:
      return loadLE<std::uint16_t>(p);
    case PotreeType::Int32:
      return loadLE<std::int32_t>(p);
    case PotreeType::UInt32:
      return loadLE<std::uint32_t>(p);
    case PotreeType::Int64:
      return double(loadLE<std::int64_t>(p));
    case PotreeType::UInt64:
      return double(loadLE<std::uint64_t>(p));
    case PotreeType::Float:
      return loadLE<float>(p);
    case PotreeType::Double:
      return loadLE<double>(p);
  }
  return 0.0;
}

// The column type that holds a Potree type exactly (64-bit integers: as double).
ScalarType columnType(PotreeType type) {
  switch (type) {
    case PotreeType::Int8:
      return ScalarType::Int8;
    case PotreeType::UInt8:
      return ScalarType::UInt8;
    case PotreeType::Int16:
      return ScalarType::Int16;
    case PotreeType::UInt16:
      return ScalarType::UInt16;
    case PotreeType::Int32:
      return ScalarType::Int32;
    case PotreeType::UInt32:
      return ScalarType::UInt32;
    case PotreeType::Float:
      return ScalarType::Float32;
    case PotreeType::Int64:
    case PotreeType::UInt64:
    case PotreeType::Double:
      return ScalarType::Float64;
  }
  return ScalarType::Float64;
}

bool isFloat(PotreeType type) {
  return type == PotreeType::Float || type == PotreeType::Double;
}

// PotreeConverter's names of LAS fields -> the LAS reader's column names.
std::string columnName(const std::string& potree_name) {
  static constexpr std::pair<std::string_view, const char*> kLasNames[] = {
      {"return number", las_names::kReturnNumber},
      {"number of returns", las_names::kNumberOfReturns},
      {"scan direction flag", las_names::kScanDirectionFlag},
      {"edge of flight line", las_names::kEdgeOfFlightLine},
      {"classification flags", las_names::kClassificationFlags},
      {"scanner channel", las_names::kScannerChannel},
      {"scan angle rank", las_names::kScanAngleRank},
      {"scan angle", las_names::kScanAngle},
      {"user data", las_names::kUserData},
      {"point source id", las_names::kPointSourceId},
      {"gps-time", las_names::kGpsTime},
      {"gps time", las_names::kGpsTime},
  };
  for (const auto& [potree, las] : kLasNames) {
    if (potree_name == potree) return las;
  }
  return potree_name;
}

const PotreeMetadataAttribute* find(const PotreeMetadata& m, std::string_view name) {
  for (const auto& a : m.attributes) {
    if (a.name == name) return &a;
  }
  return nullptr;
}

}  // namespace

PotreeRecordReader::PotreeRecordReader(const PotreeMetadata& metadata)
    : record_size_(metadata.record_size), quantization_(metadata.quantization) {
  // Normals as three scalars, when all three are there and are floating point.
  const PotreeMetadataAttribute* axes[3] = {find(metadata, "NormalX"), find(metadata, "NormalY"),
                                            find(metadata, "NormalZ")};
  const bool split_normals = axes[0] && axes[1] && axes[2] && axes[0]->num_elements == 1 &&
                             axes[1]->num_elements == 1 && axes[2]->num_elements == 1 &&
                             isFloat(axes[0]->type) && axes[1]->type == axes[0]->type &&
                             axes[2]->type == axes[0]->type;
  if (split_normals) {
    normal_ = {true,
               {axes[0]->record_offset, axes[1]->record_offset, axes[2]->record_offset},
               axes[0]->type};
  }

  for (const auto& a : metadata.attributes) {
    const bool one = a.num_elements == 1;
    if (a.name == "position") {
      position_offset_ = a.record_offset;
      continue;
    }
    // "rgba" also names 3 elements in some writers' output (three-loader reads it so).
    if ((a.name == "rgb" || a.name == "rgba") && (a.num_elements == 3 || a.num_elements == 4)) {
      if (!color_.present && (a.type == PotreeType::UInt16 || a.type == PotreeType::UInt8)) {
        color_.present = true;
        color_.offset = a.record_offset;
        color_.sixteen_bit = a.type == PotreeType::UInt16;
        bool eight_bit_values = a.max.size() == std::size_t(a.num_elements);
        for (double v : a.max) eight_bit_values = eight_bit_values && v <= 255;
        color_.scale_down = color_.sixteen_bit && !eight_bit_values;
        color_.alpha = a.num_elements == 4;
        continue;
      }
    }
    if (a.name == "intensity" && one && !intensity_.present) {
      intensity_ = {true, a.record_offset, a.type};
      continue;
    }
    if (a.name == "classification" && one && a.type == PotreeType::UInt8 &&
        !classification_.present) {
      classification_ = {true, a.record_offset, a.type};
      continue;
    }
    if (split_normals && (&a == axes[0] || &a == axes[1] || &a == axes[2])) continue;
    if ((a.name == "normal" || a.name == "normals" || a.name == "NORMAL") && a.num_elements == 3 &&
        isFloat(a.type) && !normal_.present) {
      const std::size_t step = potreeTypeSize(a.type);
      normal_ = {
          true, {a.record_offset, a.record_offset + step, a.record_offset + 2 * step}, a.type};
      continue;
    }
    const std::string name = columnName(a.name);
    const std::size_t step = potreeTypeSize(a.type);
    for (int e = 0; e < a.num_elements; ++e) {
      ScalarField field;
      field.name = one ? name : name + "[" + std::to_string(e) + "]";
      field.offset = a.record_offset + std::size_t(e) * step;
      field.source = a.type;
      field.type = columnType(a.type);
      if (name == las_names::kScanAngleRank && a.type == PotreeType::UInt8) {
        field.type = ScalarType::Int8;  // the same byte, read as LAS's signed degrees
      }
      scalars_.push_back(std::move(field));
    }
  }
}

void PotreeRecordReader::describe(OctreeInfo& info) const {
  info.attributes = {column_names::kX, column_names::kY, column_names::kZ};
  info.has_colors = color_.present;
  info.has_normals = normal_.present;
  info.has_intensity = intensity_.present;
  info.has_classification = classification_.present;
  if (color_.present) {
    info.attributes.insert(info.attributes.end(),
                           {column_names::kRed, column_names::kGreen, column_names::kBlue});
    if (color_.alpha) info.attributes.push_back(column_names::kAlpha);
  }
  if (normal_.present)
    info.attributes.insert(info.attributes.end(),
                           {column_names::kNx, column_names::kNy, column_names::kNz});
  if (intensity_.present) info.attributes.push_back(column_names::kIntensity);
  if (classification_.present) info.attributes.push_back(column_names::kClassification);
  for (const auto& field : scalars_) info.attributes.push_back(field.name);
}

PointCloud PotreeRecordReader::decode(std::span<const std::byte> bytes, std::uint64_t count) const {
  assert(bytes.size() == count * record_size_ && "decode needs count whole records");
  const std::size_t n = std::size_t(count);
  const std::byte* records = bytes.data();
  const std::size_t stride = record_size_;

  PointCloud cloud;
  cloud.count = count;
  cloud.quantization = quantization_;
  cloud.source.position = ScalarType::Int32;
  cloud.positions = Column<Int3>(n);
  for (std::size_t i = 0; i < n; ++i) {
    std::memcpy(&cloud.positions[i], records + i * stride + position_offset_, sizeof(Int3));
  }

  if (color_.present) {
    cloud.colors = Column<Rgba8>(n);
    cloud.source.color = color_.scale_down ? ScalarType::UInt16 : ScalarType::UInt8;
    cloud.source.has_alpha = color_.alpha;
    const int channels = color_.alpha ? 4 : 3;
    // 16-bit rgb (Potree's "rgb", as LAS stores colour) is also kept as stored, so that a
    // conversion to LAS, LAZ or COPC writes the values the octree holds, whatever their range.
    const bool keep_stored = color_.sixteen_bit && !color_.alpha;
    if (keep_stored) cloud.stored_colors = Column<Rgb16>(n);
    for (std::size_t i = 0; i < n; ++i) {
      const std::byte* p = records + i * stride + color_.offset;
      std::uint8_t rgba[4] = {0, 0, 0, 255};
      if (keep_stored) {
        cloud.stored_colors[i] = {loadLE<std::uint16_t>(p), loadLE<std::uint16_t>(p + 2),
                                  loadLE<std::uint16_t>(p + 4)};
      }
      for (int c = 0; c < channels; ++c) {
        if (!color_.sixteen_bit) {
          rgba[c] = loadLE<std::uint8_t>(p + c);
          continue;
        }
        const unsigned v = loadLE<std::uint16_t>(p + 2 * c);
        // Rounded v / 257: 65535 -> 255 and c * 257 -> c. A value above 255 in a file whose
        // metadata promised 8 bits (a lying max) saturates instead of wrapping.
        rgba[c] =
            color_.scale_down ? colorTo8Bits(std::uint16_t(v)) : std::uint8_t(v > 255 ? 255 : v);
      }
      cloud.colors[i] = {rgba[0], rgba[1], rgba[2], rgba[3]};
    }
  }

  if (normal_.present) {
    cloud.normals = Column<Float3>(n);
    cloud.source.normal = columnType(normal_.type);
    for (std::size_t i = 0; i < n; ++i) {
      const std::byte* r = records + i * stride;
      float v[3];
      for (int c = 0; c < 3; ++c) {
        v[c] = normal_.type == PotreeType::Float
                   ? loadLE<float>(r + normal_.offsets[c])
                   : narrowToFloat(loadLE<double>(r + normal_.offsets[c]));
      }
      cloud.normals[i] = {v[0], v[1], v[2]};
    }
  }

  if (intensity_.present) {
    cloud.intensity = Column<float>(n);
    cloud.source.intensity = columnType(intensity_.type);
    for (std::size_t i = 0; i < n; ++i) {
      cloud.intensity[i] =
          narrowToFloat(loadAsDouble(records + i * stride + intensity_.offset, intensity_.type));
    }
  }

  if (classification_.present) {
    cloud.classification = Column<std::uint8_t>(n);
    for (std::size_t i = 0; i < n; ++i) {
      cloud.classification[i] = loadLE<std::uint8_t>(records + i * stride + classification_.offset);
    }
  }

  cloud.scalars.reserve(scalars_.size());
  for (const auto& field : scalars_) {
    ScalarColumn column;
    column.name = field.name;
    column.type = field.type;
    const std::size_t size = scalarSize(field.type);
    column.data = ByteBuffer(n * size);
    std::byte* out = column.data.data();
    const bool converted = field.source == PotreeType::Int64 || field.source == PotreeType::UInt64;
    if (!converted) {
      // The column has the source's width (also uint8 read as int8): the bytes as they are.
      for (std::size_t i = 0; i < n; ++i) {
        std::memcpy(out + i * size, records + i * stride + field.offset, size);
      }
    } else {
      for (std::size_t i = 0; i < n; ++i) {
        const double v = loadAsDouble(records + i * stride + field.offset, field.source);
        std::memcpy(out + i * size, &v, sizeof v);
      }
    }
    cloud.scalars.push_back(std::move(column));
  }

  cloud.computeBounds();
  return cloud;
}

}  // namespace parallax
