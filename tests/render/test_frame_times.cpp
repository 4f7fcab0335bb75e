// The viewer's recent frame times: the same median, 90th percentile and worst as
// `parallax bench render --orbit` (values[min(n - 1, floor(f * n))] of the sorted times), over
// the last frames only.
#include <gtest/gtest.h>

#include "render/frame_times.h"

namespace parallax {
namespace {

TEST(FrameTimes, SummarisesAsTheOrbitBenchmark) {
  FrameTimes times(10);
  EXPECT_EQ(times.summary().frames, 0u);
  for (double t : {0.05, 0.01, 0.09, 0.03, 0.07, 0.02, 0.10, 0.04, 0.08, 0.06}) times.add(t);
  const FrameTimeSummary s = times.summary();
  EXPECT_EQ(s.frames, 10u);
  EXPECT_DOUBLE_EQ(s.median_s, 0.06);  // sorted[5]
  EXPECT_DOUBLE_EQ(s.p90_s, 0.10);     // sorted[9]
  EXPECT_DOUBLE_EQ(s.worst_s, 0.10);
}

TEST(FrameTimes, KeepsOnlyTheLastFrames) {
  FrameTimes times(3);
  for (double t : {1.0, 2.0, 3.0, 0.5, 0.25}) times.add(t);  // 1.0 and 2.0 dropped
  const FrameTimeSummary s = times.summary();
  EXPECT_EQ(s.frames, 3u);
  EXPECT_DOUBLE_EQ(s.median_s, 0.5);
  EXPECT_DOUBLE_EQ(s.worst_s, 3.0);
  times.clear();
  EXPECT_EQ(times.summary().frames, 0u);
}

TEST(FrameTimes, PercentileOfOneValueIsThatValue) {
  EXPECT_DOUBLE_EQ(framePercentile({0.25}, 0.0), 0.25);
  EXPECT_DOUBLE_EQ(framePercentile({0.25}, 0.9), 0.25);
  EXPECT_DOUBLE_EQ(framePercentile({3.0, 1.0, 2.0, 4.0}, 0.9), 4.0);  // sorted[3]
  EXPECT_DOUBLE_EQ(framePercentile({3.0, 1.0, 2.0, 4.0}, 0.5), 3.0);  // sorted[2]
}

}  // namespace
}  // namespace parallax
