// Which wanted byte ranges of one file go into one HTTP request.
//
// A request costs a round trip, and a Potree octree stores a node's siblings and a chunk's
// nodes one after another in octree.bin, so the nodes a view wants next are often adjacent:
// one `Range: bytes=a-b` for all of them saves round trips without fetching a byte more.
// Ranges closer than `max_gap` are joined too, fetching the gap (0 by default: every byte
// fetched is a byte asked for); a group never grows past `max_bytes`, so one request cannot hold
// the first node back behind megabytes of the others. Overlapping ranges always join.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "core/byte_source.h"

namespace parallax {

struct MergeLimits {
  std::uint64_t max_gap = 0;           // bytes fetched and thrown away between two ranges
  std::uint64_t max_bytes = 8u << 20;  // the most one merged request covers
};

struct MergedRange {
  ByteRange span;                    // what one request fetches
  std::vector<std::size_t> members;  // indices into the input ranges, by offset
};

// Groups `ranges` (any order; empty ones are ignored) into requests, in order of offset. A
// range larger than max_bytes is a group of its own.
std::vector<MergedRange> mergeRanges(std::span<const ByteRange> ranges, const MergeLimits& limits);

// The group that holds ranges[seed], grown from the seed outwards (the nearer neighbour first)
// while the limits allow: for a scheduler that starts with its most urgent range.
MergedRange mergeAround(std::span<const ByteRange> ranges, std::size_t seed,
                        const MergeLimits& limits);

}  // namespace parallax
