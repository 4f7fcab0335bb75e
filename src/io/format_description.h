// A format's own account of a file for `parallax info`, apart from the format table
// (point_format.h) because only `info` and the formats' describe functions need it, and the JSON
// header it holds costs every unit that includes the table about two seconds of compiling.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/bounds.h"

namespace parallax {

// A format's own account of a file for `parallax info`: the first line, the lines under it, and
// the same as JSON ("format_details"; PLY adds "elements").
struct FormatDescription {
  std::string name;                // the format's id: "ply", "las", "laz", "text", ...
  std::string summary;             // one line: "PLY ascii 1.0, header 222 bytes"
  std::vector<std::string> lines;  // details, one a line, already indented
  nlohmann::ordered_json details = nlohmann::ordered_json::object();
  nlohmann::ordered_json elements;         // PLY's elements; null for other formats
  std::optional<Bounds3> declared_bounds;  // bounds the file itself declares (LAS header)
};

}  // namespace parallax
