// Asynchronous HTTP(S) GETs over libcurl: one network thread drives a curl multi handle, whose
// connection cache is the pool (keep-alive; HTTP/2 multiplexing where a TLS server offers it
// through ALPN, many requests on one connection). Callers on any thread submit requests and get
// a callback, on the network thread, exactly once per request: with the answer, a transport
// error, or `cancelled`.
//
// What every request gets:
// - redirects followed (at most 10, http and https only; the Range header goes along);
// - TLS peers verified (certificate and host name) unless HttpOptions::verify_tls is false; the
//   CA bundle is the system's unless HttpOptions::ca_file names one;
// - proxies from the environment, as libcurl reads them: http_proxy, https_proxy, all_proxy,
//   no_proxy (lower case; HTTPS_PROXY, ALL_PROXY and NO_PROXY upper case too);
// - a connect timeout, and a stall timeout: a transfer that receives nothing for that long
//   fails (TransportError::Timeout), so no request waits forever on a silent server;
// - no content encoding (ranges are of the file's own bytes).
// A request for a range aborts as soon as the headers show an answer that is not that range
// (200 with more than `max_body` bytes: a server that ignores Range), before any body arrives.
//
// The client retries nothing: that is the caller's policy (net/retry_policy.h).
#pragma once

#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <stop_token>
#include <string>
#include <vector>

#include "core/byte_source.h"
#include "net/retry_policy.h"

namespace parallax {

// A transfer slower than this for the whole stall timeout is stalled: a server that trickles a
// few bytes a second (broken, or hostile) never finishes a node but never goes quiet either.
// Far below any real link, even shared by a connection's multiplexed transfers.
inline constexpr long kStallBytesPerSecond = 64;

struct HttpOptions {
  std::chrono::milliseconds connect_timeout{10'000};
  // Under kStallBytesPerSecond received for this long ends a transfer (1 s granularity).
  std::chrono::milliseconds stall_timeout{20'000};
  long max_host_connections = 8;  // HTTP/1.1 connections per host (HTTP/2 multiplexes more)
  bool verify_tls = true;
  std::string ca_file;  // empty: the system's CA bundle
  std::string user_agent = "parallax/0.1 (libcurl)";
};

struct HttpRequest {
  std::string url;
  std::optional<ByteRange> range;  // "Range: bytes=offset-(offset+size-1)"
  // Conditional GET: the server answers 304 when the file still has this ETag / this date.
  std::string if_none_match;
  std::string if_modified_since;
  // A body longer than this aborts the transfer (body_too_large); 0: range->size for a range
  // request, 64 MiB otherwise.
  std::uint64_t max_body = 0;
};

struct HttpResponse {
  long status = 0;  // the final answer's code (after redirects); 0 when none arrived
  TransportError transport = TransportError::None;
  std::string transport_message;  // libcurl's, when transport != None
  bool cancelled = false;
  // The answer was 200 to a range request and larger than max_body: aborted at its headers.
  bool ignored_range = false;
  bool body_too_large = false;
  // Headers of the final answer (empty when absent).
  std::string etag, last_modified, content_range, retry_after;
  std::optional<std::uint64_t> content_length;
  std::string http_version;  // "HTTP/1.1", "HTTP/2", ...
  std::vector<std::byte> body;
};

// "bytes 0-99/1234" -> {0, 100} and total 1234; "bytes */1234" -> total only. Anything else:
// nothing (the caller reports the header it got).
struct ContentRange {
  std::optional<ByteRange> range;
  std::optional<std::uint64_t> total;
};
std::optional<ContentRange> parseContentRange(std::string_view value);

// Counters of one client, since it was made.
struct HttpClientStats {
  std::uint64_t requests = 0;  // submitted
  std::uint64_t completed = 0;
  std::uint64_t in_flight = 0;       // submitted, not yet called back
  std::uint64_t bytes_received = 0;  // body bytes, of every answer
  std::uint64_t cancelled = 0;
  std::uint64_t transport_errors = 0;
};

class HttpClient {
 public:
  using Callback = std::function<void(HttpResponse&&)>;

  explicit HttpClient(HttpOptions options = {});
  // Cancels what is in flight (each callback runs, with `cancelled`) and joins the thread.
  ~HttpClient();
  HttpClient(const HttpClient&) = delete;
  HttpClient& operator=(const HttpClient&) = delete;

  const HttpOptions& options() const { return options_; }

  // Starts a request; returns its id for cancel(). The callback runs on the network thread and
  // must not block for long (it may call submit, cancel and after).
  std::uint64_t submit(HttpRequest request, Callback callback);
  // Ends a request early: its callback runs with `cancelled` (unless it already ran).
  void cancel(std::uint64_t id);
  // Runs `task` on the network thread after `delay` (retries' backoff). Tasks still waiting
  // when the client ends are dropped.
  void after(std::chrono::milliseconds delay, std::function<void()> task);

  // submit() and wait: for callers that have nothing else to do. Requesting `cancel` cancels.
  HttpResponse fetch(HttpRequest request, std::stop_token cancel = {});

  HttpClientStats stats() const;

 private:
  struct State;
  HttpOptions options_;
  std::unique_ptr<State> state_;
};

}  // namespace parallax
