// Process-wide counters of the network layer, for the viewer's panel and the commands' reports:
// every HTTP client and HTTP byte source of the process adds to them.
#pragma once

#include <atomic>
#include <cstdint>

namespace parallax {

struct NetworkCounters {
  std::atomic<std::uint64_t> requests{0};            // HTTP requests submitted
  std::atomic<std::uint64_t> requests_in_flight{0};  // submitted, not yet answered
  std::atomic<std::uint64_t> bytes_received{0};      // body bytes of every answer
  std::atomic<std::uint64_t> cache_hits{0};          // reads served by the on-disk cache
  std::atomic<std::uint64_t> cache_bytes{0};         // bytes they read
  std::atomic<std::uint64_t> retries{0};             // requests sent again after a failure
  std::atomic<std::uint64_t> cancelled{0};           // requests ended early: no longer wanted
  std::atomic<std::uint64_t> failed_reads{0};        // reads that ended in an error
};

NetworkCounters& networkCounters();

// A snapshot, with the rate of received bytes.
struct NetworkStats {
  std::uint64_t requests = 0, requests_in_flight = 0, bytes_received = 0;
  std::uint64_t cache_hits = 0, cache_bytes = 0, retries = 0, cancelled = 0, failed_reads = 0;
  // Bytes received per second, over the time since the snapshot before (when at least half a
  // second ago; otherwise the rate that snapshot gave).
  double bytes_per_second = 0.0;
};

NetworkStats networkStats();

}  // namespace parallax
