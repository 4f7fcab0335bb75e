#include "net/http_client.h"

#include <curl/curl.h>

#include <algorithm>
#include <cassert>
#include <charconv>
#include <condition_variable>
#include <cstring>
#include <deque>
#include <mutex>
#include <queue>
#include <stdexcept>
#include <thread>
#include <unordered_map>

#include "net/network_counters.h"

namespace parallax {
namespace {

constexpr std::uint64_t kDefaultMaxBody = 64ull << 20;

// curl_global_init once per process, before the first handle (it is not thread-safe itself on
// older libcurls, and the multi handle of a second client may be made on another thread).
void initCurlOnce() {
  static const CURLcode code = curl_global_init(CURL_GLOBAL_DEFAULT);
  if (code != CURLE_OK) {
    throw std::runtime_error(std::string("libcurl could not start: ") + curl_easy_strerror(code));
  }
}

TransportError classify(CURLcode code) {
  switch (code) {
    case CURLE_OK:
      return TransportError::None;
    case CURLE_COULDNT_CONNECT:
      return TransportError::ConnectFailed;
    case CURLE_OPERATION_TIMEDOUT:
      return TransportError::Timeout;
    case CURLE_PARTIAL_FILE:
    case CURLE_RECV_ERROR:
    case CURLE_SEND_ERROR:
    case CURLE_GOT_NOTHING:
    case CURLE_HTTP2:
    case CURLE_HTTP2_STREAM:
    case CURLE_SSL_CONNECT_ERROR:  // also a connection reset during the handshake
      return TransportError::Reset;
    default:
      return TransportError::Fatal;
  }
}

std::string_view trim(std::string_view text) {
  while (!text.empty() && (text.front() == ' ' || text.front() == '\t')) text.remove_prefix(1);
  while (!text.empty() && (text.back() == ' ' || text.back() == '\t' || text.back() == '\r' ||
                           text.back() == '\n')) {
    text.remove_suffix(1);
  }
  return text;
}

bool equalsNoCase(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (std::tolower(static_cast<unsigned char>(a[i])) !=
        std::tolower(static_cast<unsigned char>(b[i]))) {
      return false;
    }
  }
  return true;
}

std::optional<std::uint64_t> parseNumber(std::string_view text) {
  std::uint64_t value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size() || text.empty()) return std::nullopt;
  return value;
}

}  // namespace

std::optional<ContentRange> parseContentRange(std::string_view value) {
  value = trim(value);
  if (value.size() < 6 || !equalsNoCase(value.substr(0, 6), "bytes ")) return std::nullopt;
  value = trim(value.substr(6));
  const std::size_t slash = value.find('/');
  if (slash == std::string_view::npos) return std::nullopt;
  ContentRange out;
  const std::string_view total = value.substr(slash + 1);
  if (total != "*") {
    out.total = parseNumber(total);
    if (!out.total) return std::nullopt;
  }
  const std::string_view span = value.substr(0, slash);
  if (span == "*") return out.total ? std::optional(out) : std::nullopt;
  const std::size_t dash = span.find('-');
  if (dash == std::string_view::npos) return std::nullopt;
  const auto first = parseNumber(span.substr(0, dash));
  const auto last = parseNumber(span.substr(dash + 1));
  if (!first || !last || *last < *first || *last == UINT64_MAX) return std::nullopt;
  if (out.total && *last >= *out.total) return std::nullopt;
  out.range = ByteRange{*first, *last - *first + 1};
  return out;
}

// ---------------------------------------------------------------------------------------------

struct HttpClient::State {
  struct Transfer {
    std::uint64_t id = 0;
    HttpRequest request;
    Callback callback;
    CURL* easy = nullptr;
    curl_slist* headers = nullptr;
    HttpResponse response;
    long header_status = 0;  // of the answer whose headers are being read
    char error[CURL_ERROR_SIZE] = {};
  };
  struct Timer {
    std::chrono::steady_clock::time_point at;
    std::uint64_t serial;
    std::function<void()> task;
    bool operator>(const Timer& other) const {
      return at != other.at ? at > other.at : serial > other.serial;
    }
  };

  const HttpOptions options;
  CURLM* multi = nullptr;

  std::mutex mutex;  // guards the members up to `stop`
  std::deque<std::unique_ptr<Transfer>> incoming;
  std::vector<std::uint64_t> cancels;
  std::priority_queue<Timer, std::vector<Timer>, std::greater<>> timers;
  std::uint64_t next_id = 1, timer_serial = 0;
  bool stop = false;
  HttpClientStats stats;

  // Network thread only.
  std::unordered_map<std::uint64_t, std::unique_ptr<Transfer>> active;
  std::thread thread;

