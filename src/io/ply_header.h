// The PLY header: format, elements and their properties, as written in the file.
// Reference: Greg Turk, "The PLY Polygon File Format" (1994), and the variants real tools write
// (CloudCompare, Meshlab, Agisoft, RealityCapture, COLMAP, PDAL, Open3D).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "core/scalar_type.h"

namespace parallax {

enum class PlyFormat { Ascii, BinaryLittleEndian, BinaryBigEndian };

// "ascii", "binary_little_endian", "binary_big_endian"
std::string_view plyFormatName(PlyFormat format);

struct PlyProperty {
  std::string name;
  ScalarType type = ScalarType::Float32;  // the value type (of the items, for a list)
  bool is_list = false;
  ScalarType list_count_type = ScalarType::UInt8;  // only for lists
  std::uint64_t header_line = 0;                   // 1-based, for messages
};

struct PlyElement {
  std::string name;
  std::uint64_t count = 0;
  std::vector<PlyProperty> properties;
  std::uint64_t header_line = 0;

  bool hasLists() const;
  // Bytes of one record in a binary body; only meaningful without lists.
  std::size_t fixedRecordSize() const;
  // Smallest possible bytes of one record in a binary body (lists counted as empty).
  std::size_t minimumRecordSize() const;
  int findProperty(std::string_view property_name) const;  // -1 when absent
};

// The comment with which Parallax's PLY writer declares the grid its double positions lie on
// (the cloud's quantization: "parallax quantization SX SY SZ OX OY OZ", shortest digits), so that
// the reader takes the grid back (after checking that every point is on it) and a LAS file's
// 0.01 m grid survives LAS -> PLY -> LAS exactly.
inline constexpr std::string_view kPlyQuantizationComment = "parallax quantization";

struct PlyHeader {
  PlyFormat format = PlyFormat::BinaryLittleEndian;
  std::string version = "1.0";
  std::vector<PlyElement> elements;
  std::vector<std::string> comments;
  std::vector<std::string> obj_info;
  std::size_t body_offset = 0;  // first byte after the LF ending the end_header line
  std::uint64_t body_line = 0;  // 1-based line number of the body's first line (ascii)

  // Index of the element holding the points: "vertex" (or "vertices", "point", "points"),
  // else -1.
  int pointElement() const;
};

// Largest header accepted: real headers are under 4 KiB; a file with no end_header in this many
// bytes is not a PLY file we can trust.
constexpr std::size_t kMaxPlyHeaderBytes = 1 << 20;

// Parses the header at the start of `bytes`. Throws InputError naming `file_name` and the header
// line for: no "ply" magic, an unknown format or version, an unknown type, a property outside an
// element, a malformed count, a missing end_header, a header over kMaxPlyHeaderBytes, other words
// on the "ply" or "end_header" line, lines ending in CR alone. Accepts what exporters write: CRLF
// line ends, spaces and tabs before, between and after the words of every line ("ply " and
// "end_header\t\r\n" included), blank lines, `comment` and `obj_info` lines. The body starts
// right after the LF that ends the end_header line.
PlyHeader parsePlyHeader(std::span<const std::byte> bytes, const std::string& file_name);

// Writes a header (LF line ends) whose body follows directly.
std::string formatPlyHeader(const PlyHeader& header);

}  // namespace parallax
