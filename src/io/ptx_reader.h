// Reading PTX files (Leica's structured text export: one or more scans, each a grid of points
// with its pose) into the column model.
//
// A scan is, line by line:
//   columns                       (a whole number)
//   rows                          (a whole number)
//   sx sy sz                      the scanner's position, in the registered frame
//   ax ay az / bx by bz / cx cy cz   the scanner's axes, in the registered frame
//   4 lines of 4 numbers          the scan's transform M, row-major as written, applied to row
//                                 vectors: [X Y Z 1] = [x y z 1] M (the translation is the last row)
//   columns * rows point lines    x y z intensity [r g b], in the scanner's own frame
// then the next scan, to the end of the file. A point line "0 0 0 ..." is a direction the
// scanner got no return from: skipped. Every point line of a file has the same number of values,
// 4 or 7 (with colour).
//
// Mapping: positions transformed by M (world = registered frame), quantized with
// chooseQuantization over the exact bounds; intensity (float, as written, usually 0..1);
// r g b -> colours (0..255); the scan's 0-based index -> the scalar column "scan_index"
// (uint16). Each scan's header (position, axes, transform, grid size, points kept) is kept in
// PtxScan, for code that needs the sensor (normals oriented towards it).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "core/column_names.h"
#include "core/point_cloud.h"
#include "core/progress.h"
#include "io/point_chunk_source.h"

namespace parallax {

struct PtxScan {
  std::uint64_t columns = 0, rows = 0;
  std::array<double, 3> position{0, 0, 0};      // scanner position, registered frame
  std::array<std::array<double, 3>, 3> axes{};  // scanner axes, registered frame
  std::array<double, 16> transform{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};  // row-major
  std::uint64_t first_line = 0;  // 1-based line of its columns line
  std::uint64_t points = 0;      // points kept (zero points skipped)
};

struct PtxReadOptions {
  Progress* progress = nullptr;  // advanced by bytes read
  // Where the scans' headers go, when given (one PtxScan a scan, in file order).
  std::vector<PtxScan>* scans = nullptr;
};

// Reads every valid point of every scan. Throws InputError naming the file, the line and the
// value ("columns", "transform row 2", "x", "intensity", ...) for: a header line with the wrong
// number of values or a value that is not a number, fewer point lines than columns * rows (a
// truncated file), a point line with a value count other than the file's (4 or 7), a colour out
// of 0..255.
PointCloud readPtx(const std::filesystem::path& path, const PtxReadOptions& options = {});

// The same from bytes in memory; `name` stands for the file in messages.
PointCloud readPtxFromMemory(std::span<const std::byte> bytes, const std::string& name,
                             const PtxReadOptions& options = {});

// Every scan's header, read without keeping the points (each scan's point lines are still
// parsed, to count the valid ones and to check them).
std::vector<PtxScan> readPtxScans(const std::filesystem::path& path);

// Streams the valid points of every scan in chunks, in file order. The quantization is fixed
// first, from a pass over the positions (exact bounds), or given.
class PtxChunkReader final : public PointChunkSource {
 public:
  explicit PtxChunkReader(const std::filesystem::path& path,
                          const Quantization* quantization = nullptr);
  ~PtxChunkReader() override;
  PtxChunkReader(PtxChunkReader&&) noexcept;

  const std::vector<PtxScan>& scans() const;
  std::uint64_t pointCount() const override;
  const Quantization& quantization() const override;
  // Replaces `chunk` with the next at most `max_points` points (`max_points` > 0); false (and an
  // empty chunk) at the end.
  bool next(PointCloud& chunk, std::size_t max_points) override;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

// True when `bytes` (the start of a file) begin like a PTX scan: two lines of one whole number,
// four of three numbers, four of four numbers.
bool looksLikePtx(std::span<const std::byte> bytes);

}  // namespace parallax
