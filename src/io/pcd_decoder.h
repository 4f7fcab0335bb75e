// Internal to the PCD reader (pcd_reader.h): how a PCD file's fields map onto the column model,
// where each value of a record lies in the bytes (binary records, the decompressed structure of
// arrays of binary_compressed, or ascii values parsed into a table of doubles), and the two
// passes over a range of records: positions first (which points are valid, their exact bounds),
// then every column.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "core/bounds.h"
#include "core/point_cloud.h"
#include "io/pcd_header.h"

namespace parallax::pcd {

enum class Target {
  Skip,
  X,
  Y,
  Z,
  Rgb,
  Rgba,
  Red,
  Green,
  Blue,
  Nx,
  Ny,
  Nz,
  Intensity,
  Classification,
  Scalar
};

// One value of a record: field `field`, its `index`-th value (fields of COUNT > 1 give several).
struct Component {
  std::size_t field = 0;
  std::uint32_t index = 0;
  char type = 'F';
  std::uint32_t size = 4;
  Target target = Target::Skip;
  std::size_t scalar = 0;  // index into cloud.scalars for Target::Scalar
  std::string name;        // the field's name, "name_i" for the i-th value of a COUNT > 1 field
};

struct Layout {
  std::vector<Component> components;
  std::size_t x = 0, y = 0, z = 0;  // components holding the position
  std::vector<std::pair<std::string, ScalarType>> scalars;
  bool colors = false, alpha = false, normals = false, intensity = false, classification = false;
  // Colour from three fields red green blue (PDAL writes LAS colour so), not a packed rgb.
  // `wide_colors`: some channel is wider than a byte; the values are kept as stored (16 bits,
  // PointCloud::stored_colors) and shown by las_reader.h's rule: as is when `colors_8bit` (every
  // value of the file below 256, which the caller finds with PositionScan::color_above_255),
  // else value / 257.
  bool channel_colors = false, wide_colors = false, colors_8bit = true;
  SourceTypes source;
};

// Maps the fields (names in any case): x y z -> positions; rgb (packed 0x00RRGGBB) or rgba
// (0xAARRGGBB), 4 bytes of type F or U -> colours, else three fields red green blue (PDAL's
// Red Green Blue, U1 or U2) -> colours; normal_x normal_y normal_z -> normals; intensity ->
// intensity; classification -> classification; a LAS field under PDAL's dimension name or ours
// without its underscores (GpsTime, ReturnNumber, NumberOfReturns, ScanAngleRank, UserData,
// PointSourceId, ClassFlags, ScanChannel, Infrared, ...) -> the scalar column of
// core/column_names.h (gps_time, return_number, ...) in the field's type, so that a PCD written
// by PDAL from a LAS file gives the LAS fields back; "_" (PCL's padding) skipped; every other
// value -> a scalar column under its own name in its type (I8 and U8 as doubles, exact below
// 2^53). Throws InputError naming `file` and the field for: no x,
// y or z, a position or colour field with COUNT > 1, a colour field not 4 bytes.
Layout mapFields(const PcdHeader& header, const std::string& file);

// Where the values of a component lie: value of record i at base + i * stride, stored as
// `type`/`size` (the file's, or 'F'/8 for ascii values parsed into doubles).
struct ComponentView {
  const std::byte* base = nullptr;
  std::size_t stride = 0;
  char type = 'F';
  std::uint32_t size = 8;
};
struct DataView {
  std::vector<ComponentView> components;
  std::uint64_t records = 0;
};

// Binary records starting at `data` (`records` of header.record_size bytes).
DataView binaryView(const PcdHeader& header, const Layout& layout, const std::byte* data,
                    std::uint64_t records);
// The decompressed structure of arrays of binary_compressed (`records` points).
DataView compressedView(const PcdHeader& header, const Layout& layout, const std::byte* data,
                        std::uint64_t records);

// Ascii values parsed into doubles, one row of layout.components.size() a record.
struct AsciiTable {
  std::vector<double> values;
  std::uint64_t records = 0;
  std::size_t end = 0;  // byte after the last line parsed
  std::uint64_t next_line = 0;
  DataView view(const Layout& layout) const;
};

// Parses up to `max_records` records of ascii data from text[begin, ...) (line `line`),
// skipping blank lines. Throws InputError naming `file`, the line and the field for a value
// that is not a number, an integer out of its type's range, a line with too few or too many
// values.
AsciiTable parseAscii(std::string_view text, std::size_t begin, std::uint64_t line,
                      std::uint64_t max_records, const Layout& layout, const std::string& file);

// Decompresses binary_compressed data (at header.data_offset of `bytes`) into `out`, sized
// POINTS * record size. Throws InputError naming `file` and the byte offset for sizes that do
// not fit the file or the header, and for LZF data that does not decompress to exactly that.
void decompress(std::span<const std::byte> bytes, const PcdHeader& header, const std::string& file,
                std::vector<std::byte>& out);

// Positions of records [begin, end): how many are valid (x, y and z finite: PCL marks points it
// has no measurement for with NaN), and the bounds of those.
struct PositionScan {
  std::uint64_t valid = 0;
  Bounds3 bounds;
  bool color_above_255 = false;  // Layout::wide_colors: some valid point's channel is over 255
};
PositionScan scanPositions(const DataView& view, const Layout& layout, std::uint64_t begin,
                           std::uint64_t end);

// Decodes the valid records of [begin, end) (`valid` of them, from scanPositions) into `cloud`
// (allocated for them by allocateCloud) from `first_index` on, positions quantized with
// cloud.quantization.
void decodeRecords(const DataView& view, const Layout& layout, std::uint64_t begin,
                   std::uint64_t end, std::uint64_t valid, PointCloud& cloud,
                   std::uint64_t first_index);

// Columns for `count` points of `layout`, untouched.
PointCloud allocateCloud(const Layout& layout, std::uint64_t count, const Quantization& q);

}  // namespace parallax::pcd
