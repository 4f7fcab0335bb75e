// Opening an HttpByteSource (the probe) and the wording of HTTP failures.
#include <future>
#include <thread>

#include "core/url.h"
#include "net/http_byte_source.h"
#include "net/http_client.h"
#include "net/http_source_state.h"

namespace parallax {

std::string describeStatus(long status) {
  const char* reason = "";
  switch (status) {
    case 200:
      reason = "OK";
      break;
    case 206:
      reason = "Partial Content";
      break;
    case 304:
      reason = "Not Modified";
      break;
    case 400:
      reason = "Bad Request";
      break;
    case 401:
      reason = "Unauthorized";
      break;
    case 403:
      reason = "Forbidden";
      break;
    case 404:
      reason = "Not Found";
      break;
    case 405:
      reason = "Method Not Allowed";
      break;
    case 408:
      reason = "Request Timeout";
      break;
    case 410:
      reason = "Gone";
      break;
    case 412:
      reason = "Precondition Failed";
      break;
    case 416:
      reason = "Range Not Satisfiable";
      break;
    case 429:
      reason = "Too Many Requests";
      break;
    case 500:
      reason = "Internal Server Error";
      break;
    case 502:
      reason = "Bad Gateway";
      break;
    case 503:
      reason = "Service Unavailable";
      break;
    case 504:
      reason = "Gateway Timeout";
      break;
    default:
      break;
  }
  std::string text = "HTTP " + std::to_string(status);
  if (*reason) text += std::string(" ") + reason;
  return text;
}

std::string describeFailure(const HttpResponse& r) {
  if (r.cancelled) return "the request was cancelled";
  if (r.transport != TransportError::None) {
    return std::string(transportErrorName(r.transport)) + " (" + r.transport_message + ")";
  }
  if (r.ignored_range) {
    std::string found = "HTTP 200 with the whole file";
    if (r.content_length) found += " (" + std::to_string(*r.content_length) + " bytes)";
    return found + ": the server ignores Range requests";
  }
  return describeStatus(r.status);
}

std::string hintForFailure(const HttpResponse& r) {
  switch (r.transport) {
    case TransportError::Timeout:
      return "the server sent nothing, or under " + std::to_string(kStallBytesPerSecond) +
             " bytes a second, for the stall timeout; PARALLAX_HTTP_TIMEOUT=SECONDS allows longer";
    case TransportError::ConnectFailed:
      return "is the server up, and the host and port right?";
    case TransportError::Reset:
      return "the connection kept failing; try again later";
    case TransportError::Fatal:
      if (r.transport_message.find("certificate") != std::string::npos ||
          r.transport_message.find("SSL") != std::string::npos) {
        return "the server's TLS certificate does not verify; PARALLAX_CA_FILE=FILE names the "
               "CA bundle that signed it";
      }
      return {};
    case TransportError::None:
      break;
  }
  if (r.ignored_range) {
    return "serve the files from a server with HTTP range requests (nginx, Apache, object "
           "stores and CDNs have them)";
  }
  if (r.status == 401 || r.status == 403) {
    return "the server refuses access: check the URL, its signature or credentials";
  }
  if (r.status == 404 || r.status == 410) return "check the URL";
  if (r.status == 429) return "the server throttles requests; try again later";
  if (r.status >= 500) return "the server kept failing; try again later";
  return {};
}

std::string versionOf(const CacheValidator& v) {
  if (!v.etag.empty()) return v.etag;
  if (!v.last_modified.empty()) return "Last-Modified: " + v.last_modified;
  return {};
}

namespace {

// The probe: size, version and head of `spec.url`; retried like any request.
std::shared_ptr<HttpByteSource::State> probe(const HttpOpenSpec& spec, HttpClient& client,
                                             const std::shared_ptr<RangeCache>& cache) {
  auto state = std::make_shared<HttpByteSource::State>();
  state->client = &client;
  state->cache = cache;
  state->options = spec.options;
  state->url = spec.url;
  state->display_url = urlForMessages(spec.url);

  const std::optional<CacheValidator> cached = cache ? cache->validator(spec.url) : std::nullopt;
  const ByteRange head{0, std::max<std::uint64_t>(spec.options.head_bytes, 1)};
  // A 200 answer (the server ignores Range) is taken whole up to whole_file_bytes.
  HttpRequest request{.url = spec.url,
                      .range = head,
                      .max_body = std::max(head.size, spec.options.whole_file_bytes)};
  if (cached && cached->usable()) {
    if (!cached->etag.empty()) {
      request.if_none_match = cached->etag;
    } else {
      request.if_modified_since = cached->last_modified;
    }
  }
  const std::string expected = "the file (an HTTP 206 answer to a Range request)";
  HttpResponse r;
  for (int attempt = 1;; ++attempt) {
    r = client.fetch(request);
    ++state->stats.requests;
    state->stats.bytes_received += r.body.size();
    if (r.transport == TransportError::None && r.status == 206) {
      // A body shorter than its Content-Range: cut on the way, as a reset connection is.
      const std::optional<ContentRange> range = parseContentRange(r.content_range);
      if (range && range->range && range->range->size != r.body.size()) {
        r.transport = TransportError::Reset;
        r.transport_message =
            "a body of " + std::to_string(r.body.size()) + " bytes for " + r.content_range;
      }
    }
    if (r.transport == TransportError::None && r.status < 500) break;
    const RetryDecision decision = spec.options.retry.decide(r.transport, r.status, attempt);
    if (decision != RetryDecision::Retry) {
      std::string found = describeFailure(r);
      if (attempt > 1) found += " (" + std::to_string(attempt) + " attempts)";
      throw InputError(state->errorAt(head, expected, found, hintForFailure(r)));
    }
    ++state->stats.retries;
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::this_thread::sleep_for(
        spec.options.retry.delay(attempt, unit(state->jitter), parseRetryAfter(r.retry_after)));
  }

  CacheValidator now{.etag = r.etag, .last_modified = r.last_modified};
  bool fresh_head = false;
  bool whole = false;
  if (r.status == 304 && cached && cached->usable()) {
    now = *cached;
    state->stats.validated_by_cache = true;
  } else if (r.status == 206) {
    const std::optional<ContentRange> range = parseContentRange(r.content_range);
    if (!range || !range->range || !range->total || range->range->offset != 0 ||
        range->range->size != r.body.size()) {
      throw InputError(state->errorAt(head, expected + " with its Content-Range",
                                      "Content-Range " + quoteInput(r.content_range, 60) + " and " +
                                          std::to_string(r.body.size()) + " bytes"));
    }
    now.size = *range->total;
    fresh_head = true;
  } else if (r.status == 200 && !r.ignored_range) {
    // The whole file, at most whole_file_bytes: a server without range requests, or a file no
    // larger than the head asked for. Kept whole below, so that no read asks for a range.
    now.size = r.body.size();
    fresh_head = true;
    whole = true;
  } else if (r.status == 416) {
    const std::optional<ContentRange> range = parseContentRange(r.content_range);
    if (!range || !range->total || *range->total != 0) {
      throw InputError(state->errorAt(
          head, expected,
          describeStatus(416) + " with Content-Range " + quoteInput(r.content_range, 60)));
    }
    now.size = 0;  // an empty file
  } else {
    std::string hint = hintForFailure(r);
    if (r.ignored_range) {
      hint += "; from a server without them only files of at most " +
              std::to_string(spec.options.whole_file_bytes >> 20) + " MiB are read (whole)";
    }
    throw InputError(state->errorAt(head, expected, describeFailure(r), hint));
  }
  state->size = now.size;
  state->validator = now;
  state->version = versionOf(now);
  if (fresh_head && (spec.options.head_bytes > 0 || whole)) state->head = std::move(r.body);
  if (cache) {
    cache->validate(spec.url, now);  // keeps the ranges of the same version, drops others
    if (!state->head.empty()) cache->store(spec.url, 0, state->head);
  }
  return state;
}

}  // namespace

std::unique_ptr<HttpByteSource> HttpByteSource::open(const std::string& url,
                                                     std::shared_ptr<HttpClient> client,
                                                     std::shared_ptr<RangeCache> cache,
                                                     const HttpSourceOptions& options) {
  const HttpOpenSpec spec{url, options};
  auto sources = openAll(std::span(&spec, 1), std::move(client), std::move(cache));
  return std::move(sources.front());
}

std::vector<std::unique_ptr<HttpByteSource>> HttpByteSource::openAll(
    std::span<const HttpOpenSpec> specs, std::shared_ptr<HttpClient> client,
    std::shared_ptr<RangeCache> cache) {
  std::vector<std::future<std::shared_ptr<State>>> probes;
  // The first runs on this thread (below), the others beside it.
  for (std::size_t i = 1; i < specs.size(); ++i) {
    probes.push_back(std::async(std::launch::async, [&spec = specs[i], &client, &cache] {
      return probe(spec, *client, cache);
    }));
  }
  std::vector<std::unique_ptr<HttpByteSource>> sources;
  std::exception_ptr first_error;
  for (std::size_t i = 0; i < specs.size(); ++i) {
    try {
      std::shared_ptr<State> state = i == 0 ? probe(specs[0], *client, cache) : probes[i - 1].get();
      sources.push_back(std::unique_ptr<HttpByteSource>(new HttpByteSource(client, state)));
    } catch (...) {
      if (!first_error) first_error = std::current_exception();
    }
  }
  if (first_error) std::rethrow_exception(first_error);
  return sources;
}

}  // namespace parallax
