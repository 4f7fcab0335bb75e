// A file on an HTTP(S) server as a ByteSource: byte ranges fetched with `Range` requests through
// a shared HttpClient, merged when adjacent, retried, cached on disk and checked for a change of
// version.
//
// Opening sends one request (the probe, `Range: bytes=0-(head-1)`), which gives the size
// (Content-Range), the version (ETag, else Last-Modified) and the first `head_bytes` of the file,
// kept in memory (metadata.json whole, hierarchy.bin's first chunk). A 200 answer with the whole
// file (a server without range requests) is kept whole when it is at most `whole_file_bytes`. With a range cache that
// holds the URL, the probe is conditional (If-None-Match / If-Modified-Since): a 304 keeps the
// cached ranges, anything else drops them.
//
// Reads (any thread):
// 1. the head, then the range cache (disk), then the network;
// 2. a range being fetched for a prefetch() is waited for, not fetched again;
// 3. at most `max_transfers` requests of this source are in flight; the most urgent wanted range
//    (a waiting read first, in order of arrival, then the prefetch hint in its order) starts the
//    next request, merged with adjacent wanted ranges (net/range_merge.h);
// 4. failures retry by the policy (net/retry_policy.h) with backoff, per range;
// 5. a read whose ReadContext::cancel is requested throws ReadCancelled; a request none of
//    whose ranges is wanted any more (no read waits, no hint names them) is cancelled.
//
// Errors are InputErrors naming the URL, the range's offset and the reader's element: HTTP 4xx
// (never retried), 5xx and transport failures after the last attempt, a 200 answer with the
// whole file to a later range request, or to the probe for a file over `whole_file_bytes` (the
// server ignores Range: fetching whole files would be the wrong client for octrees of hundreds
// of GB), a short body, and an answer of another version (ETag or
// Last-Modified or size not those of the probe). A change of version fails that read and every
// later one: the source never returns bytes of two versions of the file.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "core/byte_source.h"
#include "net/http_client.h"
#include "net/range_cache.h"
#include "net/range_merge.h"
#include "net/retry_policy.h"

namespace parallax {

struct HttpSourceOptions {
  // Bytes the probe fetches and the source keeps in memory (0: a 1-byte probe, nothing kept).
  std::uint64_t head_bytes = 0;
  // A server without range requests (Python's http.server, some CDNs' origins) answers the probe
  // with 200 and the whole file: a file of at most this many bytes is then kept whole and every
  // read is served from memory; a larger one fails the probe at its headers, before its body.
  std::uint64_t whole_file_bytes = 64ull << 20;
  MergeLimits merge;
  int max_transfers = 8;  // requests of this source in flight at once
  // Fetched ranges that no read or hint wants any more are kept up to this many bytes: a hint
  // reorders as the view's hierarchy unfolds, and a range dropped from it is often read soon.
  std::uint64_t spare_bytes = 64ull << 20;
  RetryPolicy retry;
};

// Counters of one source, since it was opened (its probe included).
struct HttpSourceStats {
  std::uint64_t requests = 0;         // sent, retries included
  std::uint64_t merged_requests = 0;  // of those, ones that fetched more than one wanted range
  std::uint64_t bytes_received = 0;   // body bytes of range answers
  std::uint64_t cache_hits = 0, cache_bytes = 0;
  std::uint64_t head_hits = 0;  // reads served by the head
  std::uint64_t retries = 0;
  std::uint64_t cancelled_requests = 0;
  std::uint64_t failed_reads = 0;
  bool validated_by_cache = false;  // the probe was answered 304: the cached ranges are current
};

struct HttpOpenSpec {
  std::string url;
  HttpSourceOptions options;
};

class HttpByteSource final : public ByteSource {
 public:
  // Opens `url` (sends the probe and waits for it; retried like any request). `cache` may be
  // null (nothing on disk). Throws InputError naming the URL for an answer that is not the file.
  static std::unique_ptr<HttpByteSource> open(const std::string& url,
                                              std::shared_ptr<HttpClient> client,
                                              std::shared_ptr<RangeCache> cache,
                                              const HttpSourceOptions& options = {});
  // Several files at once, their probes in parallel (one round trip for the three files of a
  // Potree directory). Throws the first file's error, in the order given.
  static std::vector<std::unique_ptr<HttpByteSource>> openAll(std::span<const HttpOpenSpec> specs,
                                                              std::shared_ptr<HttpClient> client,
                                                              std::shared_ptr<RangeCache> cache);

  // Cancels the requests in flight and waits for their callbacks.
  ~HttpByteSource() override;
  HttpByteSource(const HttpByteSource&) = delete;
  HttpByteSource& operator=(const HttpByteSource&) = delete;

  const std::string& name() const override;
  std::uint64_t size() const override;
  const std::string& version() const override;
  bool local() const override { return false; }
  void read(std::uint64_t offset, std::span<std::byte> out,
            const ReadContext& context = {}) const override;
  void prefetch(std::span<const ByteRange> ranges) const override;

  // The URL as given (name() is the form for messages, without credentials).
  const std::string& url() const;
  // The first bytes, as the probe fetched them (may be shorter than asked: a shorter file; empty
  // when the probe was answered 304).
  std::span<const std::byte> head() const;
  HttpSourceStats stats() const;

  struct State;  // net/http_byte_source.cpp

 private:
  HttpByteSource(std::shared_ptr<HttpClient> client, std::shared_ptr<State> state);
  std::shared_ptr<HttpClient> client_;
  std::shared_ptr<State> state_;
};

}  // namespace parallax
