// Records of a Potree 2.0 octree.bin (DEFAULT encoding) to PointCloud columns.
//
// The mapping, chosen once from metadata.json:
//   position (int32 x 3)        -> positions, exactly as stored; the cloud's quantization is the
//                                  metadata's scale and offset
//   rgb (uint16 or uint8 x 3)   -> colors. PotreeConverter copies LAS's 16-bit colour, but some
//                                  writers put 0-255 in the 16-bit fields: when the metadata's
//                                  max of every channel is at most 255 the values are kept as
//                                  they are (source.color = UInt8), otherwise each is rounded to
//                                  value / 257 (source.color = UInt16), the LAS reader's rule.
//                                  "rgba" is read alike; a fourth element is alpha.
//   intensity (any 1 number)    -> intensity (float), source.intensity = its type
//   classification (uint8)      -> classification
//   normals: "NormalX", "NormalY", "NormalZ" (float or double each: Potree's and three-loader's
//            naming) or one 3-element float/double "normal", "normals" or "NORMAL" -> normals
//   everything else             -> a ScalarColumn in its declared type (int64 and uint64 as
//                                  double, exact below 2^53; an array attribute as one column
//                                  per element, "name[i]"). The LAS fields PotreeConverter
//                                  writes get the LAS reader's names ("return number" ->
//                                  return_number, "gps-time" -> gps_time, ...), so a cloud read
//                                  from a Potree directory and from its LAS source look alike.
//                                  "scan angle rank" is declared uint8 by PotreeConverter but
//                                  holds LAS's signed byte (-90..90): it is read as int8.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "core/point_cloud.h"
#include "lod/octree.h"
#include "lod/potree_metadata_reader.h"

namespace parallax {

class PotreeRecordReader {
 public:
  explicit PotreeRecordReader(const PotreeMetadata& metadata);

  // Fills the attribute names and has_* flags of `info` as decoded clouds will have them.
  void describe(OctreeInfo& info) const;

  // Decodes `count` records from `bytes`, which holds exactly count * record size bytes (the
  // caller checks). The cloud's bounds are computed.
  PointCloud decode(std::span<const std::byte> bytes, std::uint64_t count) const;

 private:
  struct ScalarField {
    std::string name;
    std::size_t offset = 0;  // in the record
    PotreeType source = PotreeType::UInt8;
    ScalarType type = ScalarType::UInt8;  // of the column
  };
  struct ColorField {
    bool present = false;
    std::size_t offset = 0;
    bool sixteen_bit = false;  // uint16 fields
    bool scale_down = false;   // values above 255: divide by 257
    bool alpha = false;
  };
  struct NormalField {
    bool present = false;
    std::array<std::size_t, 3> offsets{};
    PotreeType type = PotreeType::Float;
  };
  struct OptionalScalar {
    bool present = false;
    std::size_t offset = 0;
    PotreeType type = PotreeType::UInt8;
  };

  std::size_t record_size_ = 0;
  Quantization quantization_;
  std::size_t position_offset_ = 0;
  ColorField color_;
  NormalField normal_;
  OptionalScalar intensity_, classification_;
  std::vector<ScalarField> scalars_;
};

}  // namespace parallax
