// metadata.json of a Potree 2.0 directory, parsed and checked.
//
// Potree 2.0 (PotreeConverter 2, docs/file_format.md of potree/PotreeConverter): metadata.json
// describes the cloud (point count, cubic bounding box, quantization, root spacing), how
// hierarchy.bin is chunked, the encoding of octree.bin, and the attributes of one record in
// order. A record is the attributes' bytes back to back, little endian; position comes first as
// int32 x 3 with world = int * scale + offset.
//
// Every field the reader needs is checked here, so that later code can trust it: a missing or
// mistyped field, an unknown type, an attribute whose size is not numElements * elementSize, a
// non-positive scale, a bounding box that is not a box, BROTLI encoding (with a hint) are each an
// InputError naming metadata.json and the field.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "core/bounds.h"
#include "core/quantization.h"

namespace parallax {

// Potree's attribute types: PLY's eight plus 64-bit integers.
enum class PotreeType : std::uint8_t {
  Int8,
  UInt8,
  Int16,
  UInt16,
  Int32,
  UInt32,
  Int64,
  UInt64,
  Float,
  Double
};

// "int8" ... "uint64", "float", "double" (Potree's spelling).
std::string_view potreeTypeName(PotreeType type);
// Size of one element in bytes.
std::size_t potreeTypeSize(PotreeType type);

struct PotreeMetadataAttribute {
  std::string name;  // as in the file: "position", "rgb", "intensity", "gps-time", ...
  std::string description;
  PotreeType type = PotreeType::UInt8;
  int num_elements = 1;           // values per point (3 for position and rgb)
  std::size_t size = 0;           // bytes per point: num_elements * potreeTypeSize(type)
  std::size_t record_offset = 0;  // where the attribute starts inside a record
  std::vector<double> min, max;   // per element; empty when the file gives none
};

struct PotreeHierarchyLayout {
  std::uint64_t first_chunk_size = 0;  // bytes of the root's chunk at offset 0 of hierarchy.bin
  int step_size = 0;                   // levels per chunk (informative: proxies say where)
  int depth = 0;                       // deepest level, as declared (may be 0 for a deeper tree)
};

struct PotreeMetadata {
  std::string version;  // "2.0"
  std::string name, description, projection;
  std::uint64_t points = 0;
  Bounds3 cube;               // "boundingBox": the root node's box
  Quantization quantization;  // "scale", "offset"
  double spacing = 0.0;       // the root's spacing
  PotreeHierarchyLayout hierarchy;
  std::string encoding;                             // "DEFAULT" (the only one read)
  std::vector<PotreeMetadataAttribute> attributes;  // in record order, record_offset filled in
  std::size_t record_size = 0;                      // bytes per point in octree.bin
};

// Parses metadata.json text; `file` names it in errors. Throws InputError as described above.
PotreeMetadata parsePotreeMetadata(std::string_view json_text, const std::string& file);

}  // namespace parallax
