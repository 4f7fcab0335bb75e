#include "network_options.h"

#include <cstdio>

#include "core/byte_source_opener.h"
#include "core/url.h"
#include "lod/potree_reader.h"
#include "net/network.h"
#include "net/network_counters.h"

namespace parallax::cli {

void configureNetworkFrom(const LodOptions& lod) {
  NetworkSettings settings = networkSettingsFromEnvironment();
  if (lod.no_cache) settings.use_cache = false;
  if (!lod.cache_dir.empty()) settings.cache_dir = std::filesystem::path(lod.cache_dir) / "http";
  configureNetwork(settings);
}

void printNetworkReport(const char* command, const Octree& octree, std::uint64_t drawn_points) {
  const std::optional<PotreeReadStats> read = potreeReadStats(octree);
  const PotreeMetadata* metadata = potreeMetadata(octree);
  if (!read || !read->remote || !metadata) return;
  const NetworkStats net = networkStats();
  const double needed =
      double(drawn_points) * double(metadata->record_size) + double(read->hierarchy_bytes);
  std::fprintf(stderr,
               "%s: network: %llu requests (%llu retried, %llu cancelled), %.3f MB received, %llu "
               "reads from the "
               "cache (%.3f MB), %llu node loads (%.3f MB); the view needed %.3f MB (drawn nodes "
               "%.3f MB + hierarchy %.3f MB): received / needed = %.3f\n",
               command, static_cast<unsigned long long>(net.requests),
               static_cast<unsigned long long>(net.retries),
               static_cast<unsigned long long>(net.cancelled), double(net.bytes_received) / 1e6,
               static_cast<unsigned long long>(net.cache_hits), double(net.cache_bytes) / 1e6,
               static_cast<unsigned long long>(read->nodes_loaded), double(read->node_bytes) / 1e6,
               needed / 1e6, double(drawn_points) * double(metadata->record_size) / 1e6,
               double(read->hierarchy_bytes) / 1e6,
               needed > 0 ? double(net.bytes_received) / needed : 0.0);
}

void printFetchReport(const char* command, const std::string& input) {
  if (!isUrl(input)) return;
  const NetworkStats net = networkStats();  // before the size's own request
  const std::uint64_t size = openByteSource(input)->size();
  std::fprintf(stderr,
               "%s: network: %llu requests (%llu retried), %llu bytes received of a file of %llu "
               "bytes (%.1f %%), %llu reads from the cache (%llu bytes): %s\n",
               command, static_cast<unsigned long long>(net.requests),
               static_cast<unsigned long long>(net.retries),
               static_cast<unsigned long long>(net.bytes_received),
               static_cast<unsigned long long>(size),
               size > 0 ? 100.0 * double(net.bytes_received) / double(size) : 0.0,
               static_cast<unsigned long long>(net.cache_hits),
               static_cast<unsigned long long>(net.cache_bytes), urlForMessages(input).c_str());
}

}  // namespace parallax::cli
