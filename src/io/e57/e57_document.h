// What the XML section of an E57 file says (ASTM E2807 sections 9-10): the scans (the children
// of /data3D) with the layout of their points, their poses and limits, and the images (the
// children of /images2D), which Parallax lists but does not decode.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/bounds.h"

namespace parallax {

// One field of a scan's point record (a child of points/prototype). Each is one bytestream of
// the compressed vector, bit-packed (the only codec E2807 defines): a record takes `bits` bits,
// least significant first, continuing across bytes and packets.
struct E57Field {
  enum class Kind { Integer, ScaledInteger, Float, String };
  std::string name;
  Kind kind = Kind::Float;
  // Integer and ScaledInteger: the raw integer range; a record holds raw - minimum.
  std::int64_t minimum = 0;
  std::int64_t maximum = 0;
  // ScaledInteger: value = raw * scale + offset.
  double scale = 1.0;
  double offset = 0.0;
  // Float: single (32 bits) or double (64 bits) precision, and the declared value range.
  bool single_precision = false;
  double float_minimum = 0.0;
  double float_maximum = 0.0;
  // Bits a record takes: 32 or 64 for Float, the width of maximum - minimum for integers (0 when
  // they are equal: the value is then not stored at all).
  unsigned bits = 0;

  // The range of the values the field can hold (declared limits for Float).
  double lowest() const;
  double highest() const;
};

// A rigid transform from a scan's own frame to the file's: rotation (a unit quaternion w, x, y,
// z) then translation. The identity when the scan has no pose.
struct E57Pose {
  std::array<double, 4> rotation{1.0, 0.0, 0.0, 0.0};  // w x y z
  std::array<double, 3> translation{0.0, 0.0, 0.0};
  // The 3x3 rotation matrix, row major, of the (normalised) quaternion.
  std::array<double, 9> matrix() const;
};

struct E57Scan {
  std::string name;  // may be empty
  std::string guid;
  std::uint64_t record_count = 0;
  std::uint64_t section_offset = 0;  // physical offset of the compressed vector section
  std::vector<E57Field> fields;      // in bytestream order
  E57Pose pose;
  // cartesianBounds, in the scan's own frame, when given.
  std::optional<Bounds3> cartesian_bounds;
  // sphericalBounds' rangeMaximum, when given.
  std::optional<double> range_maximum;
  // intensityLimits and colorLimits (red, green, blue: minimum, maximum), when given.
  std::optional<std::array<double, 2>> intensity_limits;
  std::optional<std::array<double, 6>> color_limits;

  const E57Field* field(std::string_view field_name) const;
};

struct E57Image {
  std::string name;
  std::string representation;  // "pinhole", "spherical", "cylindrical", "visualReference"
  std::string format;          // "JPEG" or "PNG"
  std::int64_t width = 0;      // 0 when not given
  std::int64_t height = 0;
  std::uint64_t byte_length = 0;  // of the encoded image
};

struct E57Document {
  std::string guid;
  std::string coordinate_metadata;  // the file's CRS as written (WKT, "EPSG:..."), may be empty
  std::vector<E57Scan> scans;
  std::vector<E57Image> images;
};

// Parses the XML section. `file` and `xml_offset` (the section's physical offset) name the place
// in messages. Throws InputError for XML that is not well formed (with its line), and for a
// missing or malformed element the reader needs (its path, e.g. "/data3D/1/points/prototype",
// what was expected and found).
E57Document parseE57Document(std::string_view xml, const std::string& file,
                             std::uint64_t xml_offset);

}  // namespace parallax
