#include "io/e57/e57_writer.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <numbers>
#include <random>

#include "core/column_names.h"
#include "io/e57/e57_pages.h"
#include "io/point_file.h"

namespace parallax {
namespace {

constexpr std::size_t kPacketMax = 64 * 1024;
constexpr std::uint64_t kSectionHeaderSize = 32;
constexpr std::uint64_t kIndexPacketSize = 32;  // a 16-byte header and one 16-byte entry

void store16(std::byte* p, std::uint16_t v) {
  p[0] = std::byte(v), p[1] = std::byte(v >> 8);
}
void store32(std::byte* p, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) p[i] = std::byte(v >> (8 * i));
}
void store64(std::byte* p, std::uint64_t v) {
  for (int i = 0; i < 8; ++i) p[i] = std::byte(v >> (8 * i));
}
std::uint64_t align4(std::uint64_t n) {
  return (n + 3) & ~std::uint64_t{3};
}

unsigned fieldBits(const E57Field& field) {
  switch (field.kind) {
    case E57Field::Kind::Float:
      return field.single_precision ? 32 : 64;
    case E57Field::Kind::Integer:
    case E57Field::Kind::ScaledInteger:
      return unsigned(std::bit_width(std::uint64_t(field.maximum) - std::uint64_t(field.minimum)));
    case E57Field::Kind::String:
      break;
  }
  return 0;
}

// Records a data packet holds: a multiple of 64, so that each field's buffer is a whole number
// of bytes (and of 8-byte words, which libE57Format's decoder reads in), the packet at most
// 64 KiB.
std::size_t recordsPerPacket(const std::vector<unsigned>& bits) {
  std::uint64_t bits_per_record = 0;
  for (unsigned b : bits) bits_per_record += b;
  const std::uint64_t room = kPacketMax - 8 - 2 * bits.size();
  if (bits_per_record == 0) return 1u << 16;
  return std::size_t(std::max<std::uint64_t>(room * 8 / bits_per_record / 64 * 64, 64));
}

std::uint64_t rawOf(const E57Field& field, double value) {
  switch (field.kind) {
    case E57Field::Kind::Float:
      return field.single_precision ? std::bit_cast<std::uint32_t>(float(value))
                                    : std::bit_cast<std::uint64_t>(value);
    case E57Field::Kind::Integer:
    case E57Field::Kind::ScaledInteger: {
      double integer = field.kind == E57Field::Kind::Integer
                           ? value
                           : std::nearbyint((value - field.offset) / field.scale);
      integer = std::clamp(integer, double(field.minimum), double(field.maximum));
      return std::uint64_t(std::int64_t(integer)) - std::uint64_t(field.minimum);
    }
    case E57Field::Kind::String:
      break;
  }
  return 0;
}

void packBits(std::span<const double> values, const E57Field& field, unsigned bits,
              std::byte* out) {
  std::uint64_t bit = 0;
  for (double value : values) {
    const std::uint64_t raw = rawOf(field, value);
    std::byte* p = out + (bit >> 3);
    const unsigned shift = unsigned(bit & 7);
    std::uint64_t word;
    std::memcpy(&word, p, 8);
    word |= raw << shift;
    std::memcpy(p, &word, 8);
    if (shift && shift + bits > 64) p[8] |= std::byte(raw >> (64 - shift));
    bit += bits;
  }
}

std::string number(double v) {
  char text[40];
  std::snprintf(text, sizeof text, "%.17g", v);
  return text;
}

std::string cdata(const std::string& text) {
  std::string out = "<![CDATA[";
  std::size_t start = 0;
  for (std::size_t at; (at = text.find("]]>", start)) != std::string::npos; start = at + 2) {
    out += text.substr(start, at + 2 - start) + "]]><![CDATA[";
  }
  return out + text.substr(start) + "]]>";
}

std::string newGuid(std::mt19937_64& random) {
  const std::uint64_t a = random(), b = random();
  char text[48];
  std::snprintf(text, sizeof text, "{%08x-%04x-4%03x-%04x-%012llx}", unsigned(a >> 32),
                unsigned(a >> 16) & 0xFFFFu, unsigned(a) & 0xFFFu,
                (unsigned(b >> 48) & 0x3FFFu) | 0x8000u,
                static_cast<unsigned long long>(b & 0xFFFFFFFFFFFFull));
  return text;
}

std::string fieldXml(const E57Field& field) {
  std::string xml = "<" + field.name;
  switch (field.kind) {
    case E57Field::Kind::Float:
      xml += " type=\"Float\" precision=\"";
      xml += field.single_precision ? "single\"" : "double\"";
      // The declared range, when given: libE57Format takes a float intensity field's range
      // for the scan's intensity limits.
      if (field.float_minimum < field.float_maximum) {
        xml += " minimum=\"" + number(field.float_minimum) + "\" maximum=\"" +
               number(field.float_maximum) + "\"";
      }
      break;
    case E57Field::Kind::Integer:
      xml += " type=\"Integer\" minimum=\"" + std::to_string(field.minimum) + "\" maximum=\"" +
             std::to_string(field.maximum) + "\"";
      break;
    case E57Field::Kind::ScaledInteger:
      xml += " type=\"ScaledInteger\" minimum=\"" + std::to_string(field.minimum) +
             "\" maximum=\"" + std::to_string(field.maximum) + "\" scale=\"" + number(field.scale) +
             "\" offset=\"" + number(field.offset) + "\"";
      break;
    case E57Field::Kind::String:
      xml += " type=\"String\"";
      break;
  }
  return xml + "/>";
}

std::string floatElement(const char* name, double value) {
  return std::string("<") + name + " type=\"Float\">" + number(value) + "</" + name + ">";
}

std::string scanXml(const E57ScanSource& scan, std::uint64_t section_offset, std::mt19937_64& r) {
  std::string xml = "<vectorChild type=\"Structure\">\n";
  xml += "<guid type=\"String\">" + cdata(newGuid(r)) + "</guid>\n";
  xml += "<name type=\"String\">" + cdata(scan.name) + "</name>\n";
  const auto& q = scan.pose.rotation;
  const auto& t = scan.pose.translation;
  xml += "<pose type=\"Structure\"><rotation type=\"Structure\">" + floatElement("w", q[0]) +
         floatElement("x", q[1]) + floatElement("y", q[2]) + floatElement("z", q[3]) +
         "</rotation><translation type=\"Structure\">" + floatElement("x", t[0]) +
         floatElement("y", t[1]) + floatElement("z", t[2]) + "</translation></pose>\n";
  if (scan.cartesian_bounds) {
    const Bounds3& b = *scan.cartesian_bounds;
    xml += "<cartesianBounds type=\"Structure\">" + floatElement("xMinimum", b.min[0]) +
           floatElement("xMaximum", b.max[0]) + floatElement("yMinimum", b.min[1]) +
           floatElement("yMaximum", b.max[1]) + floatElement("zMinimum", b.min[2]) +
           floatElement("zMaximum", b.max[2]) + "</cartesianBounds>\n";
  }
  if (scan.range_maximum) {
    // Every member of sphericalBounds: libE57Format's reader asks for all six. The angles are
    // their whole ranges; Parallax reads only rangeMaximum.
    const double pi = std::numbers::pi;
    xml += "<sphericalBounds type=\"Structure\">" + floatElement("rangeMinimum", 0.0) +
           floatElement("rangeMaximum", *scan.range_maximum) +
           floatElement("elevationMinimum", -pi / 2) + floatElement("elevationMaximum", pi / 2) +
           floatElement("azimuthStart", -pi) + floatElement("azimuthEnd", pi) +
           "</sphericalBounds>\n";
  }
  if (scan.intensity_limits) {
    xml += "<intensityLimits type=\"Structure\">" +
           floatElement("intensityMinimum", (*scan.intensity_limits)[0]) +
           floatElement("intensityMaximum", (*scan.intensity_limits)[1]) + "</intensityLimits>\n";
  }
  if (scan.color_limits) {
    const char* names[6] = {"colorRedMinimum",   "colorRedMaximum",  "colorGreenMinimum",
                            "colorGreenMaximum", "colorBlueMinimum", "colorBlueMaximum"};
    xml += "<colorLimits type=\"Structure\">";
    for (int i = 0; i < 6; ++i) {
      xml += std::string("<") + names[i] + " type=\"Integer\">" +
             std::to_string(std::int64_t((*scan.color_limits)[i])) + "</" + names[i] + ">";
    }
    xml += "</colorLimits>\n";
  }
  xml += "<points type=\"CompressedVector\" fileOffset=\"" + std::to_string(section_offset) +
         "\" recordCount=\"" + std::to_string(scan.record_count) +
         "\">\n<prototype type=\"Structure\">\n";
  for (const E57Field& field : scan.fields) xml += fieldXml(field) + "\n";
  xml += "</prototype>\n<codecs type=\"Vector\" allowHeterogeneousChildren=\"1\"/>\n</points>\n";
  return xml + "</vectorChild>\n";
}

// Writes one scan's compressed vector section at the writer's position (4-byte aligned) and
// returns its physical offset.
std::uint64_t writeSection(E57PageWriter& pages, const E57ScanSource& scan, Progress* progress) {
  const std::size_t fields = scan.fields.size();
  std::vector<unsigned> bits(fields);
  for (std::size_t f = 0; f < fields; ++f) bits[f] = fieldBits(scan.fields[f]);
  const std::size_t per_packet = recordsPerPacket(bits);
  // The section's length is known before its packets are made: their sizes follow from the
  // record counts, so the header is written first and never revisited.
  auto packetSize = [&](std::uint64_t records) {
    std::uint64_t size = 6 + 2 * fields;
    for (unsigned b : bits) size += (records * b + 7) / 8;
    return align4(size);
  };
  std::uint64_t data_length = 0;
  const std::uint64_t full_packets = scan.record_count / per_packet;
  const std::uint64_t tail = scan.record_count % per_packet;
  data_length += full_packets * packetSize(per_packet) + (tail ? packetSize(tail) : 0);
  const std::uint64_t start = pages.logicalPosition();
  const std::uint64_t section_physical = pages.physicalPosition();
  const std::uint64_t data_physical = e57LogicalToPhysical(start + kSectionHeaderSize);
  const std::uint64_t index_logical = start + kSectionHeaderSize + data_length;
  std::byte header[kSectionHeaderSize] = {};
  header[0] = std::byte{1};
  store64(header + 8, kSectionHeaderSize + data_length + kIndexPacketSize);
  store64(header + 16, data_physical);
  store64(header + 24, e57LogicalToPhysical(index_logical));
  pages.write(header);

  std::vector<std::vector<double>> values(fields);
  std::vector<std::byte> packet;
  for (std::uint64_t first = 0; first < scan.record_count; first += per_packet) {
    const std::size_t n =
        std::size_t(std::min<std::uint64_t>(per_packet, scan.record_count - first));
    for (auto& v : values) v.resize(n);
    scan.fill(first, n, values);
    const std::uint64_t size = packetSize(n);
    packet.assign(size + 16, std::byte{0});
    packet[0] = std::byte{1};
    store16(packet.data() + 2, std::uint16_t(size - 1));
    store16(packet.data() + 4, std::uint16_t(fields));
    std::size_t at = 6 + 2 * fields;
    for (std::size_t f = 0; f < fields; ++f) {
      const std::size_t length = std::size_t((std::uint64_t(n) * bits[f] + 7) / 8);
      store16(packet.data() + 6 + 2 * f, std::uint16_t(length));
      if (bits[f] > 0) packBits(values[f], scan.fields[f], bits[f], packet.data() + at);
      at += length;
    }
    pages.write({packet.data(), std::size_t(size)});
    if (progress) progress->advance(n);
  }
  // The index packet E2807 asks for: one entry, the first data packet.
  std::byte index[kIndexPacketSize] = {};
  store16(index + 2, std::uint16_t(kIndexPacketSize - 1));
  store16(index + 4, 1);
  store64(index + 24, data_physical);
  pages.write(index);
  return section_physical;
}

}  // namespace

