// Where a path or a URL becomes a ByteSource. A local path is a file (openFileSource); a URL
// ("scheme://...") goes to the opener registered for its scheme. Core knows no network: the
// net module registers http and https (net/http_opener.cpp, compiled into every program that
// links parallax::net), so a reader, the octree code and the format table open a URL exactly as
// they open a file, and a program that does not link net reports the scheme as unknown.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/byte_source.h"

namespace parallax {

// One source to open: the path or URL, and how many of its first bytes are wanted at once
// (a source with latency fetches them with the opening request; 0: none in particular).
struct ByteSourceRequest {
  std::string location;
  std::uint64_t head_bytes = 0;
};

// Opens every request (all of one scheme) at once (an HTTP opener probes them in parallel),
// the sources in the order asked. Throws InputError naming the URL that failed.
using ByteSourceOpener =
    std::function<std::vector<std::unique_ptr<ByteSource>>(std::span<const ByteSourceRequest>)>;

// Installs `opener` for `scheme` (lower case, without "://"), replacing an earlier one.
// Thread-safe; meant for static initialisation.
void registerByteSourceOpener(std::string scheme, ByteSourceOpener opener);

// The scheme of "scheme://..." in lower case (letters, digits, '+', '-', '.' after a letter);
// empty for anything else (a local path, "C:\\..." included).
std::string urlScheme(std::string_view location);

// True where `location` is a URL ("scheme://...") rather than a local path.
inline bool isUrl(std::string_view location) {
  return !urlScheme(location).empty();
}

// A local path (openFileSource) or a URL through its scheme's opener. Throws InputError for a
// scheme nobody registered (naming it and the schemes that are), and as the opener does.
std::unique_ptr<ByteSource> openByteSource(const std::string& path_or_url,
                                           std::uint64_t head_bytes = 0);

// Several at once (the files of a Potree directory); requests of one scheme go to its opener
// together. Sources come back in the order asked.
std::vector<std::unique_ptr<ByteSource>> openByteSources(
    std::span<const ByteSourceRequest> requests);

}  // namespace parallax
