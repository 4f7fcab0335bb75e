#include "io/ptx_writer.h"

#include <algorithm>
#include <charconv>
#include <map>
#include <stdexcept>
#include <string>

#include "io/point_file.h"

namespace parallax {
namespace {

template <class T>
void append(std::string& out, T value) {
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  out.append(buffer, result.ptr);
}

void appendNumbers(std::string& out, std::initializer_list<double> values) {
  bool first = true;
  for (double v : values) {
    if (!first) out.push_back(' ');
    first = false;
    append(out, v);
  }
  out.push_back('\n');
}

}  // namespace

void writePtx(const PointCloud& cloud, const std::filesystem::path& path,
              const PtxWriteOptions& options) {
  const ScalarColumn* scan_column = cloud.findScalar(column_names::kScanIndex);
  // The points of each scan, in file order.
  std::map<std::uint64_t, std::vector<std::size_t>> scans;
  for (std::size_t i = 0; i < cloud.count; ++i) {
    const double index = scan_column ? scan_column->valueAsDouble(i) : 0.0;
    if (cloud.worldX(i) == 0 && cloud.worldY(i) == 0 && cloud.worldZ(i) == 0) {
      throw std::invalid_argument(path.string() + ": point " + std::to_string(i) +
                                  " is at (0, 0, 0), which PTX reads as a missing point");
    }
    scans[std::uint64_t(std::max(0.0, index))].push_back(i);
  }
  if (scans.empty()) scans[0];
  OutputFile out(path);
  std::string text;
  for (const auto& [index, points] : scans) {
    text.clear();
    append(text, points.size());
    text += "\n1\n";
    PtxScan pose;
    if (options.scans && index < options.scans->size()) pose = (*options.scans)[index];
    appendNumbers(text, {pose.position[0], pose.position[1], pose.position[2]});
    if (!options.scans || index >= options.scans->size()) {
      pose.axes = {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
    }
    for (const auto& axis : pose.axes) appendNumbers(text, {axis[0], axis[1], axis[2]});
    text += "1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n";  // points are written in world coordinates
    out.write(text);
    text.clear();
    for (const std::size_t i : points) {
      if (text.size() > (1 << 20)) {
        out.write(text);
        text.clear();
      }
      append(text, cloud.worldX(i));
      text.push_back(' ');
      append(text, cloud.worldY(i));
      text.push_back(' ');
      append(text, cloud.worldZ(i));
      text.push_back(' ');
      append(text, cloud.hasIntensity() ? cloud.intensity[i] : 0.0f);
      if (cloud.hasColors()) {
        const Rgba8 c = cloud.colors[i];
        text.push_back(' ');
        append(text, unsigned(c.r));
        text.push_back(' ');
        append(text, unsigned(c.g));
        text.push_back(' ');
        append(text, unsigned(c.b));
      }
      text.push_back('\n');
    }
    out.write(text);
    text.clear();
    if (options.progress) options.progress->advance(points.size());
  }
  out.commit();
}

}  // namespace parallax
