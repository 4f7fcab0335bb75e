// LAS 1.0-1.4: the public header block, variable length records (VLRs and 1.4's EVLRs), the
// point data record formats 0-10, the extra bytes descriptions and the coordinate reference system.
// Reference: ASPRS LAS Specification 1.4 R15 (2019), sections 2.4-2.6 (header, VLRs, point
// records) and 2.8-2.9 (extra bytes, EVLRs); LAS 1.0-1.3 for the shorter headers.
//
// All multi-byte values in a LAS file are little endian; this code assumes a little-endian host.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/bounds.h"
#include "core/byte_source.h"
#include "core/point_cloud.h"
#include "core/quantization.h"
#include "core/scalar_type.h"
#include "io/laz/chunk_codec.h"

namespace parallax {

// Header sizes by version: 1.0-1.2, 1.3 (adds the waveform offset), 1.4 (EVLRs, 64-bit counts).
constexpr std::size_t kLasHeaderSize12 = 227;
constexpr std::size_t kLasHeaderSize13 = 235;
constexpr std::size_t kLasHeaderSize14 = 375;
constexpr std::size_t kLasVlrHeaderSize = 54;
constexpr std::size_t kLasEvlrHeaderSize = 60;
constexpr std::size_t kLasExtraBytesDescriptorSize = 192;
constexpr int kLasMaxPointFormat = 10;

// Bytes of the fixed part of a point record of `format` (0-10); 0 for an unknown format.
std::size_t lasPointFormatSize(int format);
bool lasFormatHasGpsTime(int format);
bool lasFormatHasColor(int format);
bool lasFormatHasNir(int format);
bool lasFormatHasWavePacket(int format);
// The smallest point format with the fields asked for: the extended (6-10) layout, GPS time,
// colour, NIR, wave packets (NIR implies the extended layout; 6-10 always have GPS time).
int lasFormatHolding(bool extended, bool gps_time, bool color, bool nir, bool wave_packets);
// The first LAS 1.x version with `format`: 0-1 in 1.0, 2-3 in 1.2, 4-5 in 1.3, 6-10 in 1.4.
int lasMinorVersionFor(int format);
// Formats 6-10 (LAS 1.4) have 4-bit returns, an 8-bit class and a 16-bit scan angle.
constexpr bool lasFormatIsExtended(int format) {
  return format >= 6;
}

struct LasVlr {
  std::string user_id;  // e.g. "LASF_Projection", "LASF_Spec"
  std::uint16_t record_id = 0;
  std::string description;
  bool extended = false;          // an EVLR (after the points, 1.4)
  std::uint64_t data_offset = 0;  // of the payload, in the file
  std::uint64_t data_size = 0;
  // The payload for the records this code understands or copies (projection, spec); empty for
  // the others (waveform data can be gigabytes).
  std::vector<std::byte> data;
};

// One extra-bytes column described by the LASF_Spec record 4 (LAS 1.4 R15 section 2.8.3).
struct LasExtraBytes {
  std::string name;
  std::string description;
  std::uint8_t data_type = 0;  // 0 undocumented bytes, 1-10 scalars, 11-30 deprecated arrays
  ScalarType type = ScalarType::UInt8;  // of one stored value (before scale/offset)
  bool is_64bit_int = false;            // data types 7 and 8: read into doubles
  std::size_t record_offset = 0;        // from the start of the point record
  std::size_t size = 0;                 // bytes of this column in each record
  bool scaled = false;                  // options bit 3 or 4: value = raw * scale + offset
  double scale = 1.0;
  double offset = 0.0;
};

// The column a reader makes of the undescribed byte at `record_offset` (bytes after the format's
// fields and the described extra bytes, which no extra bytes VLR names: kept one UInt8 column a
// byte, so that a LAS or LAZ writer puts them back where they were); and the offset of such a
// column's name, if it is one.
inline std::string lasUndescribedByteName(std::size_t record_offset) {
  return "undescribed_extra_byte_" + std::to_string(record_offset);
}
std::optional<std::size_t> lasUndescribedByteOffset(const std::string& name);
// The points' normals as extra bytes. LAS has no normal field; CloudCompare and PDAL write them
// as three float extra bytes named NormalX NormalY NormalZ (PDAL's dimension names, which its
// LAS reader maps back to its normals), others as nx ny nz or normal_x... A name is a normal's
// component when, in lower case and without '_', '-' and spaces, it is nx, normx or normalx (y,
// z alike): the axis 0-2, or -1.
int lasNormalComponentAxis(std::string_view name);
// The names the LAS writer gives the normals' extra bytes (CloudCompare's and PDAL's).
inline constexpr const char* kLasNormalExtraBytesNames[3] = {"NormalX", "NormalY", "NormalZ"};
// Indices in `extra_bytes` of the x, y and z components of the normals (the first of each name),
// where all three are present, unscaled float or double (data type 9 or 10); nullopt otherwise,
// and the reader keeps such columns as scalars under their names.
std::optional<std::array<std::size_t, 3>> lasNormalExtraBytes(
    const std::vector<LasExtraBytes>& extra_bytes);

// Where the described extra bytes end (the format's size when there are none).
struct LasHeader;
std::size_t lasDescribedRecordEnd(const LasHeader& header);

// Calls f with a value of the C type of an extra bytes data type 1-10 (LAS 1.4 R15 Table 24;
// 10, and anything else a caller lets through, as double): the reader and the writer both.
template <class F>
inline void withExtraDataType(int data_type, F f) {
  switch (data_type) {
    case 1:
      f(std::uint8_t{});
      break;
    case 2:
      f(std::int8_t{});
      break;
    case 3:
      f(std::uint16_t{});
      break;
    case 4:
      f(std::int16_t{});
      break;
    case 5:
      f(std::uint32_t{});
      break;
    case 6:
      f(std::int32_t{});
      break;
    case 7:
      f(std::uint64_t{});
      break;
    case 8:
      f(std::int64_t{});
      break;
    case 9:
      f(float{});
      break;
    default:
      f(double{});
      break;
  }
}

// What the file says about its coordinate reference system. LAS 1.4 with the WKT bit (global
// encoding bit 4) uses OGC WKT (LASF_Projection 2112); older files use GeoTIFF keys (34735, with
// doubles in 34736 and text in 34737).
struct LasGeoKey {
  std::uint16_t id = 0, location = 0, count = 0, value = 0;
};
struct LasCrs {
  std::string wkt;                               // empty when absent
  std::optional<std::uint16_t> projected_epsg;   // GeoTIFF key 3072 (ProjectedCSTypeGeoKey)
  std::optional<std::uint16_t> geographic_epsg;  // key 2048 (GeographicTypeGeoKey)
  std::optional<std::uint16_t> vertical_epsg;    // key 4096 (VerticalCSTypeGeoKey)
  std::string geotiff_citation;                  // GeoAsciiParams text, '|' separators as written
  std::vector<LasGeoKey> geo_keys;

