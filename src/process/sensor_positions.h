// Where each point was scanned from, for `--orient sensor`: normals are turned towards it.
//
// A file tells it one of these ways, looked for in this order:
// - per point, in three columns: sensor_x sensor_y sensor_z, scanner_x scanner_y scanner_z (PLY
//   files of scan software) or vp_x vp_y vp_z (PCL's PointWithViewpoint, in PLY and PCD);
// - per scan, by the point's `scan_index` column: an E57 file's scan poses (the translation: a
//   scan's origin is its scanner) or a PTX file's scanner positions (its header lines);
// - for the whole file, a PCD file's VIEWPOINT line.
// A file with none of these is an error naming the file and what was looked for.
#pragma once

#include <array>
#include <filesystem>
#include <string>
#include <vector>

#include "core/point_cloud.h"

namespace parallax {

class SensorPositions {
 public:
  // The sensor source of `input`, whose first points are `first` (a batch of its stream, for
  // the columns it has). `step` names the step in messages. Throws std::invalid_argument naming
  // the step, the file and what it lacks.
  static SensorPositions of(const std::filesystem::path& input, const PointCloud& first,
                            const std::string& step);

  // The sensor position of point i of `batch` (a batch of the same input). Throws InputError for
  // a scan_index with no scan.
  std::array<double, 3> at(const PointCloud& batch, std::size_t i) const;

  // How the positions are found, for messages: "columns sensor_x sensor_y sensor_z", ...
  const std::string& source() const { return source_; }

 private:
  std::filesystem::path input_;
  std::string source_;
  std::array<std::string, 3> columns_;                 // per point, when set
  std::vector<std::array<double, 3>> scan_positions_;  // by scan_index
  bool by_scan_ = false;
  std::array<double, 3> whole_{0, 0, 0};  // the file's one viewpoint
};

// The scanner positions of a PTX file's scans, in file order (in sensor_ptx.cpp: ptx_reader.h
// and e57_reader.h both name the scan index column).
std::vector<std::array<double, 3>> ptxScannerPositions(const std::filesystem::path& path);

}  // namespace parallax
