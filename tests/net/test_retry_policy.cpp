// When a request is tried again: 5xx and broken transfers, within the attempts; never 4xx or a
// fatal transport error. Backoff doubles, is capped, and jitters within [half, whole].
#include "net/retry_policy.h"

#include <gtest/gtest.h>

namespace parallax {
namespace {

using std::chrono::milliseconds;

TEST(RetryPolicy, ServerErrorsAndBrokenTransfersAreRetried) {
  const RetryPolicy policy{.max_attempts = 3};
  for (long status : {500L, 502L, 503L, 504L}) {
    EXPECT_EQ(policy.decide(TransportError::None, status, 1), RetryDecision::Retry) << status;
  }
  for (TransportError e :
       {TransportError::Reset, TransportError::Timeout, TransportError::ConnectFailed}) {
    EXPECT_EQ(policy.decide(e, 0, 1), RetryDecision::Retry) << transportErrorName(e);
    EXPECT_EQ(policy.decide(e, 0, 2), RetryDecision::Retry);
    EXPECT_EQ(policy.decide(e, 0, 3), RetryDecision::Fail) << "the attempts are spent";
  }
}

TEST(RetryPolicy, ClientErrorsAndFatalTransportErrorsAreNeverRetried) {
  const RetryPolicy policy{.max_attempts = 10};
  for (long status : {400L, 401L, 403L, 404L, 410L, 416L, 429L}) {
    EXPECT_EQ(policy.decide(TransportError::None, status, 1), RetryDecision::Fail) << status;
  }
  EXPECT_EQ(policy.decide(TransportError::Fatal, 0, 1), RetryDecision::Fail);
}

TEST(RetryPolicy, SuccessIsDone) {
  const RetryPolicy policy;
  for (long status : {200L, 206L, 304L}) {
    EXPECT_EQ(policy.decide(TransportError::None, status, 1), RetryDecision::Done);
  }
}

TEST(RetryPolicy, BackoffDoublesUpToTheCapWithJitter) {
  const RetryPolicy policy{.base_delay = milliseconds(100), .max_delay = milliseconds(1000)};
  // Jitter 1: the whole step; jitter 0: half of it.
  EXPECT_EQ(policy.delay(1, 1.0), milliseconds(100));
  EXPECT_EQ(policy.delay(2, 1.0), milliseconds(200));
  EXPECT_EQ(policy.delay(3, 1.0), milliseconds(400));
  EXPECT_EQ(policy.delay(4, 1.0), milliseconds(800));
  EXPECT_EQ(policy.delay(5, 1.0), milliseconds(1000));
  EXPECT_EQ(policy.delay(60, 1.0), milliseconds(1000));
  EXPECT_EQ(policy.delay(1, 0.0), milliseconds(50));
  EXPECT_EQ(policy.delay(3, 0.5), milliseconds(300));
  EXPECT_EQ(policy.delay(3, 7.0), milliseconds(400)) << "jitter clamped to [0, 1]";
}

TEST(RetryPolicy, RetryAfterIsHonouredWithinTheBounds) {
  const RetryPolicy policy{.base_delay = milliseconds(100), .max_delay = milliseconds(3000)};
  EXPECT_EQ(policy.delay(1, 0.0, std::chrono::seconds(2)), milliseconds(2000));
  EXPECT_EQ(policy.delay(1, 0.0, std::chrono::seconds(60)), milliseconds(3000));
  EXPECT_EQ(policy.delay(1, 0.0, std::chrono::seconds(0)), milliseconds(100));
  EXPECT_EQ(parseRetryAfter(" 120 "), std::chrono::seconds(120));
  EXPECT_EQ(parseRetryAfter("0"), std::chrono::seconds(0));
  EXPECT_FALSE(parseRetryAfter("Wed, 21 Oct 2015 07:28:00 GMT"));
  EXPECT_FALSE(parseRetryAfter(""));
  EXPECT_FALSE(parseRetryAfter("-5"));
  EXPECT_FALSE(parseRetryAfter("12abc"));
}

}  // namespace
}  // namespace parallax