void writeE57Scans(std::span<const E57ScanSource> scans, const std::filesystem::path& path,
                   Progress* progress) {
  OutputFile file(path);
  E57PageWriter pages(file);
  std::byte placeholder[kE57FileHeaderSize] = {};
  pages.write(placeholder);
  std::mt19937_64 random(std::random_device{}());
  std::string scans_xml;
  for (const E57ScanSource& scan : scans) {
    E57ScanSource with_bits = scan;
    for (E57Field& field : with_bits.fields) field.bits = fieldBits(field);
    const std::uint64_t offset = writeSection(pages, with_bits, progress);
    scans_xml += scanXml(with_bits, offset, random);
  }
  const std::string xml =
      "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      "<e57Root type=\"Structure\" xmlns=\"http://www.astm.org/COMMIT/E57/2010-e57-v1.0\">\n"
      "<formatName type=\"String\">" +
      cdata("ASTM E57 3D Imaging Data File") + "</formatName>\n<guid type=\"String\">" +
      cdata(newGuid(random)) +
      "</guid>\n<versionMajor type=\"Integer\">1</versionMajor>\n"
      "<versionMinor type=\"Integer\">0</versionMinor>\n"
      "<e57LibraryVersion type=\"String\">" +
      cdata("Parallax") + "</e57LibraryVersion>\n" +
      "<coordinateMetadata type=\"String\"/>\n"
      "<data3D type=\"Vector\" allowHeterogeneousChildren=\"1\">\n" +
      scans_xml +
      "</data3D>\n<images2D type=\"Vector\" allowHeterogeneousChildren=\"1\"/>\n</e57Root>\n";
  const std::uint64_t xml_physical = pages.physicalPosition();
  pages.write({reinterpret_cast<const std::byte*>(xml.data()), xml.size()});
  pages.finish();
  const std::uint64_t length = pages.physicalPosition();  // whole pages after finish()
  std::byte header[kE57FileHeaderSize] = {};
  std::memcpy(header, kE57Signature, 8);
  store32(header + 8, 1);
  store32(header + 12, 0);
  store64(header + 16, length);
  store64(header + 24, xml_physical);
  store64(header + 32, xml.size());
  store64(header + 40, kE57PageSize);
  pages.rewriteStart(header);
  file.commit();
}

