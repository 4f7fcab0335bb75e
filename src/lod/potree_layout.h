// The record layout of a Potree 2.0 octree.bin in the DEFAULT encoding, and the conversion of
// points between the column model and those records.
//
// A record is the point's attributes one after the other, in metadata.json order, little endian,
// unpadded. Parallax writes:
//   position        int32 x 3   world = value * scale + offset (metadata "scale", "offset")
//   rgb             uint16 x 3  8-bit colour * 257 (so 255 -> 65535), as LAS stores colour
//   intensity       uint16      when the source's intensity is an integer type; float otherwise
//   classification  uint8
//   NormalX/Y/Z     float       the names Potree's loader joins into one normal vector
//   other scalars   their own type, under their name; the LAS fields under the names Potree's
//                   viewer knows ("return number", "gps-time", "point source id", ...)
// The same layout is used for the conversion's spill files, so that each point is encoded once.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "core/point_cloud.h"
#include "core/quantization.h"

namespace parallax {

enum class PotreeAttributeSource {
  Position,
  Rgb,
  Intensity,
  Classification,
  NormalX,
  NormalY,
  NormalZ,
  Scalar
};

struct PotreeAttribute {
  std::string name;  // as metadata.json names it
  PotreeAttributeSource source = PotreeAttributeSource::Scalar;
  ScalarType type = ScalarType::UInt8;  // of one element
  int num_elements = 1;
  std::string scalar_name;  // Scalar: the PointCloud column's name
  std::size_t offset = 0;   // byte offset inside the record
  std::size_t size() const { return scalarSize(type) * std::size_t(num_elements); }
};

// Per-attribute, per-element minimum and maximum (metadata "min"/"max"); positions in world units.
struct AttributeStats {
  std::vector<std::array<double, 3>> min, max;
  void merge(const AttributeStats& other);
};

class PotreeLayout {
 public:
  // The layout for the attributes of `cloud` (positions always; the rest when present).
  static PotreeLayout fromCloud(const PointCloud& cloud);
  // Adds the attributes of `other` this layout lacks (several inputs with different attributes;
  // points of an input without an attribute get zeros there).
  void merge(const PotreeLayout& other);

  const std::vector<PotreeAttribute>& attributes() const { return attributes_; }
  std::size_t recordSize() const { return record_size_; }

  AttributeStats emptyStats() const;

  // Writes the records of points [first, first + count) of `cloud` to `out` (count *
  // recordSize() bytes), with positions in `quantization` (the cloud's own is converted when it
  // differs; the caller made sure every point fits), and widens `stats`.
  void encode(const PointCloud& cloud, std::uint64_t first, std::uint64_t count,
              const Quantization& quantization, std::byte* out, AttributeStats& stats) const;

  // The points of `count` records (positions keep `quantization`; colours back to 8 bits).
  PointCloud decode(const std::byte* records, std::uint64_t count,
                    const Quantization& quantization) const;

  // metadata.json's "attributes" array.
  nlohmann::json toJson(const AttributeStats& stats) const;

  // The layout as the distributed build's plan keeps it (every field of every attribute, so that
  // fromPlanJson gives back the same layout); fromPlanJson throws std::runtime_error naming
  // `origin` for anything else.
  nlohmann::json toPlanJson() const;
  static PotreeLayout fromPlanJson(const nlohmann::json& json, const std::string& origin);

 private:
  void add(PotreeAttribute attribute);

  std::vector<PotreeAttribute> attributes_;
  std::size_t record_size_ = 0;
};

// "int8" ... "uint32", "float", "double": the type names of Potree's metadata.
const char* potreeTypeName(ScalarType type);

// The name Potree uses for a scalar column ("return_number" -> "return number", "gps_time" ->
// "gps-time"); other names unchanged. potreeToColumnName inverts it.
std::string columnToPotreeName(const std::string& column);
std::string potreeToColumnName(const std::string& potree);

}  // namespace parallax
