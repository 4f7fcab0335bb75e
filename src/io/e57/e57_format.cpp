#include "io/e57/e57_format.h"

#include <cstdio>
#include <memory>

#include "io/e57/e57_reader.h"
#include "io/e57/e57_writer.h"
#include "io/format_description.h"
#include "io/point_file.h"

namespace parallax {
namespace {

std::string shortNumber(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", v + 0.0);  // + 0.0: no "-0"
  return text;
}

const char* kindName(E57Field::Kind kind) {
  switch (kind) {
    case E57Field::Kind::Integer:
      return "Integer";
    case E57Field::Kind::ScaledInteger:
      return "ScaledInteger";
    case E57Field::Kind::Float:
      return "Float";
    case E57Field::Kind::String:
      return "String";
  }
  return "?";
}

// `parallax info`: the scans (records, coordinates, position, rotation, fields) and the images
// (listed, never decoded).
FormatDescription describeE57(const std::filesystem::path& path) {
  const E57ChunkReader reader(path);
  const E57Header& header = reader.header();
  const E57Document& document = header.document;
  const std::string version =
      std::to_string(header.version_major) + "." + std::to_string(header.version_minor);
  FormatDescription out;
  out.name = "e57";
  out.summary = "E57 " + version + ", " + std::to_string(document.scans.size()) + " scan(s), " +
                std::to_string(document.images.size()) + " image(s)";
  out.details = {{"version", version},
                 {"guid", document.guid},
                 {"records", header.record_count},
                 {"bounds_measured", header.bounds_measured},
                 {"scans", nlohmann::ordered_json::array()},
                 {"images", nlohmann::ordered_json::array()}};
  if (!header.bounds_measured) out.declared_bounds = header.bounds;
  if (!document.coordinate_metadata.empty()) {
    out.lines.push_back("  coordinate metadata " + document.coordinate_metadata);
    out.details["coordinate_metadata"] = document.coordinate_metadata;
  }
  for (std::size_t s = 0; s < document.scans.size(); ++s) {
    const E57Scan& scan = document.scans[s];
    const bool spherical = scan.field("cartesianX") == nullptr;
    const auto& t = scan.pose.translation;
    const auto& q = scan.pose.rotation;
    out.lines.push_back("  scan " + std::to_string(s) + " '" + scan.name +
                        "': " + std::to_string(scan.record_count) + " records, " +
                        (spherical ? "spherical" : "cartesian") + ", position (" +
                        shortNumber(t[0]) + ", " + shortNumber(t[1]) + ", " + shortNumber(t[2]) +
                        "), rotation (w x y z) (" + shortNumber(q[0]) + ", " + shortNumber(q[1]) +
                        ", " + shortNumber(q[2]) + ", " + shortNumber(q[3]) + ")");
    std::string fields = "    fields";
    nlohmann::ordered_json field_list = nlohmann::ordered_json::array();
    for (const E57Field& field : scan.fields) {
      fields += " " + field.name + ":" + kindName(field.kind);
      field_list.push_back({{"name", field.name}, {"type", kindName(field.kind)}});
    }
    out.lines.push_back(fields);
    out.details["scans"].push_back({{"name", scan.name},
                                    {"guid", scan.guid},
                                    {"records", scan.record_count},
                                    {"coordinates", spherical ? "spherical" : "cartesian"},
                                    {"position", t},
                                    {"rotation_wxyz", q},
                                    {"fields", field_list}});
  }
  for (const E57Image& image : document.images) {
    std::string line = "  image '" + image.name + "': " + image.representation + ", " +
                       (image.format.empty() ? "no image data" : image.format);
    if (image.width > 0) {
      line += ", " + std::to_string(image.width) + " x " + std::to_string(image.height);
    }
    line += ", " + std::to_string(image.byte_length) + " bytes (not decoded)";
    out.lines.push_back(line);
    out.details["images"].push_back({{"name", image.name},
                                     {"representation", image.representation},
                                     {"format", image.format},
                                     {"width", image.width},
                                     {"height", image.height},
                                     {"bytes", image.byte_length}});
  }
  return out;
}

}  // namespace

PointFormatEntry e57Format() {
  PointFormatEntry row;
  row.id = "e57";
  row.name = "E57";
  row.description = "E57 (ASTM E2807: scans with poses, cartesian or spherical; .e57)";
  row.extensions = {".e57"};
  row.detect = [](std::span<const std::byte> head) { return looksLikeE57(head); };
  row.header = [](const std::filesystem::path& path) {
    const E57ChunkReader reader(path);
    PointFileHeader header;
    header.point_count = reader.pointCount();  // records: invalid points are skipped later
    if (!reader.header().bounds_measured) header.bounds = reader.header().bounds;
    header.attributes = reader.header().attributes;
    return header;
  };
  row.read = [](const std::filesystem::path& path, const PointReadOptions& options) {
    return readE57(path, {.progress = options.progress});
  };
  row.preview = readE57Preview;
  row.open_chunks = [](const std::filesystem::path& path, const ChunkSourceOptions& options) {
    auto reader = std::make_unique<E57ChunkReader>(path);
    if (options.quantization) reader->setQuantization(*options.quantization);
    return std::unique_ptr<PointChunkSource>(std::move(reader));
  };
  row.describe = describeE57;
  row.write = [](const PointCloud& cloud, const std::filesystem::path& path,
                 const PointWriteOptions& options) {
    if (!options.properties.empty()) {
      throw std::invalid_argument(path.string() +
                                  ": E57 records are written in a fixed layout (x y z, "
                                  "intensity, colour), no attribute order to choose");
    }
    writeE57(cloud, path, {.progress = options.progress});
  };
  row.write_losses = [](const PointCloud& cloud, const std::filesystem::path&,
                        const PointWriteOptions&) { return describeE57Losses(cloud); };
  row.fixed_layout = [](const std::filesystem::path&) { return true; };
  return row;
}

}  // namespace parallax
