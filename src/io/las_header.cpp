#include "io/las_header.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <ctime>
#include <sstream>

#include "core/byte_order.h"
#include "core/byte_source_opener.h"
#include "core/error.h"
#include "io/laz/laz_layout.h"
#include "io/mapped_file.h"

namespace parallax {
namespace {

static_assert(std::endian::native == std::endian::little, "LAS decoding assumes little endian");

// LAS 1.4 R15 Table 7 (point format sizes 0-10).
constexpr std::array<std::size_t, 11> kFormatSizes = {20, 28, 26, 34, 57, 63, 30, 36, 38, 59, 67};

// A fixed-size char field: up to the first NUL, trailing spaces removed.
std::string loadText(const std::byte* p, std::size_t size) {
  std::string text(reinterpret_cast<const char*>(p), size);
  text.resize(std::strlen(text.c_str()));
  while (!text.empty() && text.back() == ' ') text.pop_back();
  return text;
}

[[noreturn]] void fail(const std::string& file, std::uint64_t offset, const std::string& field,
                       const std::string& expected, const std::string& found,
                       const std::string& hint = "") {
  throw InputError({.file = file,
                    .byte_offset = offset,
                    .element = "header",
                    .property = field,
                    .expected = expected,
                    .found = found,
                    .hint = hint});
}

constexpr const char* kTruncatedHint = "the file may be truncated or not a LAS file";

// Extra bytes data types 1-10 (LAS 1.4 R15 Table 24).
struct ExtraType {
  ScalarType type;
  std::size_t size;
  bool is_64bit_int;
};
std::optional<ExtraType> extraType(int data_type) {
  switch (data_type) {
    case 1:
      return ExtraType{ScalarType::UInt8, 1, false};
    case 2:
      return ExtraType{ScalarType::Int8, 1, false};
    case 3:
      return ExtraType{ScalarType::UInt16, 2, false};
    case 4:
      return ExtraType{ScalarType::Int16, 2, false};
    case 5:
      return ExtraType{ScalarType::UInt32, 4, false};
    case 6:
      return ExtraType{ScalarType::Int32, 4, false};
    case 7:
      return ExtraType{ScalarType::Float64, 8, true};  // uint64, read into doubles
    case 8:
      return ExtraType{ScalarType::Float64, 8, true};  // int64
    case 9:
      return ExtraType{ScalarType::Float32, 4, false};
    case 10:
      return ExtraType{ScalarType::Float64, 8, false};
    default:
      return std::nullopt;
  }
}

void parseExtraBytes(LasHeader& header, const LasVlr& vlr, const std::string& file) {
  if (vlr.data.size() % kLasExtraBytesDescriptorSize != 0) {
    fail(file, vlr.data_offset, "extra bytes VLR", "a multiple of 192 bytes (one descriptor each)",
         std::to_string(vlr.data.size()) + " bytes");
  }
  std::size_t offset = lasPointFormatSize(header.point_format);
  for (std::size_t pos = 0; pos < vlr.data.size(); pos += kLasExtraBytesDescriptorSize) {
    const std::byte* d = vlr.data.data() + pos;
    int data_type = int(loadLE<std::uint8_t>(d + 2));
    int options = int(loadLE<std::uint8_t>(d + 3));
    std::string name = loadText(d + 4, 32);
    std::string description = loadText(d + 160, 32);
    if (name.empty()) name = "extra_" + std::to_string(header.extra_bytes.size());
    double scale = loadLE<double>(d + 112), value_offset = loadLE<double>(d + 136);
    bool scaled = (options & (8 | 16)) != 0;
    if (!(options & 8)) scale = 1.0;
    if (!(options & 16)) value_offset = 0.0;
    if (data_type == 0) {
      // Undocumented bytes: `options` is their count; each becomes an unsigned byte column.
      for (int i = 0; i < options; ++i) {
        header.extra_bytes.push_back({name + "_" + std::to_string(i), description, 0,
                                      ScalarType::UInt8, false, offset++, 1});
      }
      continue;
    }
    // 11-30: deprecated 2- and 3-element arrays of the types 1-10, one column per element.
    int base = data_type <= 10 ? data_type : (data_type - 1) % 10 + 1;
    int elements = data_type <= 10 ? 1 : (data_type - 1) / 10 + 1;
    auto type = extraType(base);
    if (!type || data_type > 30) {
      fail(file, vlr.data_offset + pos + 2, "extra bytes data_type", "a type 0-30",
           std::to_string(data_type), "the extra bytes VLR is damaged");
    }
    for (int e = 0; e < elements; ++e) {
      LasExtraBytes column{elements == 1 ? name : name + "[" + std::to_string(e) + "]",
                           description,
                           std::uint8_t(data_type),
                           scaled ? ScalarType::Float64 : type->type,
                           type->is_64bit_int,
                           offset,
                           type->size,
                           scaled,
                           scale,
                           value_offset};
      offset += type->size;
      header.extra_bytes.push_back(std::move(column));
    }
  }
  if (offset > header.record_length) {
    fail(file, vlr.data_offset, "extra bytes VLR",
         "extra bytes that fit the point record of " + std::to_string(header.record_length) +
             " bytes",
         "descriptions of " + std::to_string(offset - lasPointFormatSize(header.point_format)) +
             " bytes after the " + std::to_string(lasPointFormatSize(header.point_format)) +
             "-byte format " + std::to_string(header.point_format) + " fields",
         "the extra bytes VLR does not match the point record length");
  }
}

void parseGeoKeys(LasCrs& crs, const LasVlr& vlr) {
  // GeoKeyDirectoryTag: 4 uint16 of header (version, revision, minor, key count), then 4 uint16
  // per key (id, tag location, count, value or offset). Location 0 means the value is inline.
  std::size_t words = vlr.data.size() / 2;
  if (words < 4) return;
  std::size_t keys = loadLE<std::uint16_t>(vlr.data.data() + 6);
  for (std::size_t k = 0; k < keys && 4 + 4 * k + 3 < words; ++k) {
    const std::byte* p = vlr.data.data() + 8 + 8 * k;
    LasGeoKey key{loadLE<std::uint16_t>(p), loadLE<std::uint16_t>(p + 2),
                  loadLE<std::uint16_t>(p + 4), loadLE<std::uint16_t>(p + 6)};
    crs.geo_keys.push_back(key);
    if (key.location != 0) continue;
    if (key.id == 3072) crs.projected_epsg = key.value;
    if (key.id == 2048) crs.geographic_epsg = key.value;
    if (key.id == 4096) crs.vertical_epsg = key.value;
  }
}

// Reads `size` bytes at `offset` of the header region (checked against the file before).
std::vector<std::byte> readRegion(const ByteSource& in, std::uint64_t offset, std::uint64_t size,
                                  std::string_view element) {
  std::vector<std::byte> bytes(static_cast<std::size_t>(size));
  in.read(offset, bytes, {.element = element});
  return bytes;
}

// The VLRs between the header and the points, then 1.4's EVLRs after them, each read by range:
// a remote file's VLRs usually come with its first request (las_header.h, kLasHeadBytes), its
// EVLRs cost one request each, and no point record is read.
void readVlrs(LasHeader& header, const ByteSource& in, bool with_records) {
  const std::string& file = in.name();
  const std::uint64_t size = in.size();
  std::uint64_t pos = header.header_size;
  for (std::uint32_t i = 0; i < header.vlr_count; ++i) {
    if (pos + kLasVlrHeaderSize > header.point_data_offset) {
      fail(file, pos, "VLR " + std::to_string(i + 1) + " of " + std::to_string(header.vlr_count),
           "a 54-byte VLR header before the point data at byte " +
               std::to_string(header.point_data_offset),
           "it would run past the point data offset",
           "the number of VLRs or the point data offset in the header is wrong");
    }
    const std::vector<std::byte> head = readRegion(in, pos, kLasVlrHeaderSize, "VLR header");
    const std::byte* p = head.data();
    LasVlr vlr;
    vlr.user_id = loadText(p + 2, 16);
    vlr.record_id = loadLE<std::uint16_t>(p + 18);
    vlr.data_size = loadLE<std::uint16_t>(p + 20);
    vlr.description = loadText(p + 22, 32);
    vlr.data_offset = pos + kLasVlrHeaderSize;
    if (vlr.data_offset + vlr.data_size > header.point_data_offset) {
      fail(file, pos + 20, "VLR " + std::to_string(i + 1) + " record length",
           "a payload ending before the point data at byte " +
               std::to_string(header.point_data_offset),
           std::to_string(vlr.data_size) + " bytes, ending at byte " +
               std::to_string(vlr.data_offset + vlr.data_size),
           "the VLR runs past the header region");
    }
    vlr.data = readRegion(in, vlr.data_offset, vlr.data_size, "VLR payload");
    pos = vlr.data_offset + vlr.data_size;
    header.vlrs.push_back(std::move(vlr));
  }
  if (header.evlr_count == 0) return;
  // EVLRs follow the points; a bad offset is reported but only the CRS depends on them.
  pos = header.evlr_offset;
  for (std::uint32_t i = 0; i < header.evlr_count; ++i) {
    if (pos < header.point_data_offset || pos > size || size - pos < kLasEvlrHeaderSize) {
      fail(file, pos, "EVLR " + std::to_string(i + 1) + " of " + std::to_string(header.evlr_count),
           "a 60-byte EVLR header inside the file (" + std::to_string(size) + " bytes)",
           "offset " + std::to_string(pos), "the EVLR offset or count in the header is wrong");
    }
    const std::vector<std::byte> head = readRegion(in, pos, kLasEvlrHeaderSize, "EVLR header");
    const std::byte* p = head.data();
    LasVlr vlr;
    vlr.extended = true;
    vlr.user_id = loadText(p + 2, 16);
    vlr.record_id = loadLE<std::uint16_t>(p + 18);
    vlr.data_size = loadLE<std::uint64_t>(p + 20);
    vlr.description = loadText(p + 28, 32);
    vlr.data_offset = pos + kLasEvlrHeaderSize;
    if (vlr.data_size > size - vlr.data_offset) {
      fail(file, pos + 20, "EVLR " + std::to_string(i + 1) + " record length",
           "a payload inside the file", std::to_string(vlr.data_size) + " bytes",
           "the file may be truncated");
    }
    // Only the small records we use are copied; waveform data stays in the file unless a writer
    // asked for every record.
    if (with_records || ((vlr.user_id == "LASF_Projection" || vlr.user_id == "LASF_Spec") &&
                         vlr.data_size <= (std::uint64_t{16} << 20))) {
      vlr.data = readRegion(in, vlr.data_offset, vlr.data_size, "EVLR payload");
    }
    pos = vlr.data_offset + vlr.data_size;
    header.vlrs.push_back(std::move(vlr));
  }
}

}  // namespace

std::optional<std::size_t> lasUndescribedByteOffset(const std::string& name) {
  static const std::string prefix = lasUndescribedByteName(0).substr(0, 23);
  if (name.size() <= prefix.size() || name.compare(0, prefix.size(), prefix) != 0) return {};
  std::size_t offset = 0;
  for (std::size_t i = prefix.size(); i < name.size(); ++i) {
    if (name[i] < '0' || name[i] > '9' || offset > 65535) return {};
    offset = offset * 10 + std::size_t(name[i] - '0');
  }
  return offset;
}

int lasNormalComponentAxis(std::string_view name) {
  std::string key;
  for (char c : name) {
    if (c == '_' || c == '-' || c == ' ') continue;
    key += (c >= 'A' && c <= 'Z') ? char(c - 'A' + 'a') : c;
  }
  if (key.size() < 2) return -1;
  const std::string_view stem = std::string_view(key).substr(0, key.size() - 1);
  if (stem != "n" && stem != "norm" && stem != "normal") return -1;
  switch (key.back()) {
    case 'x':
      return 0;
    case 'y':
      return 1;
    case 'z':
      return 2;
    default:
      return -1;
  }
}

std::optional<std::array<std::size_t, 3>> lasNormalExtraBytes(
    const std::vector<LasExtraBytes>& extra_bytes) {
  std::array<std::optional<std::size_t>, 3> found;
  for (std::size_t i = 0; i < extra_bytes.size(); ++i) {
    const LasExtraBytes& extra = extra_bytes[i];
    const int axis = lasNormalComponentAxis(extra.name);
    if (axis < 0 || found[std::size_t(axis)]) continue;
    if (extra.scaled || (extra.data_type != 9 && extra.data_type != 10)) return std::nullopt;
    found[std::size_t(axis)] = i;
  }
  if (!found[0] || !found[1] || !found[2]) return std::nullopt;
  return std::array<std::size_t, 3>{*found[0], *found[1], *found[2]};
}

std::size_t lasDescribedRecordEnd(const LasHeader& header) {
  std::size_t end = lasPointFormatSize(header.point_format);
  for (const LasExtraBytes& extra : header.extra_bytes) {
    end = std::max(end, extra.record_offset + extra.size);
  }
  return end;
}

std::size_t lasPointFormatSize(int format) {
  return format >= 0 && format <= kLasMaxPointFormat ? kFormatSizes[std::size_t(format)] : 0;
}
bool lasFormatHasGpsTime(int format) {
  return format != 0 && format != 2;
}
bool lasFormatHasColor(int format) {
  return format == 2 || format == 3 || format == 5 || format == 7 || format == 8 || format == 10;
}
bool lasFormatHasNir(int format) {
  return format == 8 || format == 10;
}
int lasFormatHolding(bool extended, bool gps_time, bool color, bool nir, bool wave_packets) {
  if (extended || nir) {
    if (nir || (color && wave_packets)) return wave_packets ? 10 : 8;
    if (wave_packets) return 9;
    return color ? 7 : 6;
  }
  if (wave_packets) return color ? 5 : 4;
  return (gps_time ? 1 : 0) + (color ? 2 : 0);
}
int lasMinorVersionFor(int format) {
  return format >= 6 ? 4 : format >= 4 ? 3 : format >= 2 ? 2 : 0;
}
bool lasFormatHasWavePacket(int format) {
  return format == 4 || format == 5 || format == 9 || format == 10;
}

std::string LasCrs::summary() const {
  if (!wkt.empty()) {
    // The WKT's outermost name: PROJCS["NAD83 / UTM zone 15N",... or PROJCRS["..."
    auto quote = wkt.find('"');
    auto end = quote == std::string::npos ? quote : wkt.find('"', quote + 1);
    std::string name =
        end == std::string::npos ? wkt.substr(0, 60) : wkt.substr(quote + 1, end - quote - 1);
    return name + " (WKT)";
  }
  if (geo_keys.empty()) return "none";
  std::string text;
  auto add = [&text](const std::string& part) { text += (text.empty() ? "" : " + ") + part; };
  if (projected_epsg && *projected_epsg != 32767) add("EPSG:" + std::to_string(*projected_epsg));
  if (!projected_epsg && geographic_epsg && *geographic_epsg != 32767) {
    add("EPSG:" + std::to_string(*geographic_epsg));
  }
  if (vertical_epsg && *vertical_epsg != 32767) add("EPSG:" + std::to_string(*vertical_epsg));
  if (text.empty()) text = "user-defined";
  if (!geotiff_citation.empty()) text += " \"" + geotiff_citation + "\"";
  return text + " (GeoTIFF keys)";
}

std::string LasHeader::versionString() const {
  return std::to_string(version_major) + "." + std::to_string(version_minor);
}

bool hasLasSignature(std::span<const std::byte> bytes) {
  return bytes.size() >= 4 && std::memcmp(bytes.data(), "LASF", 4) == 0;
}

bool looksLikeLaz(std::span<const std::byte> bytes) {
  if (!hasLasSignature(bytes) || bytes.size() < kLasHeaderSize12) return false;
  // LASzip sets bit 7 (and in its compatibility mode bit 6) of the point format byte.
  return (loadLE<std::uint8_t>(bytes.data() + 104) & 0xC0) != 0;
}

namespace {

LasHeader readHeader(const ByteSource& in, bool with_records) {
  const std::string& file = in.name();
  const std::uint64_t size = in.size();
  // The public header block: at most 375 bytes (1.4), fewer in a shorter file.
  const std::vector<std::byte> bytes =
      readRegion(in, 0, std::min<std::uint64_t>(size, kLasHeaderSize14), "header");
  if (!hasLasSignature(bytes)) {
    std::string_view found(reinterpret_cast<const char*>(bytes.data()),
                           std::min<std::size_t>(bytes.size(), 4));
    fail(file, 0, "file signature", "'LASF'", quoteInput(found), "this is not a LAS file");
  }
  if (size < kLasHeaderSize12) {
    fail(file, 0, "header", "at least 227 bytes (the LAS 1.0-1.2 header)",
         std::to_string(size) + " bytes in the file", kTruncatedHint);
  }
  const std::byte* h = bytes.data();
  LasHeader header;
  header.file_source_id = loadLE<std::uint16_t>(h + 4);
  header.global_encoding = loadLE<std::uint16_t>(h + 6);
  std::memcpy(header.guid.data(), h + 8, header.guid.size());
  header.version_major = loadLE<std::uint8_t>(h + 24);
  header.version_minor = loadLE<std::uint8_t>(h + 25);
  if (header.version_major != 1 || header.version_minor > 4) {
    fail(file, 24, "version", "1.0 to 1.4", header.versionString());
  }
  header.system_identifier = loadText(h + 26, 32);
  header.generating_software = loadText(h + 58, 32);
  header.creation_day = loadLE<std::uint16_t>(h + 90);
  header.creation_year = loadLE<std::uint16_t>(h + 92);
  header.header_size = loadLE<std::uint16_t>(h + 94);
  header.point_data_offset = loadLE<std::uint32_t>(h + 96);
  header.vlr_count = loadLE<std::uint32_t>(h + 100);
  std::uint8_t format_byte = loadLE<std::uint8_t>(h + 104);
  header.record_length = loadLE<std::uint16_t>(h + 105);
  const bool compressed = (format_byte & 0xC0) != 0;
  format_byte &= 0x3F;

  std::size_t minimum_header = header.version_minor <= 2   ? kLasHeaderSize12
                               : header.version_minor == 3 ? kLasHeaderSize13
                                                           : kLasHeaderSize14;
  if (header.header_size < minimum_header || header.header_size > size) {
    fail(file, 94, "header size",
         "at least " + std::to_string(minimum_header) + " bytes for LAS " + header.versionString() +
             ", inside the file (" + std::to_string(size) + " bytes)",
         std::to_string(header.header_size), kTruncatedHint);
  }
  if (header.point_data_offset < header.header_size || header.point_data_offset > size) {
    fail(file, 96, "offset to point data",
         "an offset between the header size (" + std::to_string(header.header_size) +
             ") and the file size (" + std::to_string(size) + ")",
         std::to_string(header.point_data_offset), kTruncatedHint);
  }
  header.point_format = format_byte;
  std::size_t format_size = lasPointFormatSize(header.point_format);
  if (format_size == 0) {
    fail(file, 104, "point data format", "a point data record format 0 to 10",
         std::to_string(format_byte));
  }
  if (header.record_length < format_size) {
    fail(file, 105, "point data record length",
         "at least " + std::to_string(format_size) + " bytes for point format " +
             std::to_string(header.point_format),
         std::to_string(header.record_length));
  }

  std::uint64_t legacy_count = loadLE<std::uint32_t>(h + 107);
  for (int r = 0; r < 5; ++r)
    header.points_by_return[std::size_t(r)] = loadLE<std::uint32_t>(h + 111 + 4 * r);
  for (int axis = 0; axis < 3; ++axis) {
    double scale = loadLE<double>(h + 131 + 8 * axis);
    double offset = loadLE<double>(h + 155 + 8 * axis);
    if (!std::isfinite(scale) || scale == 0.0 || !std::isfinite(offset)) {
      fail(file, std::uint64_t(131 + 8 * axis),
           std::string("xyz").substr(std::size_t(axis), 1) + " scale factor",
           "a finite, non-zero scale and a finite offset",
           "scale " + std::to_string(scale) + ", offset " + std::to_string(offset));
    }
    header.quantization.scale[std::size_t(axis)] = scale;
    header.quantization.offset[std::size_t(axis)] = offset;
    header.bounds.max[std::size_t(axis)] = loadLE<double>(h + 179 + 16 * axis);
    header.bounds.min[std::size_t(axis)] = loadLE<double>(h + 187 + 16 * axis);
  }
  header.point_count = legacy_count;
  if (header.version_minor >= 3) header.waveform_offset = loadLE<std::uint64_t>(h + 227);
  if (header.version_minor >= 4) {
    header.evlr_offset = loadLE<std::uint64_t>(h + 235);
    header.evlr_count = loadLE<std::uint32_t>(h + 243);
    std::uint64_t count = loadLE<std::uint64_t>(h + 247);
    // Writers of formats 0-5 may fill only the legacy count; the 64-bit one wins when set.
    if (count != 0) header.point_count = count;
    for (int r = 0; r < 15; ++r) {
      std::uint64_t n = loadLE<std::uint64_t>(h + 255 + 8 * r);
      if (n != 0 || r >= 5) header.points_by_return[std::size_t(r)] = n;
    }
  }
  std::uint64_t room = size - header.point_data_offset;
  if (header.evlr_count != 0 && header.evlr_offset >= header.point_data_offset &&
      header.evlr_offset <= size) {
    room = header.evlr_offset - header.point_data_offset;
  }
  if (!compressed && header.point_count > room / header.record_length) {
    fail(file, header.version_minor >= 4 ? 247 : 107, "number of point records",
         "at most " + std::to_string(room / header.record_length) + " records of " +
             std::to_string(header.record_length) + " bytes in the " + std::to_string(room) +
             " bytes after the point data offset",
         std::to_string(header.point_count), kTruncatedHint);
  }

  readVlrs(header, in, with_records);
  for (const LasVlr& vlr : header.vlrs) {
    if (vlr.user_id == "LASF_Spec" && vlr.record_id == 4) parseExtraBytes(header, vlr, file);
    if (compressed && !vlr.extended && vlr.user_id == laz::kLaszipUserId &&
        vlr.record_id == laz::kLaszipRecordId && !header.laszip) {
      try {
        header.laszip = laz::parseLaszipVlr(vlr.data);
        header.laszip_vlr_offset = vlr.data_offset;
      } catch (const laz::UnsupportedItems& e) {
        fail(file, vlr.data_offset, "laszip VLR", "a LASzip compression description", e.what(),
             "the file's LAZ description is damaged");
      }
    }
    if (vlr.user_id != "LASF_Projection") continue;
    if (vlr.record_id == 2112) {
      header.crs.wkt.assign(reinterpret_cast<const char*>(vlr.data.data()), vlr.data.size());
      header.crs.wkt.resize(std::strlen(header.crs.wkt.c_str()));
    } else if (vlr.record_id == 34735) {
      parseGeoKeys(header.crs, vlr);
    } else if (vlr.record_id == 34737) {
      header.crs.geotiff_citation.assign(reinterpret_cast<const char*>(vlr.data.data()),
                                         vlr.data.size());
      header.crs.geotiff_citation.resize(std::strlen(header.crs.geotiff_citation.c_str()));
    }
  }
  if (compressed && !header.laszip) {
    fail(file, 104, "point data format",
         "a 'laszip encoded' VLR (record 22204) describing the compression",
         "LASzip's compression bit set in the point format byte but no such VLR",
         "the LAZ file is damaged, or not written by a LAZ writer");
  }
  return header;
}

}  // namespace

LasHeader parseLasHeader(std::span<const std::byte> bytes, const std::string& file_name) {
  return readHeader(*viewMemorySource(bytes, file_name), false);
}

LasHeader readLasHeader(const ByteSource& in) {
  return readHeader(in, false);
}

LasHeader readLasHeaderWithRecords(const ByteSource& in) {
  return readHeader(in, true);
}

std::unique_ptr<ByteSource> openLasSource(const std::filesystem::path& path) {
  if (!isUrl(path.string()) && !std::filesystem::is_regular_file(path)) {
    // A pipe or a special file: read whole into memory (MappedFile's fallback), which the
    // source then owns.
    const MappedFile file(path);
    const std::span<const std::byte> bytes = file.bytes();
    return makeMemorySource(std::vector<std::byte>(bytes.begin(), bytes.end()), path.string());
  }
  return openByteSource(path.string(), kLasHeadBytes);
}

LasHeader readLasHeader(const std::filesystem::path& path) {
  return readLasHeader(*openLasSource(path));
}

LasHeader readLasHeaderWithRecords(const std::filesystem::path& path) {
  return readLasHeaderWithRecords(*openLasSource(path));
}

std::size_t lasHeaderSizeFor(int minor_version) {
  return minor_version >= 4   ? kLasHeaderSize14
         : minor_version == 3 ? kLasHeaderSize13
                              : kLasHeaderSize12;
}

void stampGeneratedBy(LasHeader& header) {
  header.system_identifier = "OTHER";
  header.generating_software = "Parallax";
  std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  header.creation_day = std::uint16_t(utc.tm_yday + 1);
  header.creation_year = std::uint16_t(utc.tm_year + 1900);
}

void LasPointTotals::merge(const LasPointTotals& other) {
  lo = {std::min(lo.x, other.lo.x), std::min(lo.y, other.lo.y), std::min(lo.z, other.lo.z)};
  hi = {std::max(hi.x, other.hi.x), std::max(hi.y, other.hi.y), std::max(hi.z, other.hi.z)};
  for (std::size_t r = 0; r < by_return.size(); ++r) by_return[r] += other.by_return[r];
}

void LasPointTotals::writeTo(LasHeader& header, std::uint64_t point_count) const {
  header.point_count = point_count;
  for (std::size_t r = 0; r < header.points_by_return.size(); ++r) {
    header.points_by_return[r] = by_return[r + 1];
  }
  const Quantization& q = header.quantization;
  header.bounds.min = {q.toWorld(0, lo.x), q.toWorld(1, lo.y), q.toWorld(2, lo.z)};
  header.bounds.max = {q.toWorld(0, hi.x), q.toWorld(1, hi.y), q.toWorld(2, hi.z)};
}

std::vector<std::byte> encodeLasHeader(const LasHeader& header, bool compressed) {
  const std::size_t size = lasHeaderSizeFor(header.version_minor);
  std::vector<std::byte> bytes(size);
  std::byte* h = bytes.data();
  auto text = [](std::byte* to, const std::string& s) {
    std::memcpy(to, s.data(), std::min<std::size_t>(32, s.size()));
  };
  std::memcpy(h, "LASF", 4);
  storeLE(h + 4, header.file_source_id);
  storeLE(h + 6, header.global_encoding);
  std::memcpy(h + 8, header.guid.data(), header.guid.size());
  h[24] = std::byte(header.version_major);
  h[25] = std::byte(header.version_minor);
  text(h + 26, header.system_identifier);
  text(h + 58, header.generating_software);
  storeLE(h + 90, header.creation_day);
  storeLE(h + 92, header.creation_year);
  storeLE(h + 94, std::uint16_t(size));
  storeLE(h + 96, header.point_data_offset);
  storeLE(h + 100, header.vlr_count);
  // LAZ: LASzip's bit 7 says the points are compressed (the laszip VLR says how).
  h[104] = std::byte(header.point_format | (compressed ? 0x80 : 0));
  storeLE(h + 105, header.record_length);
  // Legacy counts are zero for formats 6-10 (R15 2.4) and when they would overflow.
  const bool legacy = header.point_format < 6 && header.point_count <= UINT32_MAX;
  storeLE(h + 107, std::uint32_t(legacy ? header.point_count : 0));
  for (std::size_t r = 0; r < 5; ++r) {
    storeLE(h + 111 + 4 * r, std::uint32_t(legacy ? header.points_by_return[r] : 0));
  }
  const Quantization& q = header.quantization;
  for (std::size_t axis = 0; axis < 3; ++axis) {
    storeLE(h + 131 + 8 * axis, q.scale[axis]);
    storeLE(h + 155 + 8 * axis, q.offset[axis]);
  }
  if (header.point_count > 0) {
    for (std::size_t axis = 0; axis < 3; ++axis) {
      storeLE(h + 179 + 16 * axis, header.bounds.max[axis]);
      storeLE(h + 187 + 16 * axis, header.bounds.min[axis]);
    }
  }
  if (header.version_minor >= 3) storeLE(h + 227, header.waveform_offset);
  if (header.version_minor >= 4) {
    storeLE(h + 235, header.evlr_offset);
    storeLE(h + 243, header.evlr_count);
    storeLE(h + 247, header.point_count);
    for (std::size_t r = 0; r < 15; ++r) storeLE(h + 255 + 8 * r, header.points_by_return[r]);
  }
  return bytes;
}

std::string describeLasHeader(const LasHeader& header) {
  std::ostringstream out;
  out.precision(15);
  out << "LAS " << header.versionString() << ", point format " << header.point_format << " ("
      << header.record_length << " bytes a record), " << header.point_count << " points\n";
  out << "scale " << header.quantization.scale[0] << " " << header.quantization.scale[1] << " "
      << header.quantization.scale[2] << ", offset " << header.quantization.offset[0] << " "
      << header.quantization.offset[1] << " " << header.quantization.offset[2] << "\n";
  out << "header bounds " << header.bounds.min[0] << " " << header.bounds.min[1] << " "
      << header.bounds.min[2] << " .. " << header.bounds.max[0] << " " << header.bounds.max[1]
      << " " << header.bounds.max[2] << "\n";
  out << "CRS " << header.crs.summary() << "\n";
  if (!header.extra_bytes.empty()) {
    out << "extra bytes";
    for (const auto& extra : header.extra_bytes) out << " " << extra.name;
    out << "\n";
  }
  out << "GPS time " << (header.gpsTimeIsStandard() ? "adjusted standard" : "GPS week seconds")
      << ", generated by '" << header.generating_software << "' on '" << header.system_identifier
      << "'";
  if (header.creation_year != 0) {
    out << ", day " << header.creation_day << " of " << header.creation_year;
  }
  out << "\n";
  return out.str();
}

}  // namespace parallax
