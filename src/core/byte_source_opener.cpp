#include "core/byte_source_opener.h"

#include <cctype>
#include <map>
#include <mutex>

#include "core/error.h"
#include "core/url.h"

namespace parallax {
namespace {

struct Registry {
  std::mutex mutex;
  std::map<std::string, ByteSourceOpener> openers;
};

// Built on first use: registrations run from other translation units' static initialisers,
// in an order nobody chooses.
Registry& registry() {
  static Registry r;
  return r;
}

ByteSourceOpener openerFor(const std::string& scheme, const std::string& location) {
  Registry& r = registry();
  const std::lock_guard lock(r.mutex);
  if (const auto it = r.openers.find(scheme); it != r.openers.end()) return it->second;
  std::string known;
  for (const auto& [name, opener] : r.openers) known += (known.empty() ? "" : ", ") + name;
  throw InputError({.file = urlForMessages(location),
                    .expected = "a local path or a URL of a scheme this program reads" +
                                (known.empty() ? std::string(" (none: built without the network)")
                                               : " (" + known + ")"),
                    .found = "the scheme '" + scheme + "'"});
}

}  // namespace

void registerByteSourceOpener(std::string scheme, ByteSourceOpener opener) {
  Registry& r = registry();
  const std::lock_guard lock(r.mutex);
  r.openers[std::move(scheme)] = std::move(opener);
}

std::string urlScheme(std::string_view location) {
  const std::size_t colon = location.find("://");
  if (colon == std::string_view::npos || colon == 0) return {};
  if (!std::isalpha(static_cast<unsigned char>(location[0]))) return {};
  std::string scheme;
  for (const char c : location.substr(0, colon)) {
    const auto u = static_cast<unsigned char>(c);
    if (!std::isalnum(u) && c != '+' && c != '-' && c != '.') return {};
    scheme += char(std::tolower(u));
  }
  return scheme;
}

std::unique_ptr<ByteSource> openByteSource(const std::string& path_or_url,
                                           std::uint64_t head_bytes) {
  const std::string scheme = urlScheme(path_or_url);
  if (scheme.empty()) return openFileSource(path_or_url);
  const ByteSourceRequest request{path_or_url, head_bytes};
  std::vector<std::unique_ptr<ByteSource>> opened =
      openerFor(scheme, path_or_url)(std::span(&request, 1));
  return std::move(opened.at(0));
}

std::vector<std::unique_ptr<ByteSource>> openByteSources(
    std::span<const ByteSourceRequest> requests) {
  std::vector<std::unique_ptr<ByteSource>> sources(requests.size());
  // Requests of one scheme together, each group in one call of its opener.
  std::map<std::string, std::vector<std::size_t>> groups;
  for (std::size_t i = 0; i < requests.size(); ++i) {
    const std::string scheme = urlScheme(requests[i].location);
    if (scheme.empty()) {
      sources[i] = openFileSource(requests[i].location);
    } else {
      groups[scheme].push_back(i);
    }
  }
  for (const auto& [scheme, indices] : groups) {
    std::vector<ByteSourceRequest> group;
    for (const std::size_t i : indices) group.push_back(requests[i]);
    std::vector<std::unique_ptr<ByteSource>> opened =
        openerFor(scheme, group.front().location)(group);
    for (std::size_t k = 0; k < indices.size(); ++k) sources[indices[k]] = std::move(opened.at(k));
  }
  return sources;
}

}  // namespace parallax
