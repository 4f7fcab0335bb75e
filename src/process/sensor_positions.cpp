#include "process/sensor_positions.h"

#include <cmath>
#include <fstream>
#include <stdexcept>

#include "core/error.h"
#include "io/e57/e57_reader.h"
#include "io/pcd_header.h"
#include "io/point_file.h"

namespace parallax {

namespace {

constexpr std::array<std::array<const char*, 3>, 3> kColumnTriples{{
    {"sensor_x", "sensor_y", "sensor_z"},
    {"scanner_x", "scanner_y", "scanner_z"},
    {"vp_x", "vp_y", "vp_z"},
}};

// The PCD header's VIEWPOINT position (tx ty tz): the first 64 KiB hold any header.
std::array<double, 3> pcdViewpoint(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::vector<std::byte> head(65536);
  in.read(reinterpret_cast<char*>(head.data()), std::streamsize(head.size()));
  head.resize(std::size_t(in.gcount()));
  const PcdHeader header = parsePcdHeader(head, path.string());
  return {header.viewpoint[0], header.viewpoint[1], header.viewpoint[2]};
}

}  // namespace

SensorPositions SensorPositions::of(const std::filesystem::path& input, const PointCloud& first,
                                    const std::string& step) {
  SensorPositions sensor;
  sensor.input_ = input;
  for (const auto& triple : kColumnTriples) {
    if (first.findScalar(triple[0]) && first.findScalar(triple[1]) && first.findScalar(triple[2])) {
      sensor.columns_ = {triple[0], triple[1], triple[2]};
      sensor.source_ = std::string("columns ") + triple[0] + " " + triple[1] + " " + triple[2];
      return sensor;
    }
  }
  const std::string format(detectPointFormat(input).id());
  const bool scan_index = first.findScalar("scan_index") != nullptr;
  if (format == "e57" && scan_index) {
    const E57ChunkReader reader(input);
    for (const E57Scan& scan : reader.header().document.scans)
      sensor.scan_positions_.push_back(scan.pose.translation);
    sensor.by_scan_ = true;
    sensor.source_ = "the E57 scans' poses";
    return sensor;
  }
  if (format == "ptx" && scan_index) {
    sensor.scan_positions_ = ptxScannerPositions(input);
    sensor.by_scan_ = true;
    sensor.source_ = "the PTX scans' scanner positions";
    return sensor;
  }
  if (format == "pcd") {
    sensor.whole_ = pcdViewpoint(input);
    sensor.source_ = "the PCD VIEWPOINT";
    return sensor;
  }
  throw std::invalid_argument(
      step + ": " + input.string() + " (" + (format.empty() ? "unknown format" : format) +
      ") has no scanner position: no sensor_x/y/z, scanner_x/y/z or vp_x/y/z columns, no E57 "
      "or PTX scans, no PCD VIEWPOINT; give the position with --orient X,Y,Z");
}

std::array<double, 3> SensorPositions::at(const PointCloud& batch, std::size_t i) const {
  if (!columns_[0].empty()) {
    return {batch.findScalar(columns_[0])->valueAsDouble(i),
            batch.findScalar(columns_[1])->valueAsDouble(i),
            batch.findScalar(columns_[2])->valueAsDouble(i)};
  }
  if (by_scan_) {
    const double scan = batch.findScalar("scan_index")->valueAsDouble(i);
    if (!(scan >= 0) || scan >= double(scan_positions_.size()) || scan != std::floor(scan)) {
      throw InputError({.file = input_.string(),
                        .expected = "a scan_index below the " +
                                    std::to_string(scan_positions_.size()) + " scans",
                        .found = std::to_string(scan)});
    }
    return scan_positions_[std::size_t(scan)];
  }
  return whole_;
}

}  // namespace parallax
