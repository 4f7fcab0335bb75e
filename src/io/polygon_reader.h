// Polygon files for `--clip-polygon` (core/point_filter.h PointFilter::polygon), in the two forms
// a surveyor has at hand:
//   - GeoJSON (RFC 7946): a Polygon geometry, or a Feature or a FeatureCollection holding exactly
//     one Feature whose geometry is a Polygon; one ring (the outer one; holes are refused),
//     positions [x, y] or [x, y, z] (z ignored) in the cloud's own coordinates (no reprojection:
//     RFC 7946's WGS 84 is not assumed).
//   - Text: one vertex a line, "x y" or "x,y" (blanks, tabs, commas or semicolons between; a third
//     number, z, is ignored); blank lines and lines starting with '#' are skipped.
// Told apart by content: a first non-blank character '{' is GeoJSON. In both, a last vertex equal
// to the first (a closed ring, as GeoJSON requires) is dropped; at least 3 vertices remain.
#pragma once

#include <array>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace parallax {

using Polygon2 = std::vector<std::array<double, 2>>;

// Throws InputError naming the file, the line (text) or the JSON path (GeoJSON), what was
// expected and what was found.
Polygon2 readPolygonFile(const std::filesystem::path& path);
Polygon2 parsePolygon(std::string_view text, const std::string& name);

}  // namespace parallax
