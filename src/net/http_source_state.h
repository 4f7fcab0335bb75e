// Internal to net/: the state of an HttpByteSource (http_byte_source.cpp: reads, prefetch and
// the request scheduler; http_probe.cpp: opening) and the wording of its errors.
#pragma once

#include <chrono>
#include <condition_variable>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <random>
#include <string>
#include <unordered_map>
#include <vector>

#include "core/error.h"
#include "net/http_byte_source.h"

namespace parallax {

using NetClock = std::chrono::steady_clock;

// "HTTP 404 Not Found" (the reason phrase for the usual codes).
std::string describeStatus(long status);
// What a failed answer or transfer was, for InputErrorInfo::found.
std::string describeFailure(const HttpResponse& response);
// A way out for that failure, for InputErrorInfo::hint (may be empty).
std::string hintForFailure(const HttpResponse& response);
// The version string of an answer: its ETag, else "Last-Modified: ...", else empty.
std::string versionOf(const CacheValidator& validator);

struct HttpByteSource::State : std::enable_shared_from_this<HttpByteSource::State> {
  // One wanted range.
  struct Piece {
    enum class Status { Queued, InFlight, Done, Failed };
    Status status = Status::Queued;
    int waiters = 0;                // reads blocked on it
    int hint_rank = -1;             // place in the current prefetch hint; -1: not hinted
    std::uint64_t wait_serial = 0;  // order of the first read that waits (urgency)
    int attempts = 0;
    NetClock::time_point not_before{};  // backoff: not requested again before
    std::uint64_t transfer = 0;         // InFlight: its transfer's key
    std::uint64_t done_serial = 0;      // Done: order of arrival (the oldest spare goes first)
    // Done: the answer's body and where this range starts in it.
    std::shared_ptr<const std::vector<std::byte>> body;
    std::size_t body_offset = 0;
    InputErrorInfo error;  // Failed
    bool wanted() const { return waiters > 0 || hint_rank >= 0; }
  };
  struct Transfer {
    std::uint64_t client_id = 0;
    ByteRange span;
    std::vector<ByteRange> parts;
    bool cancelling = false;
  };

  HttpClient* client = nullptr;  // owned by the HttpByteSource (outlives this state's requests)
  std::shared_ptr<RangeCache> cache;
  HttpSourceOptions options;
  std::string url, display_url;
  std::uint64_t size = 0;
  CacheValidator validator;  // of the version being read
  std::string version;
  std::vector<std::byte> head;

  mutable std::mutex mutex;
  mutable std::condition_variable_any changed;  // a piece finished, or no transfer is left
  std::map<ByteRange, Piece> pieces;
  std::unordered_map<std::uint64_t, Transfer> transfers;  // by key
  std::uint64_t next_transfer = 1, next_wait_serial = 1, next_done_serial = 1;
  std::optional<InputErrorInfo> poisoned;  // the version changed: every read fails
  bool closing = false;
  bool timer_armed = false;
  NetClock::time_point timer_at{};
  std::minstd_rand jitter{0x5eed};
  HttpSourceStats stats;

  // The scheduler: starts requests for wanted, queued ranges while there is room. Lock held.
  void pump();
  // Cancels requests none of whose ranges is wanted. Lock held.
  void cancelUnwanted();
  // Drops unwanted pieces: queued and failed ones all, fetched ones (spares: a hint that changed
  // its mind may want them back) beyond options.spare_bytes, the oldest first. Lock held.
  void dropUnwanted();
  // A request's answer (network thread).
  void onAnswer(std::uint64_t key, HttpResponse&& response);
  // An error about [range] of this file, the element left for the reader to fill in.
  InputErrorInfo errorAt(ByteRange range, std::string expected, std::string found,
                         std::string hint = {}) const;
};

}  // namespace parallax
