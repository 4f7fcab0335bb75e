// `parallax info FILE.copc.laz`: what a COPC file holds as an octree (command_info.cpp hands
// COPC files here, told by their content).
#pragma once

#include <filesystem>

namespace parallax::cli {

// Prints the LAS header's summary, the info VLR, the hierarchy (pages, nodes, depth, nodes and
// points per level), bounds, cube, quantization, CRS and attributes; one JSON object with
// `json`. Throws InputError for a damaged file.
int runCopcInfo(const std::filesystem::path& path, bool json);

}  // namespace parallax::cli
