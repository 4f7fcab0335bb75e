// core's opener: local paths are files, a URL goes to the opener registered for its scheme
// (net registers http and https; here a test scheme), unknown schemes are errors naming them.
#include "core/byte_source_opener.h"

#include <gtest/gtest.h>

#include <fstream>
#include <string>
#include <vector>

#include "core/error.h"
#include "support/temp_dir.h"

namespace parallax {
namespace {

std::vector<std::byte> bytesOf(const std::string& text) {
  std::vector<std::byte> bytes(text.size());
  for (std::size_t i = 0; i < text.size(); ++i) bytes[i] = std::byte(text[i]);
  return bytes;
}

// "mem://NAME": a source holding NAME itself, with the head asked for as its version.
std::vector<ByteSourceRequest> g_asked;
void registerMemScheme() {
  registerByteSourceOpener("mem", [](std::span<const ByteSourceRequest> requests) {
    std::vector<std::unique_ptr<ByteSource>> sources;
    for (const ByteSourceRequest& r : requests) {
      g_asked.push_back(r);
      const std::string name = r.location.substr(r.location.find("://") + 3);
      sources.push_back(makeMemorySource(bytesOf(name), r.location, std::to_string(r.head_bytes)));
    }
    return sources;
  });
}

TEST(ByteSourceOpener, SchemesAreRecognisedOnlyBeforeColonSlashSlash) {
  EXPECT_EQ(urlScheme("http://example.com/x.laz"), "http");
  EXPECT_EQ(urlScheme("HTTPS://example.com"), "https");
  EXPECT_EQ(urlScheme("s3+x.y-z://bucket/key"), "s3+x.y-z");
  EXPECT_EQ(urlScheme("/data/http://x"), "");
  EXPECT_EQ(urlScheme("cloud.ply"), "");
  EXPECT_EQ(urlScheme("://x"), "");
  EXPECT_EQ(urlScheme("1http://x"), "");
  EXPECT_EQ(urlScheme("C:\\data\\x.ply"), "");
  EXPECT_TRUE(isUrl("mem://a"));
  EXPECT_FALSE(isUrl("dir/mem:/a"));
}

TEST(ByteSourceOpener, AUrlGoesToItsSchemesOpenerWithTheHeadAskedFor) {
  registerMemScheme();
  g_asked.clear();
  const std::unique_ptr<ByteSource> source = openByteSource("MEM://hello", 64);
  EXPECT_EQ(source->size(), 5u);
  EXPECT_EQ(source->version(), "64");
  std::vector<std::byte> out(5);
  source->read(0, out);
  EXPECT_EQ(out, bytesOf("hello"));
  ASSERT_EQ(g_asked.size(), 1u);
  EXPECT_EQ(g_asked[0].location, "MEM://hello");
  EXPECT_EQ(g_asked[0].head_bytes, 64u);
}

TEST(ByteSourceOpener, SeveralSourcesComeBackInTheOrderAskedWithTheirSchemesGroupedInOneCall) {
  registerMemScheme();
  g_asked.clear();
  test::TempDir dir;
  { std::ofstream(dir / "local.bin", std::ios::binary) << "abc"; }
  const ByteSourceRequest requests[] = {
      {"mem://first", 1}, {(dir / "local.bin").string(), 0}, {"mem://third", 3}};
  const std::vector<std::unique_ptr<ByteSource>> sources = openByteSources(requests);
  ASSERT_EQ(sources.size(), 3u);
  EXPECT_EQ(sources[0]->size(), 5u);  // "first"
  EXPECT_EQ(sources[1]->size(), 3u);  // the file
  EXPECT_EQ(sources[1]->name(), (dir / "local.bin").string());
  EXPECT_EQ(sources[2]->size(), 5u);  // "third"
  EXPECT_EQ(sources[2]->version(), "3");
  ASSERT_EQ(g_asked.size(), 2u);  // one call of the opener, both mem requests, in order
  EXPECT_EQ(g_asked[0].location, "mem://first");
  EXPECT_EQ(g_asked[1].location, "mem://third");
}

TEST(ByteSourceOpener, AnUnknownSchemeIsAnErrorNamingItAndTheKnownOnes) {
  registerMemScheme();
  try {
    (void)openByteSource("gopher://user:secret@host/x.laz");
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("'gopher'"), std::string::npos) << message;
    EXPECT_NE(message.find("mem"), std::string::npos) << message;
    EXPECT_EQ(message.find("secret"), std::string::npos) << "credentials stay out: " << message;
  }
}

TEST(ByteSourceOpener, AMissingLocalFileIsTheFileSourcesError) {
  test::TempDir dir;
  EXPECT_THROW((void)openByteSource((dir / "absent.laz").string()), InputError);
}

}  // namespace
}  // namespace parallax
