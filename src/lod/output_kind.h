// What an output name asks for: a point file, a Potree 2.0 octree directory or a COPC file. The
// rule `parallax convert`, `parallax process` and the viewer's Processing panel share, decided
// here once.
#pragma once

#include <filesystem>
#include <string_view>

namespace parallax {

enum class OutputKind { kPointFile, kPotree, kCopc };

// `format`: "potree" or "copc" forces that octree whatever the name (convert's --format); empty:
// from the name. A file name ending in .copc.laz (any case) is COPC; a name ending in '/', an
// existing directory, or a name with no extension is a Potree directory; anything else is a point
// file, whose extension the writer checks (an unknown one is its error, naming the formats).
OutputKind outputKind(const std::filesystem::path& output, std::string_view format = {});

}  // namespace parallax
