// PTS files (Leica's plain text export): a line holding the point count, then one point a line,
// x y z intensity r g b (or x y z intensity without colour; x y z and x y z r g b are read too);
// several scans are concatenated, each with its own count line.
//
// The points are parsed by the text reader (text_reader.h, its fast decoder, in PTS mode: count
// lines skipped, 4 values xyz intensity, 7 values xyz intensity rgb); this adds what makes PTS a
// format of its own: the file must start with a count line, and every count must equal the
// number of point lines that follow it. Writing is the text writer's PTS layout (text_writer.h).
#pragma once

#include <cstddef>
#include <filesystem>
#include <span>
#include <string>

#include "core/point_cloud.h"
#include "core/progress.h"

namespace parallax {

struct PtsReadOptions {
  Progress* progress = nullptr;  // advanced by bytes read
  bool parallel = true;
};

// Throws InputError naming the file and the line for: no count line first, a count that differs
// from the point lines after it (the count line's number and what followed), and everything the
// text reader refuses (a value that is not a number, a line with the wrong number of values).
PointCloud readPts(const std::filesystem::path& path, const PtsReadOptions& options = {});

// The same from bytes in memory; `name` stands for the file in messages.
PointCloud readPtsFromMemory(std::span<const std::byte> bytes, const std::string& name,
                             const PtsReadOptions& options = {});

// The count lines' check alone (readPts runs it before the parse). Returns the total count.
std::uint64_t checkPtsCounts(std::string_view text, const std::string& name);

// True when `bytes` (the start of a file) begin like a PTS file: a line of one whole number, then
// a line of 3, 4, 6 or 7 numbers.
bool looksLikePts(std::span<const std::byte> bytes);

}  // namespace parallax
