#include "io/ptx_reader.h"
#include "process/sensor_positions.h"

namespace parallax {

std::vector<std::array<double, 3>> ptxScannerPositions(const std::filesystem::path& path) {
  // The scans' headers come with a read of the whole file (PTX has no index of its scans): a
  // text pass more, the price of orienting a PTX file's normals.
  std::vector<PtxScan> scans;
  readPtx(path, {.scans = &scans});
  std::vector<std::array<double, 3>> positions;
  for (const PtxScan& scan : scans) positions.push_back(scan.position);
  return positions;
}

}  // namespace parallax