  bool empty() const { return wkt.empty() && geo_keys.empty(); }
  // One line: "EPSG:26915 + EPSG:5703 (GeoTIFF keys)", the WKT's name ("PROJCS[\"NAD83 / UTM
  // zone 15N\"" ...), or "none".
  std::string summary() const;
};

struct LasHeader {
  std::uint8_t version_major = 1;
  std::uint8_t version_minor = 2;
  std::uint16_t file_source_id = 0;
  std::uint16_t global_encoding = 0;  // bit 0: standard GPS time, bit 4: CRS is WKT
  std::array<std::byte, 16> guid{};   // project ID (GUID data 1-4), as stored
  std::string system_identifier;
  std::string generating_software;
  std::uint16_t creation_day = 0;
  std::uint16_t creation_year = 0;
  std::uint16_t header_size = 0;
  std::uint32_t point_data_offset = 0;
  std::uint32_t vlr_count = 0;
  int point_format = 0;             // 0-10
  std::uint16_t record_length = 0;  // >= lasPointFormatSize(point_format)
  std::uint64_t point_count = 0;    // 1.4's 64-bit count, else the legacy 32-bit one
  std::array<std::uint64_t, 15> points_by_return{};
  Quantization quantization;          // exactly the header's scale and offset
  Bounds3 bounds;                     // as the header states it (not checked against the points)
  std::uint64_t waveform_offset = 0;  // 1.3+
  std::uint64_t evlr_offset = 0;      // 1.4
  std::uint32_t evlr_count = 0;       // 1.4
  std::vector<LasVlr> vlrs;           // VLRs, then EVLRs
  std::vector<LasExtraBytes> extra_bytes;
  LasCrs crs;
  // LAZ (LASzip-compressed LAS): the "laszip encoded" VLR, present exactly when the point data
  // format byte has LASzip's bit 7 (or 6) set; `point_format` is then the format without them.
  std::optional<laz::LaszipVlr> laszip;
  std::uint64_t laszip_vlr_offset = 0;  // of the VLR's payload, for messages