std::vector<std::string> describeE57Losses(const PointCloud& cloud) {
  std::vector<std::string> losses;
  if (cloud.hasNormals()) losses.push_back("normals (E57 points have none)");
  if (cloud.hasClassification()) losses.push_back("classification (E57 points have none)");
  if (cloud.hasColors() && cloud.source.has_alpha) losses.push_back("alpha (E57 has no alpha)");
  for (const ScalarColumn& scalar : cloud.scalars) {
    if (scalar.name != column_names::kScanIndex) {
      losses.push_back(scalar.name + " (not written to E57)");
      continue;
    }
    // writeE57 writes one scan: the points of several (A_B.e57's two) become scan 0, and the
    // report said nothing of it.
    double last = 0.0;
    for (std::size_t i = 0; i < cloud.count; ++i) last = std::max(last, scalar.valueAsDouble(i));
    if (last > 0.0) {
      losses.push_back("scan_index (the points of scans 0 to " +
                       std::to_string(std::uint64_t(last)) + " written as one scan)");
    }
  }
  return losses;
}

void writeE57(const PointCloud& cloud, const std::filesystem::path& path,
              const E57WriteOptions& options) {
  E57ScanSource scan;
  scan.name = options.scan_name;
  scan.record_count = cloud.count;
  const Quantization& q = cloud.quantization;
  const char* axes[3] = {"cartesianX", "cartesianY", "cartesianZ"};
  for (int a = 0; a < 3; ++a) {
    E57Field field;
    field.name = axes[a];
    if (options.scaled_integer_positions) {
      std::int32_t lo = 0, hi = 0;
      if (cloud.count > 0) {
        lo = hi = (&cloud.positions[0].x)[a];
        for (const Int3& p : cloud.positions) {
          lo = std::min(lo, (&p.x)[a]), hi = std::max(hi, (&p.x)[a]);
        }
      }
      field.kind = E57Field::Kind::ScaledInteger;
      field.minimum = lo, field.maximum = hi;
      field.scale = q.scale[a], field.offset = q.offset[a];
    } else {
      field.kind = E57Field::Kind::Float;
    }
    scan.fields.push_back(field);
  }
  if (cloud.count > 0) {
    Bounds3 bounds;
    for (std::size_t i = 0; i < cloud.count; ++i) {
      bounds.extend(cloud.worldX(i), cloud.worldY(i), cloud.worldZ(i));
    }
    scan.cartesian_bounds = bounds;
  }
  bool intensity_in_range = true;
  if (cloud.hasIntensity()) {
    float lo = std::numeric_limits<float>::max(), hi = std::numeric_limits<float>::lowest();
    for (float v : cloud.intensity) lo = std::min(lo, v), hi = std::max(hi, v);
    intensity_in_range = cloud.count == 0 || (lo >= 0.0f && hi <= 65535.0f);
    E57Field field;
    field.name = "intensity";
    field.kind = E57Field::Kind::Float;
    field.single_precision = true;
    if (intensity_in_range) {
      // Limits the reader maps onto 0..65535: onto the values themselves.
      scan.intensity_limits = std::array<double, 2>{0.0, 65535.0};
      field.float_minimum = 0.0, field.float_maximum = 65535.0;
    } else {
      // No limits: the reader keeps the values as stored.
      field.float_minimum = lo, field.float_maximum = hi;
    }
    scan.fields.push_back(field);
  }
  if (cloud.hasColors()) {
    for (const char* name : {"colorRed", "colorGreen", "colorBlue"}) {
      E57Field field;
      field.name = name;
      field.kind = E57Field::Kind::Integer;
      field.minimum = 0, field.maximum = 255;
      scan.fields.push_back(field);
    }
    scan.color_limits = std::array<double, 6>{0, 255, 0, 255, 0, 255};
  }
  const bool scaled = options.scaled_integer_positions;
  const bool has_intensity = cloud.hasIntensity();
  scan.fill = [&, scaled, has_intensity](std::uint64_t first, std::size_t count,
                                         std::vector<std::vector<double>>& values) {
    for (std::size_t i = 0; i < count; ++i) {
      const std::size_t p = std::size_t(first + i);
      const Int3& position = cloud.positions[p];
      for (int a = 0; a < 3; ++a) {
        const std::int32_t raw = (&position.x)[a];
        values[std::size_t(a)][i] =
            scaled ? double(raw) * q.scale[a] + q.offset[a] : q.toWorld(a, raw);
      }
      std::size_t f = 3;
      if (has_intensity) values[f++][i] = cloud.intensity[p];
      if (cloud.hasColors()) {
        const Rgba8& c = cloud.colors[p];
        values[f][i] = c.r, values[f + 1][i] = c.g, values[f + 2][i] = c.b;
      }
    }
  };
  writeE57Scans({&scan, 1}, path, options.progress);
}

}  // namespace parallax
