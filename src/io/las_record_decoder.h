// LAS point records (formats 0-10, with extra bytes) to columns: shared by the LAS reader, which
// reads records from the file, and the LAZ reader, which decompresses them (a LAZ chunk decodes
// to exactly the records of the uncompressed file). See las_reader.h for the mapping of fields to
// columns.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/attribute_selection.h"
#include "core/point_cloud.h"
#include "io/las_header.h"

namespace parallax {

// How one scalar column is filled from the record.
struct LasFieldDecoder {
  enum class Kind { Bits, Copy, Int64ToDouble, UInt64ToDouble, Scaled };
  Kind kind = Kind::Copy;
  std::size_t offset = 0;   // in the record
  std::size_t size = 0;     // Copy: bytes of one value
  int shift = 0, mask = 0;  // Bits
  int data_type = 0;        // Scaled: the extra bytes base type 1-10
  double scale = 1.0, add = 0.0;
};

struct LasDecodePlan {
  std::size_t record_length = 0;
  bool extended = false;                         // formats 6-10
  bool intensity = true, classification = true;  // those columns filled
  std::optional<std::size_t> color_offset;       // none: no colour, or none asked for
  // The 8-bit rule (las_reader.h): colours below 256 everywhere are kept as they are, otherwise
  // scaled from 16 bits. Decided by the reader before the decode (and checked by it).
  bool colors_8bit = true;
  // The extra bytes read into PointCloud::normals (las_header.h lasNormalExtraBytes): each
  // component's offset in the record and whether it is a double (else a float); none when the
  // file names no normals or they were not asked for.
  struct NormalFields {
    std::array<std::size_t, 3> offset{};
    std::array<bool, 3> is_double{};
    // Three floats side by side in x, y, z order: a Float3 as it is in memory.
    bool adjacentFloats() const {
      return !is_double[0] && !is_double[1] && !is_double[2] && offset[1] == offset[0] + 4 &&
             offset[2] == offset[1] + 4;
    }
  };
  std::optional<NormalFields> normals;
  std::vector<LasFieldDecoder> fields;  // one per scalar column, in order
  std::vector<std::pair<std::string, ScalarType>> columns;
  // The LAZ field groups (laz::fields::k*) the columns come from: what a layered LAZ decoder
  // must decode for this plan (the rest of its layers are never read).
  std::uint32_t laz_fields = 0;
};

// The columns of `header`'s records that `selection` asks for (every one by default); a column
// not asked for is left out of the plan and of allocateLasCloud's cloud.
LasDecodePlan makeLasDecodePlan(const LasHeader& header, const AttributeSelection& selection = {});

// Integer bounds of the positions, and whether a colour of 256 or more was seen, gathered while
// decoding (saves passes over the columns).
struct LasDecodeStats {
  Int3 lo{INT32_MAX, INT32_MAX, INT32_MAX};
  Int3 hi{INT32_MIN, INT32_MIN, INT32_MIN};
  bool color_above_255 = false;

  void merge(const LasDecodeStats& b);
  Bounds3 world(const Quantization& q) const;
};

// Decodes records [0, n) at `records` into `out` from point index `at` (the columns must hold
// at + n points), and adds to `stats`.
void decodeLasRecords(const std::byte* records, std::size_t n, const LasDecodePlan& plan,
                      PointCloud& out, std::size_t at, LasDecodeStats& stats);

// Only the colours of records [0, n) into out.colors from `at` (the second pass when a file
// turns out to hold 16-bit colours after all).
void decodeLasColors(const std::byte* records, std::size_t n, const LasDecodePlan& plan,
                     PointCloud& out, std::size_t at);

// True when a colour channel of one of records [0, n) is 256 or more (needs a color_offset).
bool lasColorsAbove255(const std::byte* records, std::size_t n, const LasDecodePlan& plan);

// A cloud with every column of the plan allocated (untouched) for `count` points, with the
// header's quantization and the source types of LAS.
PointCloud allocateLasCloud(const LasHeader& header, const LasDecodePlan& plan, std::size_t count);

}  // namespace parallax
