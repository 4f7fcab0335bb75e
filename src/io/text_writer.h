// Writing PointClouds as plain text: one point a line, values separated by a space (.xyz .txt
// .asc), a comma (.csv) or in the PTS layout (.pts).
//
// Columns: every attribute in the source's order (a text or PLY file's own; else x y z, red green
// blue [alpha], nx ny nz, intensity, classification, then every scalar column under its name),
// or the order TextWriteOptions::properties gives, after a header line naming them (read back by
// text_reader.h). PTS has
// no header: its first line is the point count, then x y z [intensity] [r g b] (the other
// attributes are dropped; see describeTextLosses).
//
// Positions are printed as world coordinates: with exactly d decimals when the scale is 10^-d
// (what the text reader and most LAS files use), so the written text is the exact decimal value;
// otherwise with the fewest digits that read back to the same double. Floats print with the
// fewest digits that read back to the same float; integer types as integers.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "core/point_cloud.h"
#include "core/progress.h"

namespace parallax {

struct TextWriteOptions {
  char delimiter = ' ';
  bool header = true;  // a first line naming the columns
  bool pts = false;    // PTS layout (overrides delimiter and header)
  // No header line when the columns are a layout the text reader takes by their count (x y z,
  // x y z intensity, x y z r g b, x y z intensity r g b, x y z r g b nx ny nz): .xyz, whose
  // readers elsewhere expect numbers only (Open3D 0.16's tensor reader refuses a header line).
  bool header_only_when_needed = false;
  Progress* progress = nullptr;  // advanced by points written
  // The columns to write, in this order (as PLY's PlyWriteOptions::properties); empty: every
  // attribute in the source's order. Not for PTS (a fixed layout: std::invalid_argument).
  std::vector<std::string> properties;
};

// The options a path's extension implies: .csv comma-separated, .pts PTS, others blanks; .xyz
// without a header line where the reader needs none.
TextWriteOptions textOptionsForPath(const std::filesystem::path& path);

// What writing `cloud` with `options` would drop (PTS only keeps xyz, intensity and colour).
std::vector<std::string> describeTextLosses(const PointCloud& cloud,
                                            const TextWriteOptions& options);

// Writes to a temporary file beside `path`, renamed at the end (parallel formatting, in order).
// Throws std::runtime_error on I/O failure. A TextStreamWriter fed the whole cloud.
void writeText(const PointCloud& cloud, const std::filesystem::path& path,
               const TextWriteOptions& options = {});

// Text written a batch at a time: memory for one batch's lines, whatever the point count (for
// a cloud larger than memory). `layout`: a cloud with the output's columns and quantization (its
// points are not written; the first batch will do); `count`: the points that will be written
// (PTS's first line; checked by finish()). Every batch must have the layout's columns, in the
// same order, and its quantization. The bytes are those writeText gives the whole cloud.
class TextStreamWriter {
 public:
  TextStreamWriter(const std::filesystem::path& path, const PointCloud& layout, std::uint64_t count,
                   const TextWriteOptions& options = {});
  ~TextStreamWriter();  // unfinished: the temporary file is removed
  TextStreamWriter(const TextStreamWriter&) = delete;
  TextStreamWriter& operator=(const TextStreamWriter&) = delete;

  void write(const PointCloud& batch);
  // Renames the temporary file to `path`. Throws std::logic_error when the points written are
  // not the `count` promised (a PTS header would lie).
  void finish();

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace parallax
