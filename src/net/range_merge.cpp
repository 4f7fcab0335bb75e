#include "net/range_merge.h"

#include <algorithm>
#include <cassert>
#include <numeric>

namespace parallax {
namespace {

// Indices of the non-empty ranges, by offset (then size, then index: a fixed order).
std::vector<std::size_t> byOffset(std::span<const ByteRange> ranges) {
  std::vector<std::size_t> order;
  order.reserve(ranges.size());
  for (std::size_t i = 0; i < ranges.size(); ++i) {
    if (ranges[i].size > 0) order.push_back(i);
  }
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    if (ranges[a].offset != ranges[b].offset) return ranges[a].offset < ranges[b].offset;
    if (ranges[a].size != ranges[b].size) return ranges[a].size < ranges[b].size;
    return a < b;
  });
  return order;
}

// Whether `next` (which starts at or after span.offset) may join `span`.
bool joinsAfter(const ByteRange& span, const ByteRange& next, const MergeLimits& limits) {
  if (next.offset < span.end()) return true;  // overlaps: joining only saves bytes
  const std::uint64_t gap = next.offset - span.end();
  const std::uint64_t end = std::max(span.end(), next.end());
  return gap <= limits.max_gap && end - span.offset <= limits.max_bytes;
}

// Whether `previous` (which starts at or before span.offset) may join `span`.
bool joinsBefore(const ByteRange& span, const ByteRange& previous, const MergeLimits& limits) {
  if (previous.end() > span.offset) return true;
  const std::uint64_t gap = span.offset - previous.end();
  return gap <= limits.max_gap && span.end() - previous.offset <= limits.max_bytes;
}

ByteRange joined(const ByteRange& a, const ByteRange& b) {
  const std::uint64_t offset = std::min(a.offset, b.offset);
  return {offset, std::max(a.end(), b.end()) - offset};
}

}  // namespace

std::vector<MergedRange> mergeRanges(std::span<const ByteRange> ranges, const MergeLimits& limits) {
  std::vector<MergedRange> groups;
  for (std::size_t index : byOffset(ranges)) {
    if (!groups.empty() && joinsAfter(groups.back().span, ranges[index], limits)) {
      groups.back().span = joined(groups.back().span, ranges[index]);
      groups.back().members.push_back(index);
    } else {
      groups.push_back({ranges[index], {index}});
    }
  }
  return groups;
}

MergedRange mergeAround(std::span<const ByteRange> ranges, std::size_t seed,
                        const MergeLimits& limits) {
  assert(seed < ranges.size() && "mergeAround: seed out of range");
  const std::vector<std::size_t> order = byOffset(ranges);
  MergedRange group{ranges[seed], {seed}};
  const auto at = std::find(order.begin(), order.end(), seed);
  if (at == order.end()) return group;  // an empty seed joins nothing
  // [low, high): the positions in `order` taken so far.
  std::size_t low = std::size_t(at - order.begin()), high = low + 1;
  while (true) {
    const bool can_right =
        high < order.size() && joinsAfter(group.span, ranges[order[high]], limits);
    const bool can_left = low > 0 && joinsBefore(group.span, ranges[order[low - 1]], limits);
    if (!can_right && !can_left) break;
    bool take_right = can_right;
    if (can_right && can_left) {
      // The nearer one first; on a tie, forwards (servers and disks read ahead).
      const ByteRange& right = ranges[order[high]];
      const ByteRange& left = ranges[order[low - 1]];
      const std::uint64_t right_gap =
          right.offset > group.span.end() ? right.offset - group.span.end() : 0;
      const std::uint64_t left_gap =
          group.span.offset > left.end() ? group.span.offset - left.end() : 0;
      take_right = right_gap <= left_gap;
    }
    const std::size_t index = take_right ? order[high++] : order[--low];
    group.span = joined(group.span, ranges[index]);
    group.members.push_back(index);
  }
  std::sort(group.members.begin(), group.members.end(), [&](std::size_t a, std::size_t b) {
    return ranges[a].offset != ranges[b].offset ? ranges[a].offset < ranges[b].offset : a < b;
  });
  return group;
}

}  // namespace parallax