  explicit State(HttpOptions o) : options(std::move(o)) {
    initCurlOnce();
    multi = curl_multi_init();
    if (!multi) throw std::runtime_error("libcurl: curl_multi_init failed");
    curl_multi_setopt(multi, CURLMOPT_PIPELINING, long(CURLPIPE_MULTIPLEX));
    curl_multi_setopt(multi, CURLMOPT_MAX_HOST_CONNECTIONS, options.max_host_connections);
    thread = std::thread([this] { loop(); });
  }

  ~State() {
    {
      std::lock_guard lock(mutex);
      stop = true;
    }
    curl_multi_wakeup(multi);
    thread.join();
    curl_multi_cleanup(multi);
  }

  static std::size_t onHeader(char* data, std::size_t size, std::size_t count, void* user) {
    auto* t = static_cast<Transfer*>(user);
    const std::size_t bytes = size * count;
    const std::string_view line(data, bytes);
    HttpResponse& r = t->response;
    if (line.starts_with("HTTP/")) {
      // A new answer (after a redirect or a 100 Continue): forget the previous one's headers.
      r.etag.clear(), r.last_modified.clear(), r.content_range.clear(), r.retry_after.clear();
      r.content_length.reset();
      const std::size_t space = line.find(' ');
      r.http_version = std::string(trim(line.substr(0, space)));
      t->header_status = 0;
      if (space != std::string_view::npos) {
        const std::string_view rest = line.substr(space + 1);
        t->header_status = long(parseNumber(trim(rest.substr(0, rest.find(' ')))).value_or(0));
      }
      return bytes;
    }
    if (trim(line).empty()) {
      // End of this answer's headers. A 200 to a range request that is larger than the range
      // is the whole file (the server ignores Range): stop before its body.
      if (t->request.range && t->header_status == 200) {
        const std::uint64_t limit = t->request.max_body;
        if (!r.content_length || *r.content_length > limit) {
          r.ignored_range = true;
          return 0;  // aborts the transfer
        }
      }
      // The body's room at once (a range of several MB would otherwise grow in steps).
      if (r.content_length && *r.content_length <= t->request.max_body) {
        r.body.reserve(std::size_t(*r.content_length));
      }
      return bytes;
    }
    const std::size_t colon = line.find(':');
    if (colon == std::string_view::npos) return bytes;
    const std::string_view name = trim(line.substr(0, colon));
    const std::string_view value = trim(line.substr(colon + 1));
    if (equalsNoCase(name, "etag"))
      r.etag = std::string(value);
    else if (equalsNoCase(name, "last-modified"))
      r.last_modified = std::string(value);
    else if (equalsNoCase(name, "content-range"))
      r.content_range = std::string(value);
    else if (equalsNoCase(name, "retry-after"))
      r.retry_after = std::string(value);
    else if (equalsNoCase(name, "content-length"))
      r.content_length = parseNumber(value);
    return bytes;
  }

  static std::size_t onBody(char* data, std::size_t size, std::size_t count, void* user) {
    auto* t = static_cast<Transfer*>(user);
    const std::size_t bytes = size * count;
    std::vector<std::byte>& body = t->response.body;
    if (body.size() + bytes > t->request.max_body) {
      t->response.body_too_large = true;
      return 0;  // aborts
    }
    const auto* begin = reinterpret_cast<const std::byte*>(data);
    body.insert(body.end(), begin, begin + bytes);
    return bytes;
  }

