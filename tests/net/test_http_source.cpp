// The HTTP byte source against a real nginx on loopback, directly and through the fault proxy:
// exact bytes, adjacent prefetches in one request, retries on 5xx, resets and short bodies and
// never on 4xx, a server that ignores Range, a file that changes while read, a stalled server,
// cancellation, the on-disk cache across opens (with an ETag, with only a date, with neither),
// Retry-After, TLS verification, redirects and proxies from the environment.
#include "net/http_byte_source.h"

#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <thread>

#include "core/error.h"
#include "loopback_servers.h"
#include "support/temp_dir.h"

namespace parallax {
namespace {

using namespace std::chrono_literals;
using test::FaultProxy;
using test::Nginx;

constexpr std::size_t kFileSize = 1 << 20;

std::vector<std::byte> pattern(std::size_t size, std::uint32_t seed) {
  std::vector<std::byte> bytes(size);
  std::uint32_t state = seed;
  for (auto& b : bytes) {
    state = state * 1664525u + 1013904223u;
    b = std::byte(state >> 24);
  }
  return bytes;
}

void writeBytes(const std::filesystem::path& path, const std::vector<std::byte>& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
}

// nginx serving data.bin (1 MiB of known bytes) from a folder of the test's own.
struct Served {
  test::TempDir dir;
  std::vector<std::byte> bytes = pattern(kFileSize, 7);
  std::unique_ptr<Nginx> nginx;
  explicit Served(std::string server_config = {}) {
    std::filesystem::create_directories(dir / "www");
    writeBytes(dir / "www" / "data.bin", bytes);
    nginx = std::make_unique<Nginx>(
        dir / "nginx", Nginx::Options{.root = dir / "www", .server_config = server_config});
  }
  std::unique_ptr<FaultProxy> proxy(const std::vector<std::string>& args) {
    return std::make_unique<FaultProxy>(dir / "proxy", nginx->port(), args);
  }
};

HttpSourceOptions fastRetries(int attempts = 4) {
  HttpSourceOptions options;
  options.retry.max_attempts = attempts;
  options.retry.base_delay = 10ms;
  options.retry.max_delay = 50ms;
  return options;
}

std::vector<std::byte> readRange(const ByteSource& source, std::uint64_t offset, std::size_t size,
                                 std::string_view element = "test range") {
  std::vector<std::byte> out(size);
  source.read(offset, out, {.element = element});
  return out;
}

std::vector<std::byte> slice(const std::vector<std::byte>& bytes, std::size_t offset,
                             std::size_t size) {
  return {bytes.begin() + std::ptrdiff_t(offset), bytes.begin() + std::ptrdiff_t(offset + size)};
}

std::string errorOf(const std::function<void()>& action) {
  try {
    action();
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

void expectContains(const std::string& text, std::initializer_list<const char*> parts) {
  for (const char* part : parts) EXPECT_NE(text.find(part), std::string::npos) << text;
}

// Polls `condition` for up to 10 s (events of other threads; no timing is asserted).
bool eventually(const std::function<bool()>& condition) {
  for (int i = 0; i < 1000; ++i) {
    if (condition()) return true;
    std::this_thread::sleep_for(10ms);
  }
  return condition();
}

TEST(HttpSource, ReadsExactRangesFromNginx) {
  Served s;
  auto client = std::make_shared<HttpClient>();
  const auto source = HttpByteSource::open(s.nginx->url("data.bin"), client, nullptr);
  EXPECT_EQ(source->size(), kFileSize);
  EXPECT_FALSE(source->version().empty()) << "nginx sends an ETag";
  EXPECT_FALSE(source->local());
  EXPECT_EQ(readRange(*source, 0, 100), slice(s.bytes, 0, 100));
  EXPECT_EQ(readRange(*source, 123457, 5000), slice(s.bytes, 123457, 5000));
  EXPECT_EQ(readRange(*source, kFileSize - 1, 1), slice(s.bytes, kFileSize - 1, 1));
  EXPECT_EQ(source->stats().requests, 4u);  // the probe and three reads
  const std::string past = errorOf([&] { readRange(*source, kFileSize - 1, 2, "node r7"); });
  expectContains(past, {"data.bin", "node r7", "past its end"});
}

TEST(HttpSource, AdjacentPrefetchesShareOneRequest) {
  Served s;
  auto client = std::make_shared<HttpClient>();
  const auto source = HttpByteSource::open(s.nginx->url("data.bin"), client, nullptr);
  // Four neighbours and one apart; hinted together, then read in another order.
  const std::vector<ByteRange> hint{
      {8192, 4096}, {4096, 4096}, {12288, 4096}, {16384, 100}, {500000, 10}};
  source->prefetch(hint);
  for (const ByteRange& r : {hint[4], hint[2], hint[0], hint[3], hint[1]}) {
    EXPECT_EQ(readRange(*source, r.offset, std::size_t(r.size)),
              slice(s.bytes, std::size_t(r.offset), std::size_t(r.size)));
  }
  const HttpSourceStats stats = source->stats();
  EXPECT_EQ(stats.requests, 3u);  // the probe, 4096-16483 merged, 500000-500009
  EXPECT_EQ(stats.merged_requests, 1u);
  EXPECT_EQ(stats.bytes_received, 1u + 12388u + 10u);
  int merged_lines = 0;
  for (const test::AccessLine& line : s.nginx->accessLogOf(stats.requests)) {
    merged_lines += line.range == "\"bytes=4096-16483\"" && line.status == 206;
  }
  EXPECT_EQ(merged_lines, 1);
}

TEST(HttpSource, ServerErrorsResetsAndShortBodiesAreRetried) {
  for (const char* mode : {"503", "drop", "truncate"}) {
    SCOPED_TRACE(mode);
    Served s;
    // Every second request of data.bin after the probe fails.
    auto proxy = s.proxy({"--mode", mode, "--path-suffix", "data.bin", "--after", "1", "--every",
                          "2", "--times-per-request", "2"});
    auto client = std::make_shared<HttpClient>();
    const auto source =
        HttpByteSource::open(proxy->url("data.bin"), client, nullptr, fastRetries());
    for (std::size_t i = 0; i < 6; ++i) {
      const std::size_t offset = i * 100000;
      EXPECT_EQ(readRange(*source, offset, 30000), slice(s.bytes, offset, 30000));
    }
    EXPECT_GE(source->stats().retries, 3u);
    int faults = 0;
    for (const test::ProxyLine& line : proxy->log()) faults += line.action == mode;
    EXPECT_GE(faults, 3);
  }
}

TEST(HttpSource, ClientErrorsAreNeverRetried) {
  Served s;
  auto proxy = s.proxy({"--mode", "404", "--path-suffix", "data.bin", "--after", "1"});
  auto client = std::make_shared<HttpClient>();
  const auto source = HttpByteSource::open(proxy->url("data.bin"), client, nullptr, fastRetries());
  const std::string message = errorOf([&] { readRange(*source, 1000, 10, "node r0"); });
  expectContains(message, {proxy->url("data.bin").c_str(), "byte offset 1000", "node r0",
                           "HTTP 404 Not Found"});
  int asked = 0;
  for (const test::ProxyLine& line : proxy->log()) asked += line.range == "bytes=1000-1009";
  EXPECT_EQ(asked, 1) << "a 404 is never asked again";
  EXPECT_EQ(source->stats().retries, 0u);
}

TEST(HttpSource, PersistentServerErrorsEndAfterTheLastAttempt) {
  Served s;
  auto proxy = s.proxy({"--mode", "503", "--path-suffix", "data.bin", "--after", "1"});
  auto client = std::make_shared<HttpClient>();
  const auto source = HttpByteSource::open(proxy->url("data.bin"), client, nullptr, fastRetries(3));
  const std::string message = errorOf([&] { readRange(*source, 50, 10, "node r12"); });
  expectContains(message, {"data.bin", "node r12", "HTTP 503", "3 attempts"});
  int asked = 0;
  for (const test::ProxyLine& line : proxy->log()) asked += line.range == "bytes=50-59";
  EXPECT_EQ(asked, 3);
}

TEST(HttpSource, AServerThatIgnoresRangeIsAnError) {
  Served s;
  {
    // From the first request, for a file over whole_file_bytes: the probe says so.
    auto proxy = s.proxy({"--mode", "ignore-range"});
    auto client = std::make_shared<HttpClient>();
    HttpSourceOptions options = fastRetries();
    options.whole_file_bytes = kFileSize - 1;
    const std::string message =
        errorOf([&] { HttpByteSource::open(proxy->url("data.bin"), client, nullptr, options); });
    expectContains(message, {"data.bin", "(1048576 bytes): the server ignores Range requests",
                             "at most 0 MiB"});
  }
  // From a later request: the read of that range says so, and no byte of the body was taken.
  auto proxy = std::make_unique<FaultProxy>(
      s.dir / "proxy2", s.nginx->port(),
      std::vector<std::string>{"--mode", "ignore-range", "--after", "1"});
  auto client = std::make_shared<HttpClient>();
  const auto source = HttpByteSource::open(proxy->url("data.bin"), client, nullptr, fastRetries());
  const std::string message = errorOf([&] { readRange(*source, 4096, 10, "node r3"); });
  expectContains(message, {"data.bin", "node r3", "ignores Range"});
  EXPECT_EQ(source->stats().bytes_received, 1u) << "only the probe's byte";
}

// A server without range requests (Python's http.server) answers the probe with the whole file:
// up to whole_file_bytes it is kept, and every read is served from it, whatever the head asked
// for (a 1-byte probe included), without asking for a range the server would answer whole again.
TEST(HttpSource, AServerThatIgnoresRangeServesAFileUpToTheLimitWhole) {
  Served s;
  auto proxy = s.proxy({"--mode", "ignore-range"});
  auto client = std::make_shared<HttpClient>();
  HttpSourceOptions options = fastRetries();
  options.whole_file_bytes = kFileSize;
  const auto source = HttpByteSource::open(proxy->url("data.bin"), client, nullptr, options);
  EXPECT_EQ(source->size(), kFileSize);
  const std::vector<ByteRange> hint{{4096, 100}, {kFileSize - 10, 10}};
  source->prefetch(hint);
  EXPECT_EQ(readRange(*source, 0, 16), slice(s.bytes, 0, 16));
  EXPECT_EQ(readRange(*source, 4096, 100), slice(s.bytes, 4096, 100));
  EXPECT_EQ(readRange(*source, kFileSize - 10, 10), slice(s.bytes, kFileSize - 10, 10));
  EXPECT_EQ(source->stats().requests, 1u) << "the probe only";
  EXPECT_EQ(source->stats().bytes_received, kFileSize);
  EXPECT_EQ(source->stats().head_hits, 3u);
  EXPECT_EQ(proxy->log().size(), 1u);
}

TEST(HttpSource, AFileChangedWhileReadFailsEveryLaterRead) {
  Served s;
  auto proxy = s.proxy({"--mode", "etag", "--path-suffix", "data.bin", "--after", "2"});
  auto client = std::make_shared<HttpClient>();
  const auto source = HttpByteSource::open(proxy->url("data.bin"), client, nullptr, fastRetries());
  EXPECT_EQ(readRange(*source, 0, 10), slice(s.bytes, 0, 10));  // still the first version
  const std::string message = errorOf([&] { readRange(*source, 2000, 10, "node r5"); });
  expectContains(message, {"data.bin", "node r5", "changed on the server while it was read"});
  // Even an answer with the old ETag is not taken now: one version only.
  const std::string later = errorOf([&] { readRange(*source, 9000, 10, "node r6"); });
  expectContains(later, {"node r6", "changed on the server"});
}

// The error of reading `size` bytes of data.bin at offset 100 through a fault proxy with `args`
// (its first request, the probe, passed), with a 1 s stall timeout and two attempts.
std::string slowServerError(Served& s, const std::vector<std::string>& args, std::size_t size) {
  auto proxy = s.proxy(args);
  HttpOptions http;
  http.stall_timeout = 1s;
  auto client = std::make_shared<HttpClient>(http);
  const auto source = HttpByteSource::open(proxy->url("data.bin"), client, nullptr, fastRetries(2));
  return errorOf([&] { readRange(*source, 100, size, "node r1"); });
}

TEST(HttpSource, AStalledServerTimesOut) {
  Served s;
  const std::string message =
      slowServerError(s, {"--mode", "stall", "--delay-ms", "60000", "--after", "1"}, 10);
  expectContains(message,
                 {"data.bin", "node r1", "timed out", "2 attempts", "PARALLAX_HTTP_TIMEOUT"});
}

// A server that sends a byte every 50 ms never goes quiet, but a 64 KiB range would take an hour:
// under kStallBytesPerSecond for the stall timeout is a stall too.
TEST(HttpSource, ATricklingServerTimesOut) {
  Served s;
  const std::string message =
      slowServerError(s, {"--mode", "trickle", "--delay-ms", "50", "--after", "1"}, 65536);
  expectContains(message,
                 {"data.bin", "node r1", "timed out", "2 attempts", "under 64 bytes a second"});
}

TEST(HttpSource, CancelledReadsThrowAndTheirRequestsEnd) {
  Served s;
  auto proxy = s.proxy({"--mode", "delay", "--delay-ms", "30000", "--after", "1"});
  auto client = std::make_shared<HttpClient>();
  const auto source = HttpByteSource::open(proxy->url("data.bin"), client, nullptr, fastRetries());
  std::stop_source stop;
  bool cancelled = false;
  std::thread reader([&] {
    std::vector<std::byte> out(100);
    try {
      source->read(5000, out, {.cancel = stop.get_token(), .element = "node r"});
    } catch (const ReadCancelled&) {
      cancelled = true;
    }
  });
  ASSERT_TRUE(eventually([&] { return client->stats().in_flight == 1; }));
  stop.request_stop();
  reader.join();
  EXPECT_TRUE(cancelled);
  EXPECT_TRUE(eventually([&] { return source->stats().cancelled_requests == 1; }));
  EXPECT_EQ(client->stats().in_flight, 0u);
}

TEST(HttpSource, AReplacedHintCancelsItsRequests) {
  Served s;
  auto proxy = s.proxy({"--mode", "delay", "--delay-ms", "30000", "--after", "1"});
  auto client = std::make_shared<HttpClient>();
  const auto source = HttpByteSource::open(proxy->url("data.bin"), client, nullptr, fastRetries());
  source->prefetch(std::vector<ByteRange>{{1000, 100}, {50000, 100}});
  ASSERT_TRUE(eventually([&] { return client->stats().in_flight == 2; }));
  // The camera moved: only the second is still wanted.
  source->prefetch(std::vector<ByteRange>{{50000, 100}});
  EXPECT_TRUE(eventually([&] { return source->stats().cancelled_requests == 1; }));
  EXPECT_EQ(client->stats().in_flight, 1u);
}

TEST(HttpSource, RangesFetchedForADroppedHintAreKeptForALaterRead) {
  Served s;
  auto client = std::make_shared<HttpClient>();
  const auto source = HttpByteSource::open(s.nginx->url("data.bin"), client, nullptr);
  source->prefetch(std::vector<ByteRange>{{10000, 300}});
  ASSERT_TRUE(eventually([&] { return source->stats().bytes_received == 301u; }));
  source->prefetch({});  // the view changed its mind...
  EXPECT_EQ(readRange(*source, 10000, 300), slice(s.bytes, 10000, 300));  // ...and back
  EXPECT_EQ(source->stats().requests, 2u) << "read from memory, not fetched again";
  // Beyond the spare budget the oldest go.
  HttpSourceOptions small;
  small.spare_bytes = 500;
  const auto tight = HttpByteSource::open(s.nginx->url("data.bin"), client, nullptr, small);
  tight->prefetch(std::vector<ByteRange>{{0, 400}, {5000, 400}});
  ASSERT_TRUE(eventually([&] { return tight->stats().bytes_received == 801u; }));
  tight->prefetch({});
  EXPECT_EQ(readRange(*tight, 5000, 400), slice(s.bytes, 5000, 400));
  EXPECT_EQ(readRange(*tight, 0, 400), slice(s.bytes, 0, 400));
  EXPECT_EQ(tight->stats().requests, 4u) << "one of the two was dropped and fetched again";
}

TEST(HttpSource, TheCacheServesASecondOpenAfterOneCheck) {
  Served s;
  auto client = std::make_shared<HttpClient>();
  auto cache = std::make_shared<RangeCache>(s.dir / "cache", 64 << 20);
  std::size_t lines_before = 0;
  {
    const auto source = HttpByteSource::open(s.nginx->url("data.bin"), client, cache);
    EXPECT_FALSE(source->stats().validated_by_cache);
    readRange(*source, 1000, 500);
    readRange(*source, 700000, 5000);
    lines_before = source->stats().requests;
  }
  // Every line of the first open written before the second open's is looked for.
  ASSERT_EQ(s.nginx->accessLogOf(lines_before).size(), lines_before);
  {
    const auto source = HttpByteSource::open(s.nginx->url("data.bin"), client, cache);
    EXPECT_TRUE(source->stats().validated_by_cache);
    EXPECT_EQ(readRange(*source, 1000, 500), slice(s.bytes, 1000, 500));
    EXPECT_EQ(readRange(*source, 701000, 100), slice(s.bytes, 701000, 100));
    EXPECT_EQ(source->stats().cache_hits, 2u);
    EXPECT_EQ(source->stats().requests, 1u);
  }
  const std::vector<test::AccessLine> log = s.nginx->accessLogOf(lines_before + 1);
  ASSERT_EQ(log.size(), lines_before + 1);
  EXPECT_EQ(log.back().status, 304) << "one conditional request, answered Not Modified";

  // The file changes on the server: the next open sees a new ETag and drops what it kept.
  // nginx's ETag is the modification time in seconds and the size: the new content is given a
  // modification time two seconds on rather than waiting for the clock to pass a second.
  const std::filesystem::path served = s.dir / "www" / "data.bin";
  const auto modified = std::filesystem::last_write_time(served);
  const std::vector<std::byte> changed = pattern(kFileSize, 99);
  writeBytes(served, changed);
  std::filesystem::last_write_time(served, modified + 2s);
  const auto source = HttpByteSource::open(s.nginx->url("data.bin"), client, cache);
  EXPECT_FALSE(source->stats().validated_by_cache);
  EXPECT_EQ(readRange(*source, 1000, 500), slice(changed, 1000, 500));
  EXPECT_EQ(source->stats().cache_hits, 0u);
}

// A server that sends no ETag (nginx's `etag off`, as some object stores and static servers do)
// still has its ranges kept: the second open asks with If-Modified-Since, and a newer file on the
// server is fetched again rather than served stale from the cache.
TEST(HttpSource, WithoutAnETagTheCacheChecksTheDate) {
  Served s("    etag off;");
  auto client = std::make_shared<HttpClient>();
  auto cache = std::make_shared<RangeCache>(s.dir / "cache", 64 << 20);
  std::size_t lines_before = 0;
  {
    const auto source = HttpByteSource::open(s.nginx->url("data.bin"), client, cache);
    readRange(*source, 200000, 4000);
    lines_before = source->stats().requests;
  }
  ASSERT_EQ(s.nginx->accessLogOf(lines_before).size(), lines_before);
  {
    const auto source = HttpByteSource::open(s.nginx->url("data.bin"), client, cache);
    EXPECT_TRUE(source->stats().validated_by_cache);
    EXPECT_EQ(readRange(*source, 201000, 1000), slice(s.bytes, 201000, 1000));
    EXPECT_EQ(source->stats().cache_hits, 1u);
    EXPECT_EQ(source->stats().requests, 1u);
  }
  const std::vector<test::AccessLine> log = s.nginx->accessLogOf(lines_before + 1);
  ASSERT_EQ(log.size(), lines_before + 1);
  EXPECT_EQ(log.back().status, 304) << "the date was the same: Not Modified";

  // Same size, a later date: the cached ranges are another version's.
  const std::filesystem::path served = s.dir / "www" / "data.bin";
  const auto modified = std::filesystem::last_write_time(served);
  const std::vector<std::byte> changed = pattern(kFileSize, 41);
  writeBytes(served, changed);
  std::filesystem::last_write_time(served, modified + 2s);
  const auto source = HttpByteSource::open(s.nginx->url("data.bin"), client, cache);
  EXPECT_FALSE(source->stats().validated_by_cache);
  EXPECT_EQ(readRange(*source, 201000, 1000), slice(changed, 201000, 1000));
  EXPECT_EQ(source->stats().cache_hits, 0u);
}

// A server that states no version at all (no ETag, no Last-Modified): nothing says whether a
// cached range is still the file's, so nothing is served from the cache; every open reads the
// server again and gets the file as it is now.
TEST(HttpSource, WithoutAnyVersionNothingIsServedFromTheCache) {
  Served s;
  auto proxy = s.proxy({"--mode", "no-validators"});
  auto client = std::make_shared<HttpClient>();
  auto cache = std::make_shared<RangeCache>(s.dir / "cache", 64 << 20);
  {
    const auto source = HttpByteSource::open(proxy->url("data.bin"), client, cache);
    EXPECT_EQ(readRange(*source, 300000, 2000), slice(s.bytes, 300000, 2000));
  }
  const std::vector<std::byte> changed = pattern(kFileSize, 43);
  writeBytes(s.dir / "www" / "data.bin", changed);
  const auto source = HttpByteSource::open(proxy->url("data.bin"), client, cache);
  EXPECT_FALSE(source->stats().validated_by_cache);
  EXPECT_EQ(readRange(*source, 300000, 2000), slice(changed, 300000, 2000));
  EXPECT_EQ(source->stats().cache_hits, 0u);
  for (const test::ProxyLine& line : proxy->log()) {
    EXPECT_NE(line.status, 304) << "no conditional request can be made without a version";
  }
}

// A 503 with Retry-After: 1 is retried no sooner than a second later, although the backoff alone
// would have waited 10-20 ms (the server asked for the time; the lower bound is the behaviour
// under test, and load can only lengthen it).
TEST(HttpSource, RetryAfterIsWaitedBeforeTheNextAttempt) {
  Served s;
  auto proxy = s.proxy({"--mode", "503", "--path-suffix", "data.bin", "--after", "1",
                        "--max-faults", "1", "--retry-after", "1"});
  auto client = std::make_shared<HttpClient>();
  HttpSourceOptions options = fastRetries();
  options.retry.max_delay = 5s;  // the cap on Retry-After: above the one asked for
  const auto source = HttpByteSource::open(proxy->url("data.bin"), client, nullptr, options);
  const auto start = std::chrono::steady_clock::now();
  EXPECT_EQ(readRange(*source, 500000, 3000), slice(s.bytes, 500000, 3000));
  EXPECT_GE(std::chrono::steady_clock::now() - start, 1s);
  EXPECT_EQ(source->stats().retries, 1u);
  int faults = 0;
  for (const test::ProxyLine& line : proxy->log()) faults += line.status == 503;
  EXPECT_EQ(faults, 1);
}

TEST(HttpSource, RedirectsAreFollowed) {
  Served s("    location = /moved.bin { return 302 /data.bin; }");
  auto client = std::make_shared<HttpClient>();
  const auto source = HttpByteSource::open(s.nginx->url("moved.bin"), client, nullptr);
  EXPECT_EQ(source->size(), kFileSize);
  EXPECT_EQ(readRange(*source, 77, 7), slice(s.bytes, 77, 7));
}

TEST(HttpSource, ProxiesComeFromTheEnvironment) {
  Served s;
  auto proxy = s.proxy({"--mode", "pass"});
  ::setenv("http_proxy", ("http://127.0.0.1:" + std::to_string(proxy->port())).c_str(), 1);
  ::unsetenv("no_proxy");
  ::unsetenv("NO_PROXY");
  auto client = std::make_shared<HttpClient>();
  {
    const auto source = HttpByteSource::open(s.nginx->url("data.bin"), client, nullptr);
    EXPECT_EQ(readRange(*source, 300, 30), slice(s.bytes, 300, 30));
  }
  ::unsetenv("http_proxy");
  const std::vector<test::ProxyLine> log = proxy->log();
  ASSERT_EQ(log.size(), 2u) << "the probe and the read went through the proxy";
  EXPECT_EQ(log[1].range, "bytes=300-329");
}

// A port that nothing listens on (bound, then closed): the connection is refused.
int refusedPort() {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t length = sizeof address;
  EXPECT_EQ(::bind(fd, reinterpret_cast<sockaddr*>(&address), length), 0);
  EXPECT_EQ(::getsockname(fd, reinterpret_cast<sockaddr*>(&address), &length), 0);
  ::close(fd);
  return ntohs(address.sin_port);
}

TEST(HttpSource, ARefusedConnectionIsRetriedThenNamed) {
  auto client = std::make_shared<HttpClient>();
  const std::string url = "http://127.0.0.1:" + std::to_string(refusedPort()) + "/data.bin";
  const std::string message =
      errorOf([&] { HttpByteSource::open(url, client, nullptr, fastRetries(3)); });
  expectContains(message, {url.c_str(), "connection failed", "3 attempts", "is the server up"});
}

TEST(HttpSource, RedirectsInALoopEndAtTheLimit) {
  Served s("    location = /loop.bin { return 302 /loop.bin; }");
  auto client = std::make_shared<HttpClient>();
  const std::string message = errorOf(
      [&] { HttpByteSource::open(s.nginx->url("loop.bin"), client, nullptr, fastRetries(1)); });
  expectContains(message, {"loop.bin", "Maximum (10) redirects followed"});
  // curl follows 10 redirects (CURLOPT_MAXREDIRS) and asks no more: 11 requests.
  EXPECT_EQ(s.nginx->settledAccessLog().size(), 11u);
}

TEST(HttpSource, NoProxyHostsAreReachedDirectly) {
  Served s;
  auto proxy = s.proxy({"--mode", "pass"});
  ::setenv("http_proxy", ("http://127.0.0.1:" + std::to_string(proxy->port())).c_str(), 1);
  ::setenv("no_proxy", "127.0.0.1", 1);
  auto client = std::make_shared<HttpClient>();
  {
    const auto source = HttpByteSource::open(s.nginx->url("data.bin"), client, nullptr);
    EXPECT_EQ(readRange(*source, 300, 30), slice(s.bytes, 300, 30));
  }
  ::unsetenv("http_proxy");
  ::unsetenv("no_proxy");
  EXPECT_TRUE(proxy->log().empty()) << "no_proxy names the host: nothing goes through the proxy";
  EXPECT_EQ(s.nginx->accessLogOf(2).size(), 2u) << "the probe and the read, straight to nginx";
}

TEST(HttpSource, TlsIsVerifiedByDefault) {
  test::TempDir dir;
  std::filesystem::create_directories(dir / "www");
  const std::vector<std::byte> bytes = pattern(4096, 3);
  writeBytes(dir / "www" / "data.bin", bytes);
  const std::string make_certificate =
      "openssl req -x509 -newkey rsa:2048 -nodes -days 2 -subj /CN=127.0.0.1 -addext "
      "subjectAltName=IP:127.0.0.1 -keyout " +
      (dir / "key.pem").string() + " -out " + (dir / "cert.pem").string() + " 2>" +
      (dir / "openssl.txt").string();
  ASSERT_EQ(std::system(make_certificate.c_str()), 0)
      << "openssl (Debian package 'openssl') failed: " << test::readWholeFile(dir / "openssl.txt");
  Nginx nginx(
      dir / "nginx",
      {.root = dir / "www", .tls_certificate = dir / "cert.pem", .tls_key = dir / "key.pem"});
  {
    auto client = std::make_shared<HttpClient>();
    const std::string message = errorOf(
        [&] { HttpByteSource::open(nginx.url("data.bin"), client, nullptr, fastRetries()); });
    expectContains(message, {"https://127.0.0.1", "data.bin", "certificate", "PARALLAX_CA_FILE"});
  }
  HttpOptions trusted;
  trusted.ca_file = (dir / "cert.pem").string();
  auto client = std::make_shared<HttpClient>(trusted);
  const auto source = HttpByteSource::open(nginx.url("data.bin"), client, nullptr);
  source->prefetch(std::vector<ByteRange>{{0, 100}, {2000, 100}, {4000, 96}});
  EXPECT_EQ(readRange(*source, 2000, 100), slice(bytes, 2000, 100));
  EXPECT_EQ(readRange(*source, 0, 100), slice(bytes, 0, 100));
  EXPECT_EQ(readRange(*source, 4000, 96), slice(bytes, 4000, 96));
  const std::vector<test::AccessLine> log = nginx.accessLogOf(source->stats().requests);
  ASSERT_FALSE(log.empty());
  EXPECT_EQ(log.back().protocol, "HTTP/2.0") << "ALPN offered h2, and the client took it";
}

}  // namespace
}  // namespace parallax
