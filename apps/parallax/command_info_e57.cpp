#include "command_info_e57.h"

#include <cstdio>

#include "io/e57/e57_reader.h"

namespace parallax::cli {
namespace {

std::string fixed(double v) {
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

}  // namespace

E57Description describeE57File(const std::filesystem::path& path) {
  const E57ChunkReader reader(path);
  const E57Header& header = reader.header();
  const E57Document& document = header.document;
  E57Description out;
  out.summary = "E57 " + std::to_string(header.version_major) + "." +
                std::to_string(header.version_minor) + ", " +
                std::to_string(document.scans.size()) + " scan(s), " +
                std::to_string(document.images.size()) + " image(s)";
  out.details = {{"version", std::to_string(header.version_major) + "." +
                                 std::to_string(header.version_minor)},
                 {"guid", document.guid},
                 {"records", header.record_count},
                 {"bounds_measured", header.bounds_measured},
                 {"scans", nlohmann::json::array()},
                 {"images", nlohmann::json::array()}};
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
                        (spherical ? "spherical" : "cartesian") + ", position (" + fixed(t[0]) +
                        ", " + fixed(t[1]) + ", " + fixed(t[2]) + "), rotation (w x y z) (" +
                        fixed(q[0]) + ", " + fixed(q[1]) + ", " + fixed(q[2]) + ", " + fixed(q[3]) +
                        ")");
    std::string fields = "    fields";
    nlohmann::json field_list = nlohmann::json::array();
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

}  // namespace parallax::cli