  void start(std::unique_ptr<Transfer> t) {
    CURL* easy = curl_easy_init();
    if (!easy) {
      t->response.transport = TransportError::Fatal;
      t->response.transport_message = "curl_easy_init failed";
      finish(std::move(t));
      return;
    }
    t->easy = easy;
    HttpRequest& q = t->request;
    if (q.max_body == 0) q.max_body = q.range ? q.range->size : kDefaultMaxBody;
    curl_easy_setopt(easy, CURLOPT_URL, q.url.c_str());
    curl_easy_setopt(easy, CURLOPT_PRIVATE, t.get());
    curl_easy_setopt(easy, CURLOPT_NOSIGNAL, 1L);
    curl_easy_setopt(easy, CURLOPT_ERRORBUFFER, t->error);
    curl_easy_setopt(easy, CURLOPT_HEADERFUNCTION, &State::onHeader);
    curl_easy_setopt(easy, CURLOPT_HEADERDATA, t.get());
    curl_easy_setopt(easy, CURLOPT_WRITEFUNCTION, &State::onBody);
    curl_easy_setopt(easy, CURLOPT_WRITEDATA, t.get());
    curl_easy_setopt(easy, CURLOPT_FOLLOWLOCATION, 1L);
    curl_easy_setopt(easy, CURLOPT_MAXREDIRS, 10L);
    curl_easy_setopt(easy, CURLOPT_PROTOCOLS_STR, "http,https");
    curl_easy_setopt(easy, CURLOPT_REDIR_PROTOCOLS_STR, "http,https");
    curl_easy_setopt(easy, CURLOPT_HTTP_VERSION, long(CURL_HTTP_VERSION_2TLS));
    curl_easy_setopt(easy, CURLOPT_PIPEWAIT, 1L);
    curl_easy_setopt(easy, CURLOPT_TCP_KEEPALIVE, 1L);
    curl_easy_setopt(easy, CURLOPT_BUFFERSIZE, 256L * 1024);
    curl_easy_setopt(easy, CURLOPT_USERAGENT, options.user_agent.c_str());
    curl_easy_setopt(easy, CURLOPT_CONNECTTIMEOUT_MS, long(options.connect_timeout.count()));
    // A stall: under kStallBytesPerSecond for the stall time, the transfer fails.
    curl_easy_setopt(easy, CURLOPT_LOW_SPEED_LIMIT, kStallBytesPerSecond);
    curl_easy_setopt(easy, CURLOPT_LOW_SPEED_TIME,
                     std::max(1L, long((options.stall_timeout.count() + 999) / 1000)));
    curl_easy_setopt(easy, CURLOPT_SSL_VERIFYPEER, options.verify_tls ? 1L : 0L);
    curl_easy_setopt(easy, CURLOPT_SSL_VERIFYHOST, options.verify_tls ? 2L : 0L);
    if (!options.ca_file.empty()) curl_easy_setopt(easy, CURLOPT_CAINFO, options.ca_file.c_str());
    if (q.range) {
      const std::string range = std::to_string(q.range->offset) + "-" +
                                std::to_string(q.range->offset + q.range->size - 1);
      curl_easy_setopt(easy, CURLOPT_RANGE, range.c_str());  // copied by libcurl
    }
    if (!q.if_none_match.empty()) {
      t->headers = curl_slist_append(t->headers, ("If-None-Match: " + q.if_none_match).c_str());
    }
    if (!q.if_modified_since.empty()) {
      t->headers =
          curl_slist_append(t->headers, ("If-Modified-Since: " + q.if_modified_since).c_str());
    }
    if (t->headers) curl_easy_setopt(easy, CURLOPT_HTTPHEADER, t->headers);
    const CURLMcode added = curl_multi_add_handle(multi, easy);
    if (added != CURLM_OK) {
      t->response.transport = TransportError::Fatal;
      t->response.transport_message = curl_multi_strerror(added);
      finish(std::move(t));
      return;
    }
    const std::uint64_t id = t->id;
    active[id] = std::move(t);
  }

  // Calls back and frees the transfer (network thread).
  void finish(std::unique_ptr<Transfer> t) {
    if (t->easy) {
      curl_multi_remove_handle(multi, t->easy);
      curl_easy_cleanup(t->easy);
      t->easy = nullptr;
    }
    curl_slist_free_all(t->headers);
    t->headers = nullptr;
    {
      std::lock_guard lock(mutex);
      ++stats.completed;
      --stats.in_flight;
      stats.bytes_received += t->response.body.size();
      if (t->response.cancelled) ++stats.cancelled;
      if (t->response.transport != TransportError::None) ++stats.transport_errors;
    }
    networkCounters().bytes_received += t->response.body.size();
    if (t->response.cancelled) ++networkCounters().cancelled;
    --networkCounters().requests_in_flight;
    Callback callback = std::move(t->callback);
    HttpResponse response = std::move(t->response);
    t.reset();
    callback(std::move(response));
  }

  void complete(CURL* easy, CURLcode code) {
    Transfer* raw = nullptr;
    curl_easy_getinfo(easy, CURLINFO_PRIVATE, &raw);
    const auto it = active.find(raw->id);
    assert(it != active.end() && "HttpClient: a finished transfer that is not active");
    std::unique_ptr<Transfer> t = std::move(it->second);
    active.erase(it);
    HttpResponse& r = t->response;
    curl_easy_getinfo(easy, CURLINFO_RESPONSE_CODE, &r.status);
    if (r.ignored_range || r.body_too_large) {
      // Our own abort: an HTTP answer did arrive; the caller judges it.
      r.transport = TransportError::None;
      if (r.ignored_range) r.body.clear();
    } else if (code != CURLE_OK) {
      r.transport = classify(code);
      r.transport_message = t->error[0] ? std::string(t->error) : curl_easy_strerror(code);
    }
    finish(std::move(t));
  }

