// Internal to the PLY reader: how each property of the point element maps onto the model's
// columns, and how a record's values are stored there. Shared by the binary and ascii decoders.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "core/point_cloud.h"
#include "io/ply_header.h"

namespace parallax::ply {

enum class Target : std::uint8_t {
  X,
  Y,
  Z,
  Red,
  Green,
  Blue,
  Alpha,
  NormalX,
  NormalY,
  NormalZ,
  Intensity,
  Classification,
  Scalar,  // an extra named column
  Skip,    // a list property: read past, not kept
};

struct PropertyPlan {
  Target target = Target::Skip;
  ScalarType type = ScalarType::Float32;
  bool is_list = false;
  ScalarType list_count_type = ScalarType::UInt8;
  std::size_t byte_offset = 0;  // within a fixed-size binary record
  int scalar_index = -1;        // into PointCloud::scalars, for Target::Scalar
  std::string name;
};

// The plan for reading one point element: which column each property feeds.
struct PointLayout {
  std::string element_name;
  std::vector<PropertyPlan> properties;  // in file order
  bool fixed_size = true;                // no list properties
  std::size_t record_size = 0;           // bytes, when fixed_size
  std::size_t min_record_size = 0;       // bytes, lists counted empty
  int position_index[3] = {-1, -1, -1};  // into properties
  bool has_color = false, has_alpha = false, has_normals = false;
  bool has_intensity = false, has_classification = false;
  SourceTypes source;
  std::vector<std::pair<std::string, ScalarType>> scalars;  // extra columns, in order
};

// Maps the element's properties by name (case-insensitive; see ply_reader.h for the names).
// Throws InputError naming the file and element when x, y or z is missing or is a list.
PointLayout planPointLayout(const PlyElement& element, const std::string& file);

// A layout that reads every property of `element` and keeps none: to check the records of the
// elements before the point element in an ascii body.
PointLayout skippingLayout(const PlyElement& element);

// Who gives the colour channels and normal axes a file lacks (a PLY without alpha: most) their
// default (0, alpha 255): allocatePointCloud, a fill of the whole column on one thread before the
// decode, or the decoder, range by range as it writes the channels it has (fillMissingChannels;
// the fixed-size binary decoder does), which saves a pass over a column about to be written.
enum class ChannelDefaults : std::uint8_t { FilledAtAllocation, FilledByDecoder };

// A cloud with every column the layout needs allocated (uninitialised) for `count` points; the
// channels the file lacks hold their default unless `defaults` leaves them to the decoder.
PointCloud allocatePointCloud(const PointLayout& layout, std::uint64_t count,
                              const Quantization& quantization,
                              ChannelDefaults defaults = ChannelDefaults::FilledAtAllocation);

// Writes the default of every colour channel and normal axis the layout lacks, for points
// [first, first + n) (their other channels untouched).
void fillMissingChannels(const PointLayout& layout, PointCloud& cloud, std::uint64_t first,
                         std::size_t n);

// Colour conversions to 8 bits. 16-bit values are scaled by 255/65535 with rounding (so 257 * k
// gives k); floating-point values are taken as 0..1 and rounded; out-of-range values clamp.
inline std::uint8_t colorFrom16(double v) {
  if (!(v > 0.0)) return 0;
  if (v >= 65535.0) return 255;
  return std::uint8_t((std::uint32_t(v) * 255u + 32767u) / 65535u);
}
inline std::uint8_t colorFromUnit(double v) {
  if (!(v > 0.0)) return 0;
  if (v >= 1.0) return 255;
  return std::uint8_t(v * 255.0 + 0.5);
}
inline std::uint8_t colorFrom8(double v) {
  if (!(v > 0.0)) return 0;
  if (v >= 255.0) return 255;
  return std::uint8_t(v + 0.5);
}
inline std::uint8_t toColor(ScalarType source, double v) {
  switch (source) {
    case ScalarType::Float32:
    case ScalarType::Float64:
      return colorFromUnit(v);
    case ScalarType::Int16:
    case ScalarType::UInt16:
      return colorFrom16(v);
    default:
      return colorFrom8(v);
  }
}

// Stores one non-position value of point `index` (ascii path and slow binary path; the fast
// binary path has typed loops). Positions are handled by the callers, which also quantize.
// Inline: it runs once per value in the ascii parser.
inline void storeAttribute(PointCloud& cloud, const PropertyPlan& plan, std::uint64_t index,
                           double value) {
  switch (plan.target) {
    case Target::Red:
      cloud.colors[index].r = toColor(plan.type, value);
      break;
    case Target::Green:
      cloud.colors[index].g = toColor(plan.type, value);
      break;
    case Target::Blue:
      cloud.colors[index].b = toColor(plan.type, value);
      break;
    case Target::Alpha:
      cloud.colors[index].a = toColor(plan.type, value);
      break;
    case Target::NormalX:
      cloud.normals[index].x = narrowToFloat(value);
      break;
    case Target::NormalY:
      cloud.normals[index].y = narrowToFloat(value);
      break;
    case Target::NormalZ:
      cloud.normals[index].z = narrowToFloat(value);
      break;
    case Target::Intensity:
      cloud.intensity[index] = narrowToFloat(value);
      break;
    case Target::Classification:
      cloud.classification[index] = value > 0.0 ? std::uint8_t(std::min(value + 0.5, 255.0)) : 0;
      break;
    case Target::Scalar:
      cloud.scalars[std::size_t(plan.scalar_index)].setFromDouble(index, value);
      break;
    default:
      break;
  }
}

}  // namespace parallax::ply
