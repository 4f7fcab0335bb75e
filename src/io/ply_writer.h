// Writing PointClouds as PLY: ascii, binary little or big endian.
//
// Columns are written as the point element "vertex" in the types and the order the source had
// (PointCloud::source), so a file read and written back keeps its layout and values: positions
// as float or double (world = quantized * scale + offset), colours as uchar (or ushort scaled by
// 257, or float 0..1), normals nx ny nz, intensity, classification and every scalar column with
// its name and type; without a source order (LAS, generated clouds) in that order. Ascii output
// prints each value with the fewest digits that read back to the same bits.
#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <memory>

#include "core/point_cloud.h"
#include "core/progress.h"
#include "io/ply_header.h"

namespace parallax {

struct PlyWriteOptions {
  PlyFormat format = PlyFormat::BinaryLittleEndian;
  std::vector<std::string> comments;  // written as `comment` lines
  Progress* progress = nullptr;       // advanced by points written
  // The properties to write, in this order (names as PointCloud::attributeNames gives them; x,
  // y and z among them); empty: every attribute in the source's order (PointCloud::
  // attributeOrder). An unknown or repeated name, or a missing x, y or z, throws
  // std::invalid_argument before anything is written.
  std::vector<std::string> properties;
};

// Writes to a temporary file beside `path` and renames it over `path` at the end, so an
// interrupted write never leaves a truncated file under the final name. Throws std::runtime_error
// with the path and the system's reason on I/O failure.
void writePly(const PointCloud& cloud, const std::filesystem::path& path,
              const PlyWriteOptions& options = {});

// Writes a file of known point count chunk by chunk in bounded memory (the generator, converters).
// Every chunk must have the same attributes as `layout` (its columns' presence, scalar names and
// types, source types); `layout.count` is ignored. `finish()` checks that exactly `total_points`
// were written and renames the temporary file into place; destroying an unfinished writer removes
// the temporary file.
class PlyStreamWriter {
 public:
  PlyStreamWriter(const std::filesystem::path& path, const PointCloud& layout,
                  std::uint64_t total_points, const PlyWriteOptions& options = {});
  ~PlyStreamWriter();

  void write(const PointCloud& chunk);
  void finish();

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace parallax
