// The process's network: one HttpClient (one connection pool for every URL the process opens)
// and one on-disk range cache, configured once by the application, and the function that turns
// an http(s) URL into a ByteSource (installed behind core's openByteSource).
//
// Settings from the environment (networkSettingsFromEnvironment), for the command line and
// tests alike:
//   PARALLAX_HTTP_TIMEOUT   seconds without a byte before a transfer fails (default 20)
//   PARALLAX_HTTP_RETRIES   attempts per range, the first included (default 4)
//   PARALLAX_HTTP_CACHE_MB  bound of the on-disk cache (default 4096; 0 turns it off)
//   PARALLAX_CA_FILE        a CA bundle for TLS verification (default: the system's)
//   http_proxy, https_proxy, all_proxy, no_proxy: read by libcurl (net/http_client.h)
// The cache lives in $XDG_CACHE_HOME/parallax/http (else ~/.cache/parallax/http) unless the
// application names another folder.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "core/byte_source.h"
#include "core/byte_source_opener.h"
#include "net/http_byte_source.h"
#include "net/http_client.h"
#include "net/range_cache.h"

namespace parallax {

struct NetworkSettings {
  HttpOptions http;
  RetryPolicy retry;
  int max_transfers_per_file = 8;
  bool use_cache = true;
  std::filesystem::path cache_dir;  // empty: the user's cache folder (above)
  std::uint64_t cache_bytes = 4ull << 30;
};

// Defaults with the PARALLAX_* variables above applied. Throws std::invalid_argument naming a
// variable whose value is not a number in range.
NetworkSettings networkSettingsFromEnvironment();

// The settings for URLs opened from now on (sources already open keep theirs). Without a call,
// the first URL opened uses networkSettingsFromEnvironment().
void configureNetwork(const NetworkSettings& settings);

// The shared client and cache of the current settings (made on first use). The cache is null
// when turned off or when its folder cannot be made (URLs then work uncached).
std::shared_ptr<HttpClient> networkClient();
std::shared_ptr<RangeCache> networkCache();

// Options for a file's source under the current settings; `head_bytes` as HttpSourceOptions.
HttpSourceOptions networkSourceOptions(std::uint64_t head_bytes = 0);

// http(s) URLs through the shared client and cache (several at once: parallel probes).
std::vector<std::unique_ptr<HttpByteSource>> openHttpSources(std::span<const HttpOpenSpec> specs);

// Registers http and https with core's opener (core/byte_source_opener.h): from then on
// openByteSource of an http(s) URL is an HttpByteSource with the current settings. Called by
// every program that links parallax::net before main (net/http_opener.cpp); calling it again
// changes nothing.
void installHttpOpener();

}  // namespace parallax