  std::string versionString() const;  // "1.4"
  bool gpsTimeIsStandard() const { return (global_encoding & 1) != 0; }
};

// True when `bytes` start with the LAS signature "LASF".
bool hasLasSignature(std::span<const std::byte> bytes);
// True for a LASzip-compressed file: the point format's compression bits (7 or 6) are set, as
// LASzip itself decides. Needs the header bytes; false for anything that is not LAS.
bool looksLikeLaz(std::span<const std::byte> bytes);

// Parses and checks the header, VLRs, EVLRs, extra bytes and CRS of a whole LAS file in `bytes`.
// Throws InputError (file, byte offset, field, expected, found, hint) for: a short file, a wrong
// signature, an unknown version or point format, a LAZ file without its laszip VLR (or a VLR
// that cannot be parsed), a header size or point data offset
// outside the file or below the version's minimum, VLRs or EVLRs running past their region, a
// record length below the format's size, extra bytes not fitting the record, a zero or
// non-finite scale, and a point count the file cannot hold (uncompressed files; a LAZ file's
// count is checked against its chunk table by the LAZ reader). Never allocates more than the
// file's size justifies.
LasHeader parseLasHeader(std::span<const std::byte> bytes, const std::string& file_name);

// The first bytes of a LAS or LAZ file a remote source fetches with its opening request: the
// header and, in nearly every file, all its VLRs (LASzip's, the CRS, extra bytes), so that the
// header costs one request and the points are read by range after it.
constexpr std::uint64_t kLasHeadBytes = 64 << 10;

// A LAS or LAZ file's bytes: a local file (pread) or a URL (core/byte_source_opener.h, its first
// kLasHeadBytes fetched at once), read by range; a pipe or special file read whole into memory.
// Throws InputError when it cannot be opened.
std::unique_ptr<ByteSource> openLasSource(const std::filesystem::path& path);

// The header, VLRs and EVLRs of the LAS or LAZ file `in`, read by range (the header block, each
// VLR, each EVLR; never a point record). Throws as parseLasHeader, naming in.name().
LasHeader readLasHeader(const ByteSource& in);
// The header of a LAS file or URL (openLasSource).
LasHeader readLasHeader(const std::filesystem::path& path);

// The same, with the payload of every VLR and EVLR loaded (parseLasHeader leaves large EVLRs,
// waveform data among them, in the file): what a LAS or LAZ writer carries over.
LasHeader readLasHeaderWithRecords(const ByteSource& in);
LasHeader readLasHeaderWithRecords(const std::filesystem::path& path);

// The public header block of `header` for its version 1.0-1.4 (LAS 1.4 R15 Table 3; 1.0-1.2
// are its first 227 bytes, 1.3 its first 235), the one encoding every LAS, LAZ and COPC writer
// uses. Written as given: version, file source ID, global encoding, GUID, system identifier and
// generating software (at most 32 bytes each), creation date, point data offset, VLR count,
// point format (with LASzip's bit 7 when `compressed`), record length, scale and offset, the
// 1.3 waveform offset and 1.4's EVLR offset and count. The header size is the version's
// standard one. The legacy 32-bit counts hold the point count and returns 1-5 for formats 0-5
// while the count fits (zero otherwise, R15 2.4); 1.4's 64-bit ones always. The bounds are
// written only when there are points (zero otherwise).
std::vector<std::byte> encodeLasHeader(const LasHeader& header, bool compressed);

// The header's size for LAS 1.`minor_version`: 227 (1.0-1.2), 235 (1.3), 375 (1.4).
std::size_t lasHeaderSizeFor(int minor_version);

// Sets what a file Parallax generated (not carried from a source) states about its origin:
// system identifier "OTHER" (R15 Table 4), generating software "Parallax", today's date (UTC).
void stampGeneratedBy(LasHeader& header);

// What a LAS header states of the points it heads, gathered while their records are written:
// the quantized bounds and the count by return number. Each block of records gathers its own
// (on any thread) and the blocks are merged in order; both writers of LAS headers (the LAS/LAZ
// writer and the COPC writer) use it.
struct LasPointTotals {
  Int3 lo{INT32_MAX, INT32_MAX, INT32_MAX};
  Int3 hi{INT32_MIN, INT32_MIN, INT32_MIN};
  std::array<std::uint64_t, 16> by_return{};  // indexed by return number, 0-15

  void addPosition(const Int3& p) {
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  }
  void merge(const LasPointTotals& other);
  // Sets the header's point count, counts by return (returns 1-15) and bounds, in world units
  // through `header.quantization`, which must already be the file's.
  void writeTo(LasHeader& header, std::uint64_t point_count) const;
};

// A few lines for `parallax info`: version, point format and record length, point count,
// scale/offset, header bounds, CRS, extra bytes, generating software.
std::string describeLasHeader(const LasHeader& header);

}  // namespace parallax
