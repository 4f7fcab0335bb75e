// Which wanted ranges share a request: adjacent ones, within the size limit, never across a gap
// wider than allowed; the scheduler's variant grows from its most urgent range.
#include "net/range_merge.h"

#include <gtest/gtest.h>

#include <vector>

namespace parallax {
namespace {

std::vector<ByteRange> spans(const std::vector<MergedRange>& groups) {
  std::vector<ByteRange> out;
  for (const MergedRange& g : groups) out.push_back(g.span);
  return out;
}

TEST(RangeMerge, AdjacentRangesJoinInOrderOfOffset) {
  // Given out of order: 200-300, 0-100, 100-200, then 400-450 after a gap.
  const std::vector<ByteRange> ranges{{200, 100}, {0, 100}, {400, 50}, {100, 100}};
  const std::vector<MergedRange> groups = mergeRanges(ranges, {});
  ASSERT_EQ(groups.size(), 2u);
  EXPECT_EQ(groups[0].span, (ByteRange{0, 300}));
  EXPECT_EQ(groups[0].members, (std::vector<std::size_t>{1, 3, 0}));
  EXPECT_EQ(groups[1].span, (ByteRange{400, 50}));
  EXPECT_EQ(groups[1].members, (std::vector<std::size_t>{2}));
}

TEST(RangeMerge, AGapIsFetchedOnlyWhenAllowed) {
  const std::vector<ByteRange> ranges{{0, 100}, {110, 90}};
  EXPECT_EQ(spans(mergeRanges(ranges, {.max_gap = 0})),
            (std::vector<ByteRange>{{0, 100}, {110, 90}}));
  EXPECT_EQ(spans(mergeRanges(ranges, {.max_gap = 9})),
            (std::vector<ByteRange>{{0, 100}, {110, 90}}));
  EXPECT_EQ(spans(mergeRanges(ranges, {.max_gap = 10})), (std::vector<ByteRange>{{0, 200}}));
}

TEST(RangeMerge, GroupsStopAtTheSizeLimit) {
  const std::vector<ByteRange> ranges{{0, 40}, {40, 40}, {80, 40}, {120, 40}};
  EXPECT_EQ(spans(mergeRanges(ranges, {.max_bytes = 80})),
            (std::vector<ByteRange>{{0, 80}, {80, 80}}));
  // A range larger than the limit alone is a group of its own.
  const std::vector<ByteRange> large{{0, 10}, {10, 500}, {510, 10}};
  EXPECT_EQ(spans(mergeRanges(large, {.max_bytes = 100})),
            (std::vector<ByteRange>{{0, 10}, {10, 500}, {510, 10}}));
}

TEST(RangeMerge, OverlapsAlwaysJoinAndEmptyRangesAreIgnored) {
  const std::vector<ByteRange> ranges{{0, 100}, {50, 100}, {60, 10}, {500, 0}};
  const std::vector<MergedRange> groups = mergeRanges(ranges, {.max_bytes = 120});
  ASSERT_EQ(groups.size(), 1u);
  EXPECT_EQ(groups[0].span, (ByteRange{0, 150}));
  EXPECT_EQ(groups[0].members, (std::vector<std::size_t>{0, 1, 2}));
}

TEST(RangeMerge, AroundTheSeedNearerNeighboursFirst) {
  // The seed is 100-200; left neighbour touches, right one is 5 bytes away.
  const std::vector<ByteRange> ranges{{205, 50}, {100, 100}, {0, 100}, {1000, 10}};
  const MergedRange touching = mergeAround(ranges, 1, {.max_gap = 0});
  EXPECT_EQ(touching.span, (ByteRange{0, 200}));
  EXPECT_EQ(touching.members, (std::vector<std::size_t>{2, 1}));
  // The left one would make 200 bytes, over the limit; the right one (gap 5) fits.
  const MergedRange limited = mergeAround(ranges, 1, {.max_gap = 5, .max_bytes = 160});
  EXPECT_EQ(limited.span, (ByteRange{100, 155}));
  EXPECT_EQ(limited.members, (std::vector<std::size_t>{1, 0}));
  const MergedRange both = mergeAround(ranges, 1, {.max_gap = 5});
  EXPECT_EQ(both.span, (ByteRange{0, 255}));
  EXPECT_EQ(both.members, (std::vector<std::size_t>{2, 1, 0}));
}

TEST(RangeMerge, AroundALoneSeed) {
  const std::vector<ByteRange> ranges{{0, 10}, {100, 10}};
  const MergedRange alone = mergeAround(ranges, 1, {});
  EXPECT_EQ(alone.span, (ByteRange{100, 10}));
  EXPECT_EQ(alone.members, (std::vector<std::size_t>{1}));
}

}  // namespace
}  // namespace parallax
