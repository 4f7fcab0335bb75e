// libFuzzer target for what the network layer parses from servers and users: Content-Range and
// Retry-After headers (net/http_client.h, net/retry_policy.h) and URLs (net/url.h,
// lod/octree_url.h). Any input must parse or be refused, never crash or read out of bounds; a
// parsed Content-Range must describe a range inside its total.
//
// Seeds: fuzz/corpus/http_response/ (header values and URLs, one per file).
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "core/url.h"
#include "lod/octree_url.h"
#include "net/http_client.h"
#include "net/retry_policy.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  if (const auto range = parallax::parseContentRange(text)) {
    if (range->range && range->total && range->range->end() > *range->total) std::abort();
    if (!range->range && !range->total) std::abort();
  }
  (void)parallax::parseRetryAfter(text);
  if (parallax::isHttpUrl(text)) {
    const parallax::UrlParts parts = parallax::splitUrl(text);
    if (parts.base.size() + parts.query.size() > text.size()) std::abort();
    (void)parallax::urlFileName(text);
    if (parallax::urlForMessages(text).size() > text.size()) std::abort();
    (void)parallax::octreeUrlKind(text);
  }
  return 0;
}
