#include "net/retry_policy.h"

#include <algorithm>
#include <charconv>

namespace parallax {

std::string_view transportErrorName(TransportError error) {
  switch (error) {
    case TransportError::None:
      return "none";
    case TransportError::ConnectFailed:
      return "connection failed";
    case TransportError::Reset:
      return "connection reset or closed early";
    case TransportError::Timeout:
      return "timed out";
    case TransportError::Fatal:
      return "fatal";
  }
  return "unknown";
}

RetryDecision RetryPolicy::decide(TransportError transport, long status, int attempts_made) const {
  bool retryable = false;
  switch (transport) {
    case TransportError::None:
      if (status >= 200 && status < 400) return RetryDecision::Done;
      retryable = status >= 500 && status < 600;
      break;
    case TransportError::ConnectFailed:
    case TransportError::Reset:
    case TransportError::Timeout:
      retryable = true;
      break;
    case TransportError::Fatal:
      retryable = false;
      break;
  }
  if (!retryable) return RetryDecision::Fail;
  return attempts_made < max_attempts ? RetryDecision::Retry : RetryDecision::Fail;
}

std::chrono::milliseconds RetryPolicy::delay(
    int attempts_made, double jitter, std::optional<std::chrono::seconds> retry_after) const {
  const std::chrono::milliseconds cap = std::max(max_delay, base_delay);
  if (retry_after) {
    return std::min<std::chrono::milliseconds>(
        std::max<std::chrono::milliseconds>(*retry_after, base_delay), cap);
  }
  // base * 2^(attempts - 1), computed without overflow.
  std::chrono::milliseconds step = base_delay;
  for (int i = 1; i < attempts_made && step < cap; ++i) step *= 2;
  step = std::min(step, cap);
  jitter = std::clamp(jitter, 0.0, 1.0);
  const double half = double(step.count()) / 2.0;
  return std::chrono::milliseconds(std::int64_t(half + half * jitter));
}

std::optional<std::chrono::seconds> parseRetryAfter(std::string_view value) {
  while (!value.empty() && (value.front() == ' ' || value.front() == '\t')) value.remove_prefix(1);
  while (!value.empty() && (value.back() == ' ' || value.back() == '\t' || value.back() == '\r' ||
                            value.back() == '\n')) {
    value.remove_suffix(1);
  }
  std::int64_t seconds = 0;
  const auto [end, error] = std::from_chars(value.data(), value.data() + value.size(), seconds);
  if (error != std::errc() || end != value.data() + value.size() || value.empty() || seconds < 0) {
    return std::nullopt;
  }
  return std::chrono::seconds(seconds);
}

}  // namespace parallax
