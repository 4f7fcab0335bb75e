// LASzip's "LAS 1.4 compatibility mode" (LASzip 3.x, laszip_dll's writer option): LAS 1.4 points
// of formats 6-10 written as formats 1, 3, 4 or 5 of a LAS 1.2/1.3 file, so that older LAZ
// readers could read them. What the legacy fields cannot hold goes into extra bytes named
// "LAS 1.4 scan angle" (the remainder of the 16-bit angle after the 8-bit rank), "LAS 1.4
// extended returns" (the return number and count above the 3-bit ones, 4 bits each), "LAS 1.4
// classification" (the class above the 5-bit one), "LAS 1.4 flags and channel" (overlap bit,
// scanner channel) and "LAS 1.4 NIR band"; a "lascompatible" VLR keeps the 1.4 header's counts.
// A reader that recognises all of them gets the 1.4 records back, exactly.
#include <cmath>
#include <cstring>

#include "core/byte_order.h"
#include "core/error.h"
#include "io/laz_source.h"

namespace parallax {
namespace {

const LasExtraBytes* findExtra(const LasHeader& header, const char* name) {
  for (const LasExtraBytes& extra : header.extra_bytes) {
    if (extra.name == name) return &extra;
  }
  return nullptr;
}

// The legacy scan angle rank in 0.006-degree units, rounded as LASzip's writer and reader do
// (a float quotient, rounded half away from zero).
std::int32_t rankInAngleUnits(std::int8_t rank) {
  const float units = float(rank) / 0.006f;
  return units >= 0 ? std::int32_t(double(units) + 0.5) : std::int32_t(double(units) - 0.5);
}

}  // namespace

std::optional<LazCompatibility> detectLazCompatibility(const LasHeader& header,
                                                       const std::string& file,
                                                       LasHeader& records) {
  const LasVlr* vlr = nullptr;
  for (const LasVlr& candidate : header.vlrs) {
    if (!candidate.extended && candidate.user_id == "lascompatible" &&
        candidate.record_id == 22204) {
      vlr = &candidate;
    }
  }
  if (vlr == nullptr) return std::nullopt;
  auto refuse = [&](const std::string& found) -> std::optional<LazCompatibility> {
    throw InputError({.file = file,
                      .byte_offset = vlr->data_offset,
                      .element = "'lascompatible' VLR",
                      .expected = "LASzip's LAS 1.4 compatibility mode (point format 1, 3, 4 or 5 "
                                  "with the 'LAS 1.4 ...' extra bytes and a 156- or 174-byte VLR)",
                      .found = found,
                      .hint = "decompress it with LASzip's laszip to a LAS 1.4 file"});
  };
  const int legacy = header.point_format;
  if (legacy != 1 && legacy != 3 && legacy != 4 && legacy != 5) {
    return refuse("point format " + std::to_string(legacy));
  }
  if (vlr->data.size() != 156 && vlr->data.size() != 174) {
    return refuse("a VLR of " + std::to_string(vlr->data.size()) + " bytes");
  }
  const LasExtraBytes* angle = findExtra(header, "LAS 1.4 scan angle");
  const LasExtraBytes* returns = findExtra(header, "LAS 1.4 extended returns");
  const LasExtraBytes* classes = findExtra(header, "LAS 1.4 classification");
  const LasExtraBytes* flags = findExtra(header, "LAS 1.4 flags and channel");
  const LasExtraBytes* nir = findExtra(header, "LAS 1.4 NIR band");
  if (!angle || !returns || !classes || !flags || angle->size != 2 || returns->size != 1 ||
      classes->size != 1 || flags->size != 1 || (nir && nir->size != 2)) {
    return refuse("extra bytes without the four 'LAS 1.4 ...' attributes of their sizes");
  }
  if (nir && legacy != 3 && legacy != 5)
    return refuse("a NIR band in point format " + std::to_string(legacy));
  LazCompatibility c;
  c.legacy_format = legacy;
  c.legacy_length = header.record_length;
  c.scan_angle = angle->record_offset;
  c.extended_returns = returns->record_offset;
  c.classification = classes->record_offset;
  c.flags_and_channel = flags->record_offset;
  if (nir) c.nir = nir->record_offset;

  const int format = legacy == 1 ? 6 : legacy == 3 ? (nir ? 8 : 7) : legacy == 4 ? 9 : 10;
  records = header;
  records.version_minor = 4;
  records.point_format = format;
  std::size_t offset = lasPointFormatSize(format);
  records.extra_bytes.clear();
  for (const LasExtraBytes& extra : header.extra_bytes) {
    if (&extra == angle || &extra == returns || &extra == classes || &extra == flags ||
        &extra == nir) {
      continue;
    }
    c.user_extra.emplace_back(extra.record_offset, extra.size);
    LasExtraBytes moved = extra;
    moved.record_offset = offset;
    offset += extra.size;
    records.extra_bytes.push_back(std::move(moved));
  }
  records.record_length = std::uint16_t(offset);
  // The 1.4 counts (LASzip's VLR: version info 8 bytes, waveform start, EVLR start and count,
  // then the 64-bit point count and 15 counts by return).
  std::uint64_t count;
  std::memcpy(&count, vlr->data.data() + 28, 8);
  if (header.point_count != 0 && count != header.point_count) {
    return refuse("a point count of " + std::to_string(count) + " where the header has " +
                  std::to_string(header.point_count));
  }
  records.point_count = count;
  for (int r = 0; r < 15; ++r) {
    std::memcpy(&records.points_by_return[std::size_t(r)], vlr->data.data() + 36 + 8 * r, 8);
  }
  return c;
}

void convertLazCompatibility(const LazCompatibility& c, const LasHeader& records,
                             const std::byte* legacy, std::size_t count, std::byte* out) {
  const std::size_t in_length = c.legacy_length, out_length = records.record_length;
  const bool color = c.legacy_format == 3 || c.legacy_format == 5;
  for (std::size_t i = 0; i < count; ++i) {
    const std::byte* r = legacy + i * in_length;
    std::byte* o = out + i * out_length;
    std::memset(o, 0, out_length);
    std::memcpy(o, r, 14);  // x y z intensity
    const unsigned bits = unsigned(r[14]), cls = unsigned(r[15]);
    const unsigned more_returns = unsigned(r[c.extended_returns]);
    const unsigned channel_flags = unsigned(r[c.flags_and_channel]);
    const unsigned return_number = (bits & 7) + ((more_returns >> 4) & 15);
    const unsigned returns = ((bits >> 3) & 7) + (more_returns & 15);
    o[14] = std::byte((return_number & 15) | (returns & 15) << 4);
    const unsigned class_flags =
        ((cls >> 5) & 1) | ((cls >> 6) & 1) << 1 | ((cls >> 7) & 1) << 2 | (channel_flags & 1) << 3;
    o[15] = std::byte(class_flags | ((channel_flags >> 1) & 3) << 4 | ((bits >> 6) & 1) << 6 |
                      ((bits >> 7) & 1) << 7);
    o[16] = std::byte((cls & 31) + unsigned(r[c.classification]));
    o[17] = r[17];  // user data
    const auto angle = std::int16_t(loadLE<std::int16_t>(r + c.scan_angle) +
                                    rankInAngleUnits(loadLE<std::int8_t>(r + 16)));
    storeLE(o + 18, angle);
    std::memcpy(o + 20, r + 18, 2);  // point source id
    std::memcpy(o + 22, r + 20, 8);  // GPS time
    std::size_t at = 30;
    if (color) {
      std::memcpy(o + 30, r + 28, 6);
      at = 36;
      if (c.nir) {
        std::memcpy(o + 36, r + *c.nir, 2);
        at = 38;
      }
    }
    if (c.legacy_format >= 4) std::memcpy(o + at, r + (color ? 34 : 28), 29);
    std::size_t extra_at = lasPointFormatSize(records.point_format);
    for (const auto& [offset, size] : c.user_extra) {
      std::memcpy(o + extra_at, r + offset, size);
      extra_at += size;
    }
  }
}

}  // namespace parallax
