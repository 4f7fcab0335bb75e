// When a failed HTTP request is tried again, and after how long.
//
// Retried: answers 5xx (the server or a gateway failing, or an object store's "slow down" 503)
// and failures of the transport that say nothing about the data: a connection refused, reset or
// closed before the whole body arrived, a stream reset by HTTP/2, no byte for the stall timeout.
// Never retried: 4xx answers (the request is wrong and asking again cannot help; 429 included:
// object stores throttle with 503) and fatal transport errors (a name that does not resolve, a TLS
// certificate that does not verify, too many redirects, an unsupported scheme).
//
// Backoff: exponential from `base_delay`, capped at `max_delay`, with "equal jitter" (a delay
// between half and all of the step) so that the requests of many clients that failed together do
// not come back together. A Retry-After the server sends is honoured up to `max_delay`.
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <string_view>

namespace parallax {

// How a transfer ended below HTTP (net/http_client.cpp maps libcurl's codes to these).
enum class TransportError {
  None,           // an HTTP answer arrived whole
  ConnectFailed,  // connection refused or unreachable
  Reset,          // reset, closed early, truncated body, HTTP/2 stream error
  Timeout,        // connect timeout, or no byte for the stall timeout
  Fatal,          // anything retrying cannot fix (name, TLS, protocol, redirects)
};

std::string_view transportErrorName(TransportError error);

enum class RetryDecision { Done, Retry, Fail };

struct RetryPolicy {
  int max_attempts = 4;  // attempts in all, the first included
  std::chrono::milliseconds base_delay{250};
  std::chrono::milliseconds max_delay{4000};

  // What to do after an attempt that ended with `transport` and, when an answer came, HTTP
  // `status` (0 when none). 2xx and 3xx are Done (the caller checks what it asked for).
  RetryDecision decide(TransportError transport, long status, int attempts_made) const;

  // The wait before attempt number `attempts_made + 1`. `jitter` in [0, 1) picks the point in
  // the jitter interval (the caller draws it; tests pass fixed values). `retry_after`: the
  // server's Retry-After, when it sent one.
  std::chrono::milliseconds delay(int attempts_made, double jitter,
                                  std::optional<std::chrono::seconds> retry_after = {}) const;
};

// Retry-After as delta-seconds ("120"); HTTP dates and anything else give nothing.
std::optional<std::chrono::seconds> parseRetryAfter(std::string_view value);

}  // namespace parallax
