// A point file with more points than a frame's budget, as `parallax view FILE` and `parallax
// render FILE` meet it: whether it is over the budget (known before loading it), and how large a
// first picture of it may be. What they then do with it (an even sample at once, the octree in
// the cache) is octree_cache.h, background_octree_build.h and the formats' preview readers.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>

namespace parallax {

// The most points a preview (the first picture of a file over the budget) samples: at 1280 x 720,
// about one a pixel, and read, uploaded and drawn on llvmpipe in well under a second where the
// default budget's 3 M take over two.
constexpr std::uint64_t kPreviewPoints = 1'000'000;

// The number of points of `path` when it is known to hold more than `budget`: from the header
// where the format states it (PLY, LAS); else by the format's counting pass (text: its data
// lines, a pass over the bytes without parsing a number), only when the file is large enough to
// hold more than `budget` points (PointFormatEntry::min_point_bytes; text: "1 2 3\n", 6). std::nullopt when the file is within the budget, or cannot be
// read (the caller's ordinary read then says why).
std::optional<std::uint64_t> pointsOverBudget(const std::filesystem::path& path,
                                              std::uint64_t budget);

}  // namespace parallax
