// The header of a PCD file (the Point Cloud Library's format, versions 0.6 and 0.7), as PCL's
// public documentation describes it: lines of text, in this order,
//   VERSION 0.7                 (".7" and "0.6" too; a 0.6 header may lack VIEWPOINT)
//   FIELDS x y z rgb ...        names of the fields of a point record
//   SIZE 4 4 4 4                bytes of one value of each field: 1, 2, 4 or 8
//   TYPE F F F U                F float (4 or 8), I signed, U unsigned integer (1, 2, 4 or 8)
//   COUNT 1 1 1 1               values each field holds (optional: 1 each when absent)
//   WIDTH 640                   points a row (organised clouds) or all points
//   HEIGHT 480                  rows; 1 for an unorganised cloud
//   VIEWPOINT tx ty tz qw qx qy qz   the sensor's position and orientation (optional)
//   POINTS 307200               WIDTH * HEIGHT
//   DATA ascii | binary | binary_compressed
// Lines starting with '#' are comments. The data follows the DATA line:
//   ascii: one point a line, values separated by blanks, in field order;
//   binary: WIDTH * HEIGHT records of the fields' bytes in order, little endian, no padding;
//   binary_compressed: uint32 compressed size, uint32 uncompressed size, then that many bytes
//     of LZF (liblzf's format), which decompress to the fields one after the other (all points'
//     values of the first field, then of the second, ...: structure of arrays).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace parallax {

enum class PcdData { Ascii, Binary, BinaryCompressed };

// "ascii", "binary", "binary_compressed".
const char* pcdDataName(PcdData data);

struct PcdField {
  std::string name;
  char type = 'F';           // 'F', 'I' or 'U'
  std::uint32_t size = 4;    // bytes of one value: 1, 2, 4 or 8 (F: 4 or 8)
  std::uint32_t count = 1;   // values of the field in a point
  std::uint32_t offset = 0;  // byte offset of its first value in a binary record
};

struct PcdHeader {
  std::string version = "0.7";
  std::vector<PcdField> fields;
  std::uint64_t width = 0;
  std::uint64_t height = 1;
  // The sensor's pose: tx ty tz (position, in the points' frame) and the quaternion qw qx qy qz.
  std::array<double, 7> viewpoint{0, 0, 0, 1, 0, 0, 0};
  std::uint64_t points = 0;
  PcdData data = PcdData::Binary;
  std::size_t data_offset = 0;    // byte after the DATA line
  std::uint64_t data_line = 0;    // 1-based number of the first line after DATA
  std::uint32_t record_size = 0;  // bytes of one binary record (the fields' size * count)

  // Index of the field of that name (case-insensitive), or -1.
  int find(std::string_view name) const;
};

// Parses the header at the start of `bytes`; `file` names the file in messages. Throws
// InputError naming the file, the line and the keyword for: a missing required line (FIELDS,
// SIZE, TYPE, WIDTH, POINTS, DATA; HEIGHT defaults to 1, COUNT to 1 each), lines out of order,
// a SIZE/TYPE/COUNT list whose length differs from FIELDS, a size the type does not have, a
// count of 0, POINTS other than WIDTH * HEIGHT, an unknown DATA kind, no DATA line at all.
PcdHeader parsePcdHeader(std::span<const std::byte> bytes, const std::string& file);

// The header text of `header` (every line, DATA last, with its line end), as writers put it.
std::string formatPcdHeader(const PcdHeader& header);

// True when `bytes` (the start of a file) begin with PCD header lines: comments, then VERSION or
// FIELDS.
bool looksLikePcd(std::span<const std::byte> bytes);

}  // namespace parallax
