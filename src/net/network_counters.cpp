#include "net/network_counters.h"

#include <chrono>
#include <mutex>

namespace parallax {

NetworkCounters& networkCounters() {
  // Never destroyed: the network thread of the process's client, which ends in a static
  // destructor, still counts its last (cancelled) requests.
  static NetworkCounters* const counters = new NetworkCounters;
  return *counters;
}

NetworkStats networkStats() {
  const NetworkCounters& c = networkCounters();
  NetworkStats stats;
  stats.requests = c.requests.load();
  stats.requests_in_flight = c.requests_in_flight.load();
  stats.bytes_received = c.bytes_received.load();
  stats.cache_hits = c.cache_hits.load();
  stats.cache_bytes = c.cache_bytes.load();
  stats.retries = c.retries.load();
  stats.cancelled = c.cancelled.load();
  stats.failed_reads = c.failed_reads.load();

  // The rate: bytes since the last sample that is at least half a second old.
  using Clock = std::chrono::steady_clock;
  static std::mutex mutex;
  static Clock::time_point sample_time = Clock::now();
  static std::uint64_t sample_bytes = 0;
  static double rate = 0.0;
  std::lock_guard lock(mutex);
  const Clock::time_point now = Clock::now();
  const double seconds = std::chrono::duration<double>(now - sample_time).count();
  if (seconds >= 0.5) {
    rate = double(stats.bytes_received - sample_bytes) / seconds;
    sample_time = now;
    sample_bytes = stats.bytes_received;
  }
  stats.bytes_per_second = rate;
  return stats;
}

}  // namespace parallax
