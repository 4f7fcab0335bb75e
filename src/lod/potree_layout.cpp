#include "lod/potree_layout.h"

#include <algorithm>
#include <cassert>
#include <cstring>
#include <limits>
#include <nlohmann/json.hpp>
#include "core/byte_order.h"
#include "core/color_depth.h"
#include "core/column_names.h"

namespace parallax {
namespace {

// LAS fields as las_reader.h names them, and as Potree's viewer names them.
constexpr std::pair<const char*, const char*> kPotreeNames[] = {
    {column_names::kReturnNumber, "return number"},
    {column_names::kNumberOfReturns, "number of returns"},
    {column_names::kClassificationFlags, "classification flags"},
    {column_names::kScannerChannel, "scanner channel"},
    {column_names::kScanDirectionFlag, "scan direction flag"},
    {column_names::kEdgeOfFlightLine, "edge of flight line"},
    {column_names::kScanAngleRank, "scan angle rank"},
    {column_names::kScanAngle, "scan angle"},
    {column_names::kUserData, "user data"},
    {column_names::kPointSourceId, "point source id"},
    {column_names::kGpsTime, "gps-time"},
};

void widen(AttributeStats& stats, std::size_t attribute, int element, double value) {
  auto& lo = stats.min[attribute][std::size_t(element)];
  auto& hi = stats.max[attribute][std::size_t(element)];
  lo = std::min(lo, value);
  hi = std::max(hi, value);
}

}  // namespace

const char* potreeTypeName(ScalarType type) {
  switch (type) {
    case ScalarType::Int8:
      return "int8";
    case ScalarType::UInt8:
      return "uint8";
    case ScalarType::Int16:
      return "int16";
    case ScalarType::UInt16:
      return "uint16";
    case ScalarType::Int32:
      return "int32";
    case ScalarType::UInt32:
      return "uint32";
    case ScalarType::Float32:
      return "float";
    case ScalarType::Float64:
      return "double";
  }
  return "uint8";
}

std::string columnToPotreeName(const std::string& column) {
  for (const auto& [ours, theirs] : kPotreeNames) {
    if (column == ours) return theirs;
  }
  return column;
}

std::string potreeToColumnName(const std::string& potree) {
  for (const auto& [ours, theirs] : kPotreeNames) {
    if (potree == theirs) return ours;
  }
  return potree;
}

void AttributeStats::merge(const AttributeStats& other) {
  for (std::size_t a = 0; a < min.size() && a < other.min.size(); ++a) {
    for (std::size_t e = 0; e < 3; ++e) {
      min[a][e] = std::min(min[a][e], other.min[a][e]);
      max[a][e] = std::max(max[a][e], other.max[a][e]);
    }
  }
}

void PotreeLayout::add(PotreeAttribute attribute) {
  attribute.offset = record_size_;
  record_size_ += attribute.size();
  attributes_.push_back(std::move(attribute));
}

PotreeLayout PotreeLayout::fromCloud(const PointCloud& cloud) {
  using S = PotreeAttributeSource;
  PotreeLayout layout;
  layout.add(
      {.name = "position", .source = S::Position, .type = ScalarType::Int32, .num_elements = 3});
  if (cloud.hasColors()) {
    layout.add({.name = "rgb", .source = S::Rgb, .type = ScalarType::UInt16, .num_elements = 3});
  }
  if (cloud.hasIntensity()) {
    const bool integral =
        !isFloatingPoint(cloud.source.intensity) && scalarSize(cloud.source.intensity) <= 2;
    layout.add({.name = "intensity",
                .source = S::Intensity,
                .type = integral ? ScalarType::UInt16 : ScalarType::Float32});
  }
  if (cloud.hasClassification()) {
    layout.add({.name = "classification", .source = S::Classification, .type = ScalarType::UInt8});
  }
  if (cloud.hasNormals()) {
    layout.add({.name = "NormalX", .source = S::NormalX, .type = ScalarType::Float32});
    layout.add({.name = "NormalY", .source = S::NormalY, .type = ScalarType::Float32});
    layout.add({.name = "NormalZ", .source = S::NormalZ, .type = ScalarType::Float32});
  }
  for (const ScalarColumn& column : cloud.scalars) {
    layout.add({.name = columnToPotreeName(column.name),
                .source = S::Scalar,
                .type = column.type,
                .scalar_name = column.name});
  }
  return layout;
}

void PotreeLayout::merge(const PotreeLayout& other) {
  for (const PotreeAttribute& attribute : other.attributes_) {
    const bool known =
        std::any_of(attributes_.begin(), attributes_.end(),
                    [&](const PotreeAttribute& a) { return a.name == attribute.name; });
    if (!known) add(attribute);
  }
}

AttributeStats PotreeLayout::emptyStats() const {
  AttributeStats stats;
  constexpr double inf = std::numeric_limits<double>::infinity();
  stats.min.assign(attributes_.size(), {inf, inf, inf});
  stats.max.assign(attributes_.size(), {-inf, -inf, -inf});
  return stats;
}

void PotreeLayout::encode(const PointCloud& cloud, std::uint64_t first, std::uint64_t count,
                          const Quantization& quantization, std::byte* out,
                          AttributeStats& stats) const {
  using S = PotreeAttributeSource;
  const std::size_t stride = record_size_;
  const std::uint64_t n = count;
  for (std::size_t a = 0; a < attributes_.size(); ++a) {
    const PotreeAttribute& attribute = attributes_[a];
    std::byte* base = out + attribute.offset;
    switch (attribute.source) {
      case S::Position: {
        const bool same = cloud.quantization == quantization;
        std::array<std::int32_t, 3> lo{INT32_MAX, INT32_MAX, INT32_MAX};
        std::array<std::int32_t, 3> hi{INT32_MIN, INT32_MIN, INT32_MIN};
        for (std::uint64_t i = first; i < first + n; ++i) {
          Int3 p = cloud.positions[i];
          if (!same) {
            p = {quantization.toQuantized(0, cloud.worldX(i)),
                 quantization.toQuantized(1, cloud.worldY(i)),
                 quantization.toQuantized(2, cloud.worldZ(i))};
          }
          std::memcpy(base + (i - first) * stride, &p, sizeof p);
          lo = {std::min(lo[0], p.x), std::min(lo[1], p.y), std::min(lo[2], p.z)};
          hi = {std::max(hi[0], p.x), std::max(hi[1], p.y), std::max(hi[2], p.z)};
        }
        if (n > 0) {
          for (int e = 0; e < 3; ++e) {
            widen(stats, a, e, quantization.toWorld(e, lo[std::size_t(e)]));
            widen(stats, a, e, quantization.toWorld(e, hi[std::size_t(e)]));
          }
        }
        break;
      }
      case S::Rgb: {
        // Colour as the source stored it (a LAS file's 16-bit values, whatever their range),
        // else the 8-bit colour widened as LAS widens it (255 -> 65535).
        const bool stored = cloud.hasStoredColors();
        const bool has = cloud.hasColors();
        for (std::uint64_t i = first; i < first + n; ++i) {
          const Rgba8 c = has ? cloud.colors[i] : Rgba8{0, 0, 0, 255};
          const std::uint16_t rgb[3] = {stored ? cloud.stored_colors[i].r : colorTo16Bits(c.r),
                                        stored ? cloud.stored_colors[i].g : colorTo16Bits(c.g),
                                        stored ? cloud.stored_colors[i].b : colorTo16Bits(c.b)};
          std::memcpy(base + (i - first) * stride, rgb, sizeof rgb);
          for (int e = 0; e < 3; ++e) widen(stats, a, e, rgb[e]);
        }
        break;
      }
      case S::NormalX:
      case S::NormalY:
      case S::NormalZ: {
        const int e = int(attribute.source) - int(S::NormalX);
        const bool has = cloud.hasNormals();
        for (std::uint64_t i = first; i < first + n; ++i) {
          const float v = has ? (&cloud.normals[i].x)[e] : 0.0f;
          storeLE(base + (i - first) * stride, v);
          widen(stats, a, 0, v);
        }
        break;
      }
      case S::Intensity:
      case S::Classification:
      case S::Scalar: {
        const ScalarColumn* column =
            attribute.source == S::Scalar ? cloud.findScalar(attribute.scalar_name) : nullptr;
        const std::size_t size = scalarSize(attribute.type);
        // Scalars of the attribute's own type are copied byte for byte (exact for every value,
        // also NaN payloads); the others go through double.
        if (column && column->type == attribute.type) {
          for (std::uint64_t i = first; i < first + n; ++i) {
            std::memcpy(base + (i - first) * stride, column->data.data() + i * size, size);
            widen(stats, a, 0, column->valueAsDouble(i));
          }
          break;
        }
        ScalarColumn converted{.name = "", .type = attribute.type, .data = ByteBuffer(size)};
        for (std::uint64_t i = first; i < first + n; ++i) {
          double value = 0.0;
          if (attribute.source == S::Intensity && cloud.hasIntensity()) value = cloud.intensity[i];
          if (attribute.source == S::Classification && cloud.hasClassification())
            value = cloud.classification[i];
          if (column) value = column->valueAsDouble(i);
          converted.setFromDouble(0, value);
          std::memcpy(base + (i - first) * stride, converted.data.data(), size);
          widen(stats, a, 0, converted.valueAsDouble(0));
        }
        break;
      }
    }
  }
}

PointCloud PotreeLayout::decode(const std::byte* records, std::uint64_t count,
                                const Quantization& quantization) const {
  using S = PotreeAttributeSource;
  PointCloud cloud;
  cloud.count = count;
  cloud.quantization = quantization;
  cloud.source.position = ScalarType::Int32;
  const std::size_t stride = record_size_;
  for (const PotreeAttribute& attribute : attributes_) {
    const std::byte* base = records + attribute.offset;
    switch (attribute.source) {
      case S::Position:
        cloud.positions = Column<Int3>(count);
        for (std::uint64_t i = 0; i < count; ++i)
          cloud.positions[i] = loadLE<Int3>(base + i * stride);
        break;
      case S::Rgb:
        cloud.colors = Column<Rgba8>(count);
        cloud.source.color = ScalarType::UInt16;
        for (std::uint64_t i = 0; i < count; ++i) {
          const std::byte* at = base + i * stride;
          cloud.colors[i] = {colorTo8Bits(loadLE<std::uint16_t>(at)),
                             colorTo8Bits(loadLE<std::uint16_t>(at + 2)),
                             colorTo8Bits(loadLE<std::uint16_t>(at + 4)), 255};
        }
        break;
      case S::NormalX:
      case S::NormalY:
      case S::NormalZ: {
        if (cloud.normals.empty()) {
          cloud.normals = Column<Float3>(count);
          std::fill(cloud.normals.begin(), cloud.normals.end(), Float3{0, 0, 0});
        }
        const int e = int(attribute.source) - int(S::NormalX);
        for (std::uint64_t i = 0; i < count; ++i)
          (&cloud.normals[i].x)[e] = loadLE<float>(base + i * stride);
        break;
      }
      case S::Intensity:
      case S::Classification:
      case S::Scalar: {
        ScalarColumn column{.name = attribute.scalar_name, .type = attribute.type};
        const std::size_t size = scalarSize(attribute.type);
        column.data = ByteBuffer(count * size);
        for (std::uint64_t i = 0; i < count; ++i)
          std::memcpy(column.data.data() + i * size, base + i * stride, size);
        if (attribute.source == S::Intensity) {
          cloud.intensity = Column<float>(count);
          cloud.source.intensity = attribute.type;
          for (std::uint64_t i = 0; i < count; ++i)
            cloud.intensity[i] = float(column.valueAsDouble(i));
        } else if (attribute.source == S::Classification) {
          cloud.classification = Column<std::uint8_t>(count);
          for (std::uint64_t i = 0; i < count; ++i)
            cloud.classification[i] = column.as<std::uint8_t>()[i];
        } else {
          cloud.scalars.push_back(std::move(column));
        }
        break;
      }
    }
  }
  return cloud;
}

nlohmann::json PotreeLayout::toJson(const AttributeStats& stats) const {
  nlohmann::json list = nlohmann::json::array();
  for (std::size_t a = 0; a < attributes_.size(); ++a) {
    const PotreeAttribute& attribute = attributes_[a];
    nlohmann::json min = nlohmann::json::array(), max = nlohmann::json::array();
    for (int e = 0; e < attribute.num_elements; ++e) {
      // An attribute no point had (an empty cloud) reports 0..0 rather than infinities,
      // which JSON cannot hold.
      const double lo = stats.min[a][std::size_t(e)], hi = stats.max[a][std::size_t(e)];
      min.push_back(lo <= hi ? lo : 0.0);
      max.push_back(lo <= hi ? hi : 0.0);
    }
    list.push_back({{"name", attribute.name},
                    {"description", ""},
                    {"size", attribute.size()},
                    {"numElements", attribute.num_elements},
                    {"elementSize", scalarSize(attribute.type)},
                    {"type", potreeTypeName(attribute.type)},
                    {"min", min},
                    {"max", max}});
  }
  return list;
}

nlohmann::json PotreeLayout::toPlanJson() const {
  nlohmann::json list = nlohmann::json::array();
  for (const PotreeAttribute& a : attributes_) {
    list.push_back({{"name", a.name},
                    {"source", int(a.source)},
                    {"type", int(a.type)},
                    {"elements", a.num_elements},
                    {"scalar", a.scalar_name}});
  }
  return list;
}

PotreeLayout PotreeLayout::fromPlanJson(const nlohmann::json& json, const std::string& origin) {
  PotreeLayout layout;
  try {
    for (const nlohmann::json& a : json) {
      const int source = a.at("source").get<int>();
      const int type = a.at("type").get<int>();
      const int elements = a.at("elements").get<int>();
      if (source < 0 || source > int(PotreeAttributeSource::Scalar) || type < 0 ||
          type > int(ScalarType::Float64) || elements < 1 || elements > 3) {
        throw std::runtime_error("an attribute out of range");
      }
      layout.add({.name = a.at("name").get<std::string>(),
                  .source = PotreeAttributeSource(source),
                  .type = ScalarType(type),
                  .num_elements = elements,
                  .scalar_name = a.at("scalar").get<std::string>()});
    }
  } catch (const std::exception& e) {
    throw std::runtime_error(origin + ": not a record layout of a conversion plan: " + e.what());
  }
  return layout;
}

}  // namespace parallax
