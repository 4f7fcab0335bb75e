#include "net/network.h"

#include <charconv>
#include <cstdlib>
#include <iterator>
#include <mutex>
#include <optional>
#include <stdexcept>

#include "core/byte_source_opener.h"
#include "core/url.h"

namespace parallax {
namespace {

std::optional<std::uint64_t> environmentNumber(const char* name, std::uint64_t low,
                                               std::uint64_t high) {
  const char* text = std::getenv(name);
  if (text == nullptr || *text == '\0') return std::nullopt;
  const std::string_view value(text);
  std::uint64_t number = 0;
  const auto [end, error] = std::from_chars(value.data(), value.data() + value.size(), number);
  if (error != std::errc() || end != value.data() + value.size() || number < low || number > high) {
    throw std::invalid_argument(std::string(name) + "=" + std::string(value) +
                                ": expected a whole number from " + std::to_string(low) + " to " +
                                std::to_string(high));
  }
  return number;
}

std::filesystem::path defaultCacheDir() {
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg != nullptr && *xdg == '/') {
    return std::filesystem::path(xdg) / "parallax" / "http";
  }
  if (const char* home = std::getenv("HOME"); home != nullptr && *home != '\0') {
    return std::filesystem::path(home) / ".cache" / "parallax" / "http";
  }
  return {};
}

struct Network {
  std::mutex mutex;
  std::optional<NetworkSettings> settings;
  std::shared_ptr<HttpClient> client;
  std::shared_ptr<RangeCache> cache;
  bool cache_tried = false;

  const NetworkSettings& current() {
    if (!settings) settings = networkSettingsFromEnvironment();
    return *settings;
  }
};

Network& network() {
  static Network instance;
  return instance;
}

}  // namespace

NetworkSettings networkSettingsFromEnvironment() {
  NetworkSettings settings;
  if (auto seconds = environmentNumber("PARALLAX_HTTP_TIMEOUT", 1, 86400)) {
    settings.http.stall_timeout = std::chrono::seconds(*seconds);
    settings.http.connect_timeout =
        std::min(settings.http.connect_timeout, std::chrono::milliseconds(*seconds * 1000));
  }
  if (auto attempts = environmentNumber("PARALLAX_HTTP_RETRIES", 1, 100)) {
    settings.retry.max_attempts = int(*attempts);
  }
  if (auto megabytes = environmentNumber("PARALLAX_HTTP_CACHE_MB", 0, 1ull << 30)) {
    settings.cache_bytes = *megabytes << 20;
    settings.use_cache = *megabytes > 0;
  }
  if (const char* ca = std::getenv("PARALLAX_CA_FILE"); ca != nullptr && *ca != '\0') {
    settings.http.ca_file = ca;
  }
  return settings;
}

void configureNetwork(const NetworkSettings& settings) {
  Network& n = network();
  std::lock_guard lock(n.mutex);
  n.settings = settings;
  n.client.reset();
  n.cache.reset();
  n.cache_tried = false;
}

std::shared_ptr<HttpClient> networkClient() {
  Network& n = network();
  std::lock_guard lock(n.mutex);
  if (!n.client) n.client = std::make_shared<HttpClient>(n.current().http);
  return n.client;
}

std::shared_ptr<RangeCache> networkCache() {
  Network& n = network();
  std::lock_guard lock(n.mutex);
  if (!n.cache_tried) {
    n.cache_tried = true;
    const NetworkSettings& s = n.current();
    const std::filesystem::path dir = s.cache_dir.empty() ? defaultCacheDir() : s.cache_dir;
    if (s.use_cache && !dir.empty() && s.cache_bytes > 0) {
      try {
        n.cache = std::make_shared<RangeCache>(dir, s.cache_bytes);
      } catch (const std::exception&) {
        n.cache.reset();  // a read-only home, say: URLs still work, uncached
      }
    }
  }
  return n.cache;
}

HttpSourceOptions networkSourceOptions(std::uint64_t head_bytes) {
  Network& n = network();
  std::lock_guard lock(n.mutex);
  const NetworkSettings& s = n.current();
  HttpSourceOptions options;
  options.head_bytes = head_bytes;
  options.retry = s.retry;
  options.max_transfers = s.max_transfers_per_file;
  return options;
}

std::vector<std::unique_ptr<HttpByteSource>> openHttpSources(std::span<const HttpOpenSpec> specs) {
  return HttpByteSource::openAll(specs, networkClient(), networkCache());
}

void installHttpOpener() {
  const ByteSourceOpener opener = [](std::span<const ByteSourceRequest> requests) {
    std::vector<HttpOpenSpec> specs;
    for (const ByteSourceRequest& request : requests) {
      specs.push_back({request.location, networkSourceOptions(request.head_bytes)});
    }
    std::vector<std::unique_ptr<HttpByteSource>> opened = openHttpSources(specs);
    return std::vector<std::unique_ptr<ByteSource>>(std::make_move_iterator(opened.begin()),
                                                    std::make_move_iterator(opened.end()));
  };
  registerByteSourceOpener("http", opener);
  registerByteSourceOpener("https", opener);
}

}  // namespace parallax
