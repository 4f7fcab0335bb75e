// Hand-made LAS files for the tests: every field of every point format written byte by byte from
// the LAS 1.4 R15 tables, independently of the writer under test.
#pragma once

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace parallax::test {

struct LasTestPoint {
  std::int32_t x = 0, y = 0, z = 0;
  std::uint16_t intensity = 0;
  std::uint8_t return_number = 1, number_of_returns = 1, scan_direction = 0, edge = 0;
  std::uint8_t classification = 0, flags = 0, channel = 0;  // flags: 1.4 layout (bits 0-3)
  std::int16_t scan_angle = 0;                              // the rank (int8) for formats 0-5
  std::uint8_t user_data = 0;
  std::uint16_t point_source_id = 0;
  double gps_time = 0.0;
  std::uint16_t red = 0, green = 0, blue = 0, nir = 0;
  std::vector<std::uint8_t> extra;  // appended after the format's fields
};

struct LasTestVlr {
  std::string user_id;
  std::uint16_t record_id = 0;
  std::string data;
};

struct LasTestFile {
  int minor = 2;
  int format = 0;
  int extra_bytes = 0;  // per record
  double scale[3] = {0.01, 0.01, 0.01};
  double offset[3] = {0.0, 0.0, 0.0};
  std::uint16_t global_encoding = 0;
  std::vector<LasTestVlr> vlrs;
  std::vector<LasTestPoint> points;
};

inline const int kLasTestFormatSizes[] = {20, 28, 26, 34, 57, 63, 30, 36, 38, 59, 67};

template <class T>
void putAt(std::string& bytes, std::size_t offset, T value) {
  if (bytes.size() < offset + sizeof value) bytes.resize(offset + sizeof value);
  std::memcpy(bytes.data() + offset, &value, sizeof value);
}

inline std::string lasRecord(const LasTestFile& file, const LasTestPoint& p) {
  const int f = file.format;
  std::string r(std::size_t(kLasTestFormatSizes[f] + file.extra_bytes), '\0');
  putAt(r, 0, p.x), putAt(r, 4, p.y), putAt(r, 8, p.z);
  putAt(r, 12, p.intensity);
  bool gps = f != 0 && f != 2;
  if (f >= 6) {
    putAt(r, 14, std::uint8_t(p.return_number | p.number_of_returns << 4));
    putAt(r, 15, std::uint8_t(p.flags | p.channel << 4 | p.scan_direction << 6 | p.edge << 7));
    putAt(r, 16, p.classification);
    putAt(r, 17, p.user_data);
    putAt(r, 18, p.scan_angle);
    putAt(r, 20, p.point_source_id);
    putAt(r, 22, p.gps_time);
    if (f == 7 || f == 8 || f == 10)
      putAt(r, 30, p.red), putAt(r, 32, p.green), putAt(r, 34, p.blue);
    if (f == 8 || f == 10) putAt(r, 36, p.nir);
  } else {
    putAt(r, 14,
          std::uint8_t(p.return_number | p.number_of_returns << 3 | p.scan_direction << 6 |
                       p.edge << 7));
    putAt(r, 15, std::uint8_t(p.classification | (p.flags & 7) << 5));
    putAt(r, 16, std::int8_t(p.scan_angle));
    putAt(r, 17, p.user_data);
    putAt(r, 18, p.point_source_id);
    if (gps) putAt(r, 20, p.gps_time);
    std::size_t c = gps ? 28 : 20;
    if (f == 2 || f == 3 || f == 5)
      putAt(r, c, p.red), putAt(r, c + 2, p.green), putAt(r, c + 4, p.blue);
  }
  for (std::size_t i = 0; i < p.extra.size(); ++i) {
    r[std::size_t(kLasTestFormatSizes[f]) + i] = char(p.extra[i]);
  }
  return r;
}

inline std::string makeLas(const LasTestFile& file) {
  std::size_t header_size = file.minor <= 2 ? 227 : file.minor == 3 ? 235 : 375;
  std::string h(header_size, '\0');
  std::memcpy(h.data(), "LASF", 4);
  putAt(h, 6, file.global_encoding);
  putAt(h, 24, std::uint8_t(1));
  putAt(h, 25, std::uint8_t(file.minor));
  std::memcpy(h.data() + 26, "test", 4);
  putAt(h, 94, std::uint16_t(header_size));
  std::string vlrs;
  for (const auto& vlr : file.vlrs) {
    std::string v(54, '\0');
    std::memcpy(v.data() + 2, vlr.user_id.data(), std::min<std::size_t>(16, vlr.user_id.size()));
    putAt(v, 18, vlr.record_id);
    putAt(v, 20, std::uint16_t(vlr.data.size()));
    vlrs += v + vlr.data;
  }
  putAt(h, 96, std::uint32_t(header_size + vlrs.size()));
  putAt(h, 100, std::uint32_t(file.vlrs.size()));
  putAt(h, 104, std::uint8_t(file.format));
  putAt(h, 105, std::uint16_t(kLasTestFormatSizes[file.format] + file.extra_bytes));
  if (file.format < 6) putAt(h, 107, std::uint32_t(file.points.size()));
  for (int a = 0; a < 3; ++a) {
    putAt(h, std::size_t(131 + 8 * a), file.scale[a]);
    putAt(h, std::size_t(155 + 8 * a), file.offset[a]);
  }
  if (file.minor >= 4) putAt(h, 247, std::uint64_t(file.points.size()));
  std::string out = h + vlrs;
  for (const auto& p : file.points) out += lasRecord(file, p);
  return out;
}

// An extra bytes descriptor (LAS 1.4 R15 Table 24): type, name, optional scale and offset.
inline std::string extraBytesDescriptor(std::uint8_t data_type, const std::string& name,
                                        double scale = 0.0, double offset = 0.0) {
  std::string d(192, '\0');
  d[2] = char(data_type);
  std::uint8_t options = (scale != 0.0 ? 8 : 0) | (offset != 0.0 ? 16 : 0);
  d[3] = char(options);
  std::memcpy(d.data() + 4, name.data(), name.size());
  putAt(d, 112, scale);
  putAt(d, 136, offset);
  return d;
}

}  // namespace parallax::test