  void loop() {
    while (true) {
      std::deque<std::unique_ptr<Transfer>> starting;
      std::vector<std::uint64_t> cancelling;
      std::vector<std::function<void()>> due;
      bool stopping = false;
      auto now = std::chrono::steady_clock::now();
      {
        std::lock_guard lock(mutex);
        starting.swap(incoming);
        cancelling.swap(cancels);
        while (!timers.empty() && timers.top().at <= now) {
          due.push_back(std::move(const_cast<Timer&>(timers.top()).task));
          timers.pop();
        }
        stopping = stop;
      }
      if (stopping) {
        // Every transfer ends with a callback, also the ones never started.
        for (auto& t : starting) {
          t->response.cancelled = true;
          finish(std::move(t));
        }
        while (!active.empty()) {
          auto t = std::move(active.begin()->second);
          active.erase(active.begin());
          t->response.cancelled = true;
          finish(std::move(t));
        }
        return;
      }
      for (auto& t : starting) {
        if (t->response.cancelled) {
          finish(std::move(t));  // cancelled before it started
        } else {
          start(std::move(t));
        }
      }
      for (std::uint64_t id : cancelling) {
        const auto it = active.find(id);
        if (it == active.end()) continue;  // finished already
        auto t = std::move(it->second);
        active.erase(it);
        t->response.cancelled = true;
        finish(std::move(t));
      }
      for (auto& task : due) task();

      int running = 0;
      curl_multi_perform(multi, &running);
      int left = 0;
      while (CURLMsg* message = curl_multi_info_read(multi, &left)) {
        if (message->msg == CURLMSG_DONE) complete(message->easy_handle, message->data.result);
      }

      long curl_timeout = -1;
      curl_multi_timeout(multi, &curl_timeout);
      long wait_ms = curl_timeout < 0 ? 1000 : std::min(curl_timeout, 1000L);
      {
        std::lock_guard lock(mutex);
        if (!incoming.empty() || !cancels.empty() || stop) wait_ms = 0;
        if (!timers.empty()) {
          now = std::chrono::steady_clock::now();
          const auto until =
              std::chrono::duration_cast<std::chrono::milliseconds>(timers.top().at - now).count();
          wait_ms = std::min(wait_ms, long(std::max<std::int64_t>(until, 0)));
        }
      }
      if (wait_ms > 0) curl_multi_poll(multi, nullptr, 0, int(wait_ms), nullptr);
    }
  }
};

HttpClient::HttpClient(HttpOptions options)
    : options_(options), state_(std::make_unique<State>(std::move(options))) {}

HttpClient::~HttpClient() = default;

std::uint64_t HttpClient::submit(HttpRequest request, Callback callback) {
  auto t = std::make_unique<State::Transfer>();
  t->request = std::move(request);
  t->callback = std::move(callback);
  std::uint64_t id = 0;
  {
    std::lock_guard lock(state_->mutex);
    id = t->id = state_->next_id++;
    ++state_->stats.requests;
    ++state_->stats.in_flight;
    state_->incoming.push_back(std::move(t));
  }
  ++networkCounters().requests;
  ++networkCounters().requests_in_flight;
  curl_multi_wakeup(state_->multi);
  return id;
}

void HttpClient::cancel(std::uint64_t id) {
  {
    std::lock_guard lock(state_->mutex);
    // Not started yet: it goes back unstarted, called back by the loop as cancelled.
    for (auto& t : state_->incoming) {
      if (t->id == id) {
        t->response.cancelled = true;
        break;
      }
    }
    state_->cancels.push_back(id);
  }
  curl_multi_wakeup(state_->multi);
}

void HttpClient::after(std::chrono::milliseconds delay, std::function<void()> task) {
  {
    std::lock_guard lock(state_->mutex);
    state_->timers.push(
        {std::chrono::steady_clock::now() + delay, ++state_->timer_serial, std::move(task)});
  }
  curl_multi_wakeup(state_->multi);
}

HttpResponse HttpClient::fetch(HttpRequest request, std::stop_token cancel_token) {
  struct Shared {
    std::mutex mutex;
    std::condition_variable_any done_cv;
    std::optional<HttpResponse> response;
  };
  auto shared = std::make_shared<Shared>();
  const std::uint64_t id = submit(std::move(request), [shared](HttpResponse&& response) {
    {
      std::lock_guard lock(shared->mutex);
      shared->response = std::move(response);
    }
    shared->done_cv.notify_all();
  });
  std::unique_lock lock(shared->mutex);
  if (!shared->done_cv.wait(lock, cancel_token, [&] { return shared->response.has_value(); })) {
    lock.unlock();
    cancel(id);
    lock.lock();
    shared->done_cv.wait(lock, [&] { return shared->response.has_value(); });
  }
  return std::move(*shared->response);
}

HttpClientStats HttpClient::stats() const {
  std::lock_guard lock(state_->mutex);
  return state_->stats;
}

}  // namespace parallax
