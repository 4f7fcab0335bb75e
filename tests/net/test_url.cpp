// URLs as the command line gives them, and Content-Range as servers send it.
#include <gtest/gtest.h>

#include "core/error.h"
#include "core/url.h"
#include "lod/octree_url.h"
#include "lod/potree_reader.h"
#include "net/http_client.h"

namespace parallax {
namespace {

TEST(Url, RecognisesHttpAndHttpsOnly) {
  EXPECT_TRUE(isHttpUrl("http://example.com/cloud/"));
  EXPECT_TRUE(isHttpUrl("HTTPS://example.com"));
  EXPECT_FALSE(isHttpUrl("http://"));
  EXPECT_FALSE(isHttpUrl("http:///path"));
  EXPECT_FALSE(isHttpUrl("ftp://example.com/x"));
  EXPECT_FALSE(isHttpUrl("/data/http://x"));
  EXPECT_FALSE(isHttpUrl("cloud.ply"));
}

TEST(Url, SplitsTheQueryAndDropsTheFragment) {
  const UrlParts parts = splitUrl("https://h/c/metadata.json?sig=a/b#top");
  EXPECT_EQ(parts.base, "https://h/c/metadata.json");
  EXPECT_EQ(parts.query, "?sig=a/b");
  EXPECT_EQ(splitUrl("http://h?x").base, "http://h");
  EXPECT_EQ(urlFileName("https://h/c/metadata.json?sig=a/b"), "metadata.json");
  EXPECT_EQ(urlFileName("https://h/c/"), "");
  EXPECT_EQ(urlFileName("https://h"), "");
}

TEST(Url, AFilesExtensionIsThatOfItsNameWithoutTheQuery) {
  EXPECT_EQ(fileExtensionOf("https://h/c/scan.pcd?X-Amz-Signature=a.b&x=1#top"), ".pcd");
  EXPECT_EQ(fileExtensionOf("http://h/c/scan.PTS#part.2"), ".PTS");
  EXPECT_EQ(fileExtensionOf("http://h.example.com/c/"), "");
  EXPECT_EQ(fileExtensionOf("http://h.example.com?x.las"), "");
  EXPECT_EQ(fileExtensionOf("/data/v1.2/scan.laz"), ".laz");
  EXPECT_EQ(fileExtensionOf("/data/v1.2/scan"), "");
}

TEST(Url, CredentialsNeverReachAMessage) {
  EXPECT_EQ(urlForMessages("https://user:secret@h:8443/c/?q=1"), "https://h:8443/c/?q=1");
  EXPECT_EQ(urlForMessages("http://h/a@b"), "http://h/a@b");
  EXPECT_EQ(urlForMessages("me@host/dir"), "me@host/dir") << "a path is not a URL";
}

TEST(Url, WhatAnOctreeUrlNames) {
  EXPECT_EQ(octreeUrlKind("/local/dir"), OctreeUrlKind::NotUrl);
  EXPECT_EQ(octreeUrlKind("http://h/cloud"), OctreeUrlKind::Potree);
  EXPECT_EQ(octreeUrlKind("http://h/cloud/"), OctreeUrlKind::Potree);
  EXPECT_EQ(octreeUrlKind("http://h/cloud/metadata.json?t=1"), OctreeUrlKind::Potree);
  EXPECT_EQ(octreeUrlKind("http://h/a/Tile.COPC.LAZ"), OctreeUrlKind::Copc);
  EXPECT_EQ(octreeUrlKind("http://h/a/scan.ply"), OctreeUrlKind::Other);
  EXPECT_EQ(octreeUrlKind("http://h/a/v1.2/"), OctreeUrlKind::Potree);
  EXPECT_TRUE(isPotreeDirectory("http://h/cloud/"));
  EXPECT_FALSE(isPotreeDirectory("http://h/cloud.las"));
  EXPECT_EQ(potreeFileLocation("http://h/c/metadata.json?s=1", "octree.bin"),
            "http://h/c/octree.bin?s=1");
  EXPECT_EQ(potreeFileLocation("http://h/c", "hierarchy.bin"), "http://h/c/hierarchy.bin");
  EXPECT_EQ(potreeFileLocation("/d/c/metadata.json", "octree.bin"), "/d/c/octree.bin");
}

TEST(Url, OctreeUrlsAreCheckedBeforeAnyRequest) {
  EXPECT_NO_THROW(checkOctreeUrl("https://h/tiles/a.copc.laz"));
  EXPECT_NO_THROW(checkOctreeUrl("http://h/cloud/"));
  EXPECT_NO_THROW(checkOctreeUrl("scan.laz"));
  try {
    checkOctreeUrl("https://user:pw@h/a/scan.laz");
    FAIL() << "no error";
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("https://h/a/scan.laz"), std::string::npos) << message;
    EXPECT_NE(message.find("only octrees stream over HTTP"), std::string::npos) << message;
    EXPECT_EQ(message.find("pw"), std::string::npos) << message;
  }
}

TEST(ContentRange, ParsesWhatServersSend) {
  auto r = parseContentRange("bytes 0-99/1234");
  ASSERT_TRUE(r && r->range && r->total);
  EXPECT_EQ(*r->range, (ByteRange{0, 100}));
  EXPECT_EQ(*r->total, 1234u);
  r = parseContentRange("Bytes 10-10/*");
  ASSERT_TRUE(r && r->range);
  EXPECT_EQ(*r->range, (ByteRange{10, 1}));
  EXPECT_FALSE(r->total);
  r = parseContentRange("bytes */0");
  ASSERT_TRUE(r && r->total);
  EXPECT_EQ(*r->total, 0u);
  EXPECT_FALSE(r->range);
}

TEST(ContentRange, RefusesWhatIsNotARange) {
  for (const char* bad : {"", "bytes", "bytes 5-4/10", "bytes 0-10/10", "bytes */*", "items 0-1/2",
                          "bytes 0-x/10", "bytes 0-18446744073709551615/*", "bytes -1-5/10"}) {
    EXPECT_FALSE(parseContentRange(bad)) << bad;
  }
}

}  // namespace
}  // namespace parallax
