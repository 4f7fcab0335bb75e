// `parallax` on an octree served by nginx on loopback: `render URL` gives the picture of
// `render PATH` pixel for pixel, a second run is served from the on-disk cache (three
// conditional requests, each answered 304), and through the fault-injecting proxy every run
// either gives that same picture or fails with an error naming the URL and the node; none hangs
// (each run is bounded by `timeout`, and the client's stall timeout is 1-2 s here). Also: info,
// convert (a copy and a point file), bench render, a proxy from the environment, and URLs of
// COPC files, and point files (info, render and pick of a LAS or LAZ file's URL).
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "lod/copc_writer.h"
#include "lod/potree_reader.h"
#include "loopback_servers.h"
#include "render/image_file.h"
#include "support/run_parallax.h"
#include "support/temp_dir.h"
#include "support/test_data.h"

namespace parallax {
namespace {

using test::FaultProxy;
using test::Nginx;
using test::quoted;

// About 50 nodes of the 200 000-point octree, fetched in a dozen requests (merged).
const char* const kView = "--width 256 --height 192 --budget 100000 --min-node-size 5";

// `parallax ARGS` with `env` set and the environment's proxies cleared (nothing leaves the
// machine), under `timeout` so that a hang fails the test instead of stalling the suite.
test::RunResult run(const test::TempDir& dir, const std::map<std::string, std::string>& env,
                    const std::string& args) {
  std::string prefix =
      "timeout 120 env -u http_proxy -u https_proxy -u HTTP_PROXY -u HTTPS_PROXY -u all_proxy "
      "-u ALL_PROXY -u no_proxy -u NO_PROXY";
  for (const auto& [name, value] : env) prefix += " " + name + "=" + quoted(value);
  const auto out = dir / "stdout.txt";
  const auto err = dir / "stderr.txt";
  const std::string command = prefix + " " + quoted(PARALLAX_EXECUTABLE) + " " + args + " >" +
                              quoted(out.string()) + " 2>" + quoted(err.string()) + " </dev/null";
  const int status = std::system(command.c_str());
  test::RunResult result;
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  result.out = test::readText(out);
  result.err = test::readText(err);
  return result;
}

// One octree for every test of the suite (and every test process: built once, renamed into
// place), with the picture `render PATH` gives.
struct Dataset {
  std::filesystem::path root;       // served by nginx; the octree is root/oct
  std::filesystem::path reference;  // render PATH's picture
};

const Dataset& dataset() {
  static const Dataset data = [] {
    const std::filesystem::path shared = std::filesystem::path(PARALLAX_TEST_TMP) / "dataset";
    Dataset d{shared / "www", shared / "reference.png"};
    if (std::filesystem::exists(shared / "ready")) return d;
    const std::filesystem::path build = std::filesystem::path(PARALLAX_TEST_TMP) /
                                        ("dataset.partial-" + std::to_string(::getpid()));
    std::filesystem::remove_all(build);
    std::filesystem::create_directories(build / "www");
    const std::string exe = quoted(PARALLAX_EXECUTABLE);
    const std::string ply = quoted((build / "scan.ply").string());
    const std::string oct = quoted((build / "www" / "oct").string());
    const std::string commands =
        exe + " generate -o " + ply + " --points 200000 --seed 11 >/dev/null 2>&1 && " + exe +
        " convert " + ply + " -o " + oct + " -q && " + exe + " render " + oct + " -o " +
        quoted((build / "reference.png").string()) + " " + kView + " >/dev/null 2>&1";
    if (std::system(commands.c_str()) != 0) throw std::runtime_error("building the dataset failed");
    std::filesystem::remove(build / "scan.ply");
    std::ofstream(build / "ready") << "ready\n";
    std::error_code error;
    std::filesystem::rename(build, shared, error);  // another process may have been first
    if (error) std::filesystem::remove_all(build);
    return d;
  }();
  return data;
}

struct Served {
  test::TempDir dir;
  Nginx nginx{dir / "nginx", {.root = dataset().root}};
  std::map<std::string, std::string> env{{"XDG_CACHE_HOME", (dir / "cache").string()}};
};

void expectSamePicture(const std::filesystem::path& png) {
  const RgbaImage expected = readPng(dataset().reference);
  const RgbaImage got = readPng(png);
  ASSERT_EQ(got.width, expected.width);
  ASSERT_EQ(got.height, expected.height);
  std::size_t differ = 0, lit = 0;
  for (std::size_t i = 0; i < got.pixels.size(); i += 4) {
    differ += !std::equal(&got.pixels[i], &got.pixels[i] + 4, &expected.pixels[i]);
    lit += expected.pixels[i] || expected.pixels[i + 1] || expected.pixels[i + 2];
  }
  EXPECT_EQ(differ, 0u) << "pixels that differ from render PATH";
  EXPECT_GT(lit, 1000u) << "the reference shows the cloud";
}

void expectContains(const std::string& text, std::initializer_list<std::string> parts) {
  for (const std::string& part : parts) EXPECT_NE(text.find(part), std::string::npos) << text;
}

TEST(HttpOctree, RenderUrlEqualsRenderPathAndTheSecondRunComesFromTheCache) {
  Served s;
  const std::string url = s.nginx.url("oct/");
  test::RunResult first =
      run(s.dir, s.env,
          "render " + quoted(url) + " -o " + quoted((s.dir / "first.png").string()) + " " + kView);
  ASSERT_EQ(first.exit_code, 0) << first.err;
  expectSamePicture(s.dir / "first.png");
  expectContains(first.err, {"network:", "received / needed"});
  const std::vector<test::AccessLine> first_log = s.nginx.settledAccessLog();
  const std::size_t first_requests = first_log.size();
  std::uint64_t node_bytes = 0;
  for (const test::AccessLine& line : first_log) {
    if (line.path == "/oct/octree.bin" && line.status == 206) node_bytes += line.bytes;
  }
  EXPECT_GT(node_bytes, 100000u);

  // Again, as ".../oct" and ".../oct/metadata.json": the same files, from the cache.
  for (const char* form : {"oct", "oct/metadata.json"}) {
    SCOPED_TRACE(form);
    const std::size_t before = s.nginx.settledAccessLog().size();
    const test::RunResult again = run(s.dir, s.env,
                                      "render " + quoted(s.nginx.url(form)) + " -o " +
                                          quoted((s.dir / "again.png").string()) + " " + kView);
    ASSERT_EQ(again.exit_code, 0) << again.err;
    expectSamePicture(s.dir / "again.png");
    const std::vector<test::AccessLine> log = s.nginx.accessLogOf(before + 3);
    ASSERT_EQ(log.size(), before + 3) << "one check per file";
    for (std::size_t i = before; i < log.size(); ++i) EXPECT_EQ(log[i].status, 304) << log[i].path;
  }
  EXPECT_GT(first_requests, 4u);
}

// `render` through the fault proxy (with `proxy_args`) in front of nginx: the run's result and
// the proxy's log.
struct ProxiedRun : test::RunResult {
  std::vector<test::ProxyLine> log;
  int faults(const std::string& action) const {
    int count = 0;
    for (const test::ProxyLine& line : log) count += line.action == action;
    return count;
  }
};

ProxiedRun renderThroughProxy(Served& s, const std::vector<std::string>& proxy_args,
                              std::map<std::string, std::string> env = {}) {
  FaultProxy proxy(s.dir / "proxy", s.nginx.port(), proxy_args);
  env.insert(s.env.begin(), s.env.end());
  ProxiedRun r{run(s.dir, env,
                   "render " + quoted(proxy.url("oct/")) + " -o " +
                       quoted((s.dir / "faulty.png").string()) + " " + kView),
               {}};
  r.log = proxy.log();
  return r;
}

TEST(HttpOctreeFaults, DelayedAnswersGiveTheSamePicture) {
  Served s;
  const ProxiedRun r = renderThroughProxy(s, {"--mode", "delay", "--delay-ms", "50"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  expectSamePicture(s.dir / "faulty.png");
  EXPECT_GT(r.faults("delay"), 4);
}

// The recoverable faults hit every second or third request, three times in all: with four
// attempts per range (the default), every range gets through however the client merges its
// requests, so the picture must be the local one.
TEST(HttpOctreeFaults, ConnectionsDroppedMidBodyAreRetried) {
  Served s;
  const ProxiedRun r =
      renderThroughProxy(s, {"--mode", "drop", "--every", "3", "--max-faults", "3"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  expectSamePicture(s.dir / "faulty.png");
  EXPECT_EQ(r.faults("drop"), 3);
}

TEST(HttpOctreeFaults, ServiceUnavailableIsRetried) {
  Served s;
  const ProxiedRun r =
      renderThroughProxy(s, {"--mode", "503", "--every", "2", "--max-faults", "3"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  expectSamePicture(s.dir / "faulty.png");
  EXPECT_EQ(r.faults("503"), 3);
}

TEST(HttpOctreeFaults, TruncatedBodiesAreRetried) {
  Served s;
  const ProxiedRun r =
      renderThroughProxy(s, {"--mode", "truncate", "--every", "3", "--max-faults", "3"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  expectSamePicture(s.dir / "faulty.png");
  EXPECT_EQ(r.faults("truncate"), 3);
}

TEST(HttpOctreeFaults, AServerThatKeepsFailingNamesTheUrlAndTheNode) {
  Served s;
  const ProxiedRun r =
      renderThroughProxy(s, {"--mode", "503", "--path-suffix", "octree.bin", "--after", "1"},
                         {{"PARALLAX_HTTP_RETRIES", "2"}});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  expectContains(
      r.err, {"/oct/octree.bin", "element 'node r", "HTTP 503 Service Unavailable", "2 attempts"});
}

TEST(HttpOctreeFaults, AServerThatIgnoresRangeNamesTheUrlAndTheNode) {
  Served s;
  const ProxiedRun r = renderThroughProxy(
      s, {"--mode", "ignore-range", "--path-suffix", "octree.bin", "--after", "1"});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  expectContains(r.err, {"/oct/octree.bin", "element 'node r", "ignores Range"});
}

TEST(HttpOctreeFaults, ADatasetChangedWhileReadIsNeverMixed) {
  Served s;
  const ProxiedRun r =
      renderThroughProxy(s, {"--mode", "etag", "--path-suffix", "octree.bin", "--after", "1"});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  expectContains(r.err,
                 {"/oct/octree.bin", "element 'node r", "changed on the server while it was read"});
  EXPECT_FALSE(std::filesystem::exists(s.dir / "faulty.png")) << "no picture of two versions";
}

TEST(HttpOctreeFaults, AStalledServerTimesOut) {
  Served s;
  const ProxiedRun r = renderThroughProxy(
      s, {"--mode", "stall", "--delay-ms", "60000", "--path-suffix", "octree.bin", "--after", "1"},
      {{"PARALLAX_HTTP_TIMEOUT", "1"}, {"PARALLAX_HTTP_RETRIES", "2"}});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  expectContains(r.err, {"/oct/octree.bin", "element 'node r", "timed out"});
}

TEST(HttpOctreeFaults, MissingFilesAreNotRetried) {
  Served s;
  FaultProxy proxy(s.dir / "proxy", s.nginx.port(),
                   {"--mode", "404", "--path-suffix", "octree.bin", "--after", "1"});
  const test::RunResult r = run(s.dir, s.env,
                                "render " + quoted(proxy.url("oct/")) + " -o " +
                                    quoted((s.dir / "x.png").string()) + " " + kView);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  expectContains(r.err, {"/oct/octree.bin", "element 'node r", "HTTP 404 Not Found"});
  std::map<std::string, int> asked;  // by range
  for (const test::ProxyLine& line : proxy.log()) {
    if (line.status == 404) ++asked[line.range];
  }
  ASSERT_FALSE(asked.empty());
  for (const auto& [range, count] : asked) EXPECT_EQ(count, 1) << range;
  // And a directory that is not there at all: metadata.json's 404, with the Potree hint.
  const test::RunResult missing = run(s.dir, s.env, "info " + quoted(s.nginx.url("nothing/")));
  EXPECT_EQ(missing.exit_code, 2);
  expectContains(missing.err,
                 {"/nothing/metadata.json", "HTTP 404", "hierarchy.bin and octree.bin"});
}

TEST(HttpOctree, ProxiesComeFromTheEnvironment) {
  Served s;
  FaultProxy proxy(s.dir / "proxy", s.nginx.port(), {"--mode", "pass"});
  std::map<std::string, std::string> env = s.env;
  env["http_proxy"] = "http://127.0.0.1:" + std::to_string(proxy.port());
  const test::RunResult r = run(s.dir, env,
                                "render " + quoted(s.nginx.url("oct/")) + " -o " +
                                    quoted((s.dir / "p.png").string()) + " " + kView);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  expectSamePicture(s.dir / "p.png");
  EXPECT_EQ(proxy.log().size(), s.nginx.settledAccessLog().size())
      << "every request went through it";
}

TEST(HttpOctree, InfoOfTheUrlMatchesInfoOfThePath) {
  Served s;
  const test::RunResult remote = run(s.dir, s.env, "info --json " + quoted(s.nginx.url("oct")));
  ASSERT_EQ(remote.exit_code, 0) << remote.err;
  const test::RunResult local =
      run(s.dir, s.env, "info --json " + quoted((dataset().root / "oct").string()));
  ASSERT_EQ(local.exit_code, 0) << local.err;
  const nlohmann::json a = nlohmann::json::parse(remote.out), b = nlohmann::json::parse(local.out);
  for (const char* key : {"points", "bounds", "attributes", "format_details", "file_bytes",
                          "quantization", "attribute_ranges"}) {
    EXPECT_EQ(a[key], b[key]) << key;
  }
  EXPECT_EQ(a["file"], s.nginx.url("oct"));
}

TEST(HttpOctree, ConvertCopiesTheOctreeAndWritesItsPoints) {
  Served s;
  const test::RunResult copy = run(s.dir, s.env,
                                   "convert " + quoted(s.nginx.url("oct/")) + " -o " +
                                       quoted((s.dir / "copy").string()) + " -q");
  ASSERT_EQ(copy.exit_code, 0) << copy.err;
  for (const char* name : {"metadata.json", "hierarchy.bin", "octree.bin"}) {
    EXPECT_EQ(test::readText(s.dir / "copy" / name), test::readText(dataset().root / "oct" / name))
        << name;
  }
  const test::RunResult remote = run(s.dir, s.env,
                                     "convert " + quoted(s.nginx.url("oct/metadata.json")) +
                                         " -o " + quoted((s.dir / "remote.ply").string()) + " -q");
  ASSERT_EQ(remote.exit_code, 0) << remote.err;
  const test::RunResult local = run(s.dir, s.env,
                                    "convert " + quoted((dataset().root / "oct").string()) +
                                        " -o " + quoted((s.dir / "local.ply").string()) + " -q");
  ASSERT_EQ(local.exit_code, 0) << local.err;
  const std::string ply = test::readText(s.dir / "remote.ply");
  EXPECT_EQ(ply, test::readText(s.dir / "local.ply"));
  EXPECT_NE(ply.find("element vertex 200000"), std::string::npos);
}

TEST(HttpOctree, BenchRenderTakesAUrl) {
  Served s;
  const test::RunResult r = run(s.dir, s.env,
                                "bench render " + quoted(s.nginx.url("oct/")) +
                                    " --budget 60000 --width 64 --height 48 --repeat 1");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  expectContains(r.out, {"bench render: " + s.nginx.url("oct/"), "LOD / plain"});
  expectContains(r.err, {"network:"});
}

// A COPC file (a real one, written by another tool) served as a plain file: `info URL` and
// `render URL` read its header, hierarchy page and chunks with range requests and give what the
// local file gives.
TEST(HttpOctree, CopcFilesStreamLikeTheLocalFile) {
  test::TempDir dir;
  std::filesystem::create_directories(dir / "www" / "tiles");
  const std::filesystem::path local = dir / "www" / "tiles" / "ellipsoid.copc.laz";
  std::filesystem::copy_file(test::testDataFile("laz/ellipsoid.copc.laz"), local);
  Nginx nginx(dir / "nginx", {.root = dir / "www"});
  const std::map<std::string, std::string> env{{"XDG_CACHE_HOME", (dir / "cache").string()}};
  const std::string url = nginx.url("tiles/ellipsoid.copc.laz");

  const test::RunResult remote = run(dir, env, "info --json " + quoted(url));
  ASSERT_EQ(remote.exit_code, 0) << remote.err;
  const test::RunResult here = run(dir, env, "info --json " + quoted(local.string()));
  ASSERT_EQ(here.exit_code, 0) << here.err;
  const nlohmann::json a = nlohmann::json::parse(remote.out), b = nlohmann::json::parse(here.out);
  for (const char* key : {"format", "format_details", "points", "bounds", "cube", "quantization"}) {
    EXPECT_EQ(a[key], b[key]) << key;
  }
  EXPECT_EQ(a["points"], 100000);
  EXPECT_EQ(a["format_details"]["hierarchy"]["nodes"], 5);
  bool ranged = false;
  for (const test::AccessLine& line : nginx.settledAccessLog())
    ranged = ranged || line.status == 206;
  EXPECT_TRUE(ranged) << "read with range requests";

  const std::string view = "--width 128 --height 96 --budget 100000";
  const test::RunResult r_remote =
      run(dir, env,
          "render " + quoted(url) + " -o " + quoted((dir / "remote.png").string()) + " " + view);
  ASSERT_EQ(r_remote.exit_code, 0) << r_remote.err;
  const test::RunResult r_here = run(dir, env,
                                     "render " + quoted(local.string()) + " -o " +
                                         quoted((dir / "local.png").string()) + " " + view);
  ASSERT_EQ(r_here.exit_code, 0) << r_here.err;
  const RgbaImage got = readPng(dir / "remote.png"), expected = readPng(dir / "local.png");
  ASSERT_EQ(got.pixels.size(), expected.pixels.size());
  EXPECT_TRUE(got.pixels == expected.pixels) << "render URL gives render PATH's picture";
  std::size_t lit = 0;
  for (std::size_t i = 0; i < expected.pixels.size(); i += 4) lit += expected.pixels[i + 1] != 0;
  EXPECT_GT(lit, 500u) << "the picture shows the cloud";

  // Again: the header, page and chunks come from the on-disk cache, checked with one request.
  const std::size_t before = nginx.settledAccessLog().size();
  const test::RunResult again =
      run(dir, env,
          "render " + quoted(url) + " -o " + quoted((dir / "again.png").string()) + " " + view);
  ASSERT_EQ(again.exit_code, 0) << again.err;
  EXPECT_TRUE(readPng(dir / "again.png").pixels == expected.pixels);
  const std::vector<test::AccessLine> log = nginx.accessLogOf(before + 1);
  ASSERT_EQ(log.size(), before + 1) << "one check of the file";
  EXPECT_EQ(log.back().status, 304);
}

// A COPC file whose hierarchy has child pages (Parallax's writer, one level a page, from the
// suite's octree): read over HTTP, `info` (which reads every page: its nodes, levels and points)
// and `render` give what the local file gives, the picture pixel for pixel; through the fault
// proxy (dropped connections, 503, truncated bodies, hitting the page reads), `info` still does.
TEST(HttpOctree, CopcChildHierarchyPagesStreamLikeTheLocalFile) {
  test::TempDir dir;
  std::filesystem::create_directories(dir / "www" / "tiles");
  const std::filesystem::path local = dir / "www" / "tiles" / "paged.copc.laz";
  {
    auto octree = openPotree(dataset().root / "oct");
    const CopcWriteResult written = writeCopc(*octree, local, {.page_levels = 1});
    ASSERT_GT(written.pages, 3u) << "the file has child hierarchy pages";
  }
  Nginx nginx(dir / "nginx", {.root = dir / "www"});
  const std::map<std::string, std::string> env{{"XDG_CACHE_HOME", (dir / "cache").string()}};
  const std::string path = "tiles/paged.copc.laz";

  const test::RunResult here = run(dir, env, "info --json " + quoted(local.string()));
  ASSERT_EQ(here.exit_code, 0) << here.err;
  const nlohmann::json expected = nlohmann::json::parse(here.out);
  EXPECT_EQ(expected["points"], 200000);
  const std::string view = kView;
  const test::RunResult r_here = run(dir, env,
                                     "render " + quoted(local.string()) + " -o " +
                                         quoted((dir / "local.png").string()) + " " + view);
  ASSERT_EQ(r_here.exit_code, 0) << r_here.err;
  const RgbaImage reference = readPng(dir / "local.png");
  std::size_t lit = 0;
  for (std::size_t i = 0; i < reference.pixels.size(); i += 4) {
    lit += reference.pixels[i] || reference.pixels[i + 1] || reference.pixels[i + 2];
  }
  EXPECT_GT(lit, 1000u) << "the picture shows the cloud";

  // `url`'s info and picture against the local file's; each run with a cache of its own, so that
  // every page is fetched again.
  int runs = 0;
  auto expectSameAsLocal = [&](const std::string& url, bool picture) {
    const std::map<std::string, std::string> fresh{
        {"XDG_CACHE_HOME", (dir / ("cache" + std::to_string(++runs))).string()}};
    const test::RunResult info = run(dir, fresh, "info --json " + quoted(url));
    ASSERT_EQ(info.exit_code, 0) << info.err;
    const nlohmann::json got = nlohmann::json::parse(info.out);
    for (const char* key : {"format", "format_details", "points", "bounds", "cube"}) {
      EXPECT_EQ(got[key], expected[key]) << key << " of " << url;
    }
    if (!picture) return;
    const auto png = dir / ("remote" + std::to_string(runs) + ".png");
    const test::RunResult render =
        run(dir, fresh, "render " + quoted(url) + " -o " + quoted(png.string()) + " " + view);
    ASSERT_EQ(render.exit_code, 0) << render.err;
    const RgbaImage got_picture = readPng(png);
    ASSERT_EQ(got_picture.pixels.size(), reference.pixels.size());
    EXPECT_TRUE(got_picture.pixels == reference.pixels) << "render " << url << " differs";
  };
  expectSameAsLocal(nginx.url(path), true);
  // The child pages were read with range requests of their own: more than the header, the root
  // page and the chunks of a single-page file would take.
  std::size_t ranged = 0;
  for (const test::AccessLine& line : nginx.settledAccessLog()) ranged += line.status == 206;
  EXPECT_GT(ranged, 3u);

  for (const std::vector<std::string>& faults :
       {std::vector<std::string>{"--mode", "drop", "--every", "3", "--max-faults", "2"},
        std::vector<std::string>{"--mode", "503", "--every", "2", "--max-faults", "2"},
        std::vector<std::string>{"--mode", "truncate", "--every", "3", "--max-faults", "2"}}) {
    FaultProxy proxy(dir / ("proxy" + std::to_string(runs)), nginx.port(), faults);
    expectSameAsLocal(proxy.url(path), false);
    int injected = 0;
    for (const test::ProxyLine& line : proxy.log()) injected += line.action == faults[1];
    EXPECT_EQ(injected, 2) << faults[1] << " faults injected";
  }
}

// Point files that are no octree: `info`, `render` and `pick` of their URL go through the format
// table (a LAS or LAZ file read by range), and each answers as for the local file.
TEST(HttpOctree, PointFilesFromAUrlAnswerAsTheLocalFile) {
  test::TempDir dir;
  std::filesystem::create_directories(dir / "www");
  for (const char* name : {"1815.las", "1815.laz"}) {
    std::filesystem::copy_file(test::testDataFile(std::string("laz/") + name), dir / "www" / name);
  }
  Nginx nginx(dir / "nginx", {.root = dir / "www"});
  const std::map<std::string, std::string> env{{"XDG_CACHE_HOME", (dir / "cache").string()}};
  const std::string size = "--width 128 --height 96";
  for (const char* name : {"1815.las", "1815.laz"}) {
    SCOPED_TRACE(name);
    const std::string url = quoted(nginx.url(name));
    const std::string path = quoted((dir / "www" / name).string());

    const test::RunResult remote_info = run(dir, env, "info --json " + url);
    ASSERT_EQ(remote_info.exit_code, 0) << remote_info.err;
    const test::RunResult local_info = run(dir, env, "info --json " + path);
    ASSERT_EQ(local_info.exit_code, 0) << local_info.err;
    const nlohmann::json a = nlohmann::json::parse(remote_info.out);
    const nlohmann::json b = nlohmann::json::parse(local_info.out);
    for (const char* key : {"format", "points", "bounds", "attributes", "format_details",
                            "file_bytes", "quantization", "attribute_ranges"}) {
      EXPECT_EQ(a[key], b[key]) << key;
    }
    EXPECT_EQ(a["points"], 1247);

    const auto remote_png = dir / "remote.png", local_png = dir / "local.png";
    const test::RunResult remote_render =
        run(dir, env, "render -q " + url + " -o " + quoted(remote_png.string()) + " " + size);
    ASSERT_EQ(remote_render.exit_code, 0) << remote_render.err;
    ASSERT_EQ(run(dir, env, "render -q " + path + " -o " + quoted(local_png.string()) + " " + size)
                  .exit_code,
              0);
    const RgbaImage remote_picture = readPng(remote_png), local_picture = readPng(local_png);
    ASSERT_EQ(remote_picture.pixels.size(), local_picture.pixels.size());
    EXPECT_TRUE(remote_picture.pixels == local_picture.pixels);
    std::size_t lit = 0;
    for (std::size_t i = 0; i < local_picture.pixels.size(); i += 4) {
      lit += local_picture.pixels[i] || local_picture.pixels[i + 1] || local_picture.pixels[i + 2];
    }
    EXPECT_GT(lit, 100u) << "the picture shows the cloud";

    const std::string pick = "pick --json --pixel 64,48 --radius 40 " + size + " ";
    const test::RunResult remote_pick = run(dir, env, pick + url);
    ASSERT_EQ(remote_pick.exit_code, 0) << remote_pick.err;
    const test::RunResult local_pick = run(dir, env, pick + path);
    ASSERT_EQ(local_pick.exit_code, 0) << local_pick.err;
    EXPECT_EQ(remote_pick.out, local_pick.out);
    EXPECT_EQ(nlohmann::json::parse(remote_pick.out)["found"], true) << remote_pick.out;
  }
  // Every request was a range or a cache's conditional one: no file was fetched whole.
  for (const test::AccessLine& line : nginx.settledAccessLog()) {
    EXPECT_TRUE(line.status == 206 || line.status == 304) << line.status << " " << line.path;
  }
}

TEST(HttpOctree, AUrlOfNoPointFileIsAnErrorNamingIt) {
  Served s;
  const test::RunResult missing = run(s.dir, s.env, "info " + quoted(s.nginx.url("scan.ply")));
  EXPECT_EQ(missing.exit_code, 2);
  expectContains(missing.err, {"/scan.ply", "404"});
  const test::RunResult render =
      run(s.dir, s.env, "render " + quoted(s.nginx.url("a/b.laz")) + " -o x.png");
  EXPECT_EQ(render.exit_code, 2);
  expectContains(render.err, {"/a/b.laz", "404"});
}

}  // namespace
}  // namespace parallax
