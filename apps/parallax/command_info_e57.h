// `parallax info FILE.e57`: the scans (records, coordinates, pose, fields) and the images an E57
// file holds, read from its XML section (command_info.cpp shows them under "format").
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace parallax::cli {

struct E57Description {
  std::string summary;             // "E57 1.0, 2 scans, 0 images"
  std::vector<std::string> lines;  // one per scan and image, indented
  nlohmann::json details;          // the same for --json
};

// Throws InputError for a damaged file (as the reader does).
E57Description describeE57File(const std::filesystem::path& path);

}  // namespace parallax::cli
