// The byte-source interface's local sources (core/byte_source.h): exact bytes, ranges past the
// end named with the caller's element, a missing file named, a version that tells files apart.
#include "core/byte_source.h"

#include <gtest/gtest.h>

#include <functional>
#include <string>

#include "core/error.h"
#include "support/temp_dir.h"

namespace parallax {
namespace {

std::string errorOf(const std::function<void()>& action) {
  try {
    action();
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(ByteSource, FileReadsExactRanges) {
  test::TempDir dir;
  const auto path = dir.write("data.bin", "0123456789abcdef");
  const auto source = openFileSource(path);
  EXPECT_EQ(source->size(), 16u);
  EXPECT_EQ(source->name(), path.string());
  EXPECT_TRUE(source->local());
  std::string out(5, '\0');
  source->read(10, std::as_writable_bytes(std::span(out)));
  EXPECT_EQ(out, "abcde");
  const auto all = source->readAll();
  EXPECT_EQ(std::string(reinterpret_cast<const char*>(all.data()), all.size()), "0123456789abcdef");
  source->prefetch(std::vector<ByteRange>{{0, 4}});  // a hint: nothing happens, nothing breaks
}

TEST(ByteSource, RangesPastTheEndNameTheElement) {
  test::TempDir dir;
  const auto source = openFileSource(dir.write("data.bin", "0123456789"));
  std::vector<std::byte> out(4);
  const std::string message = errorOf([&] { source->read(8, out, {.element = "node r042"}); });
  EXPECT_NE(message.find("data.bin"), std::string::npos) << message;
  EXPECT_NE(message.find("byte offset 8"), std::string::npos) << message;
  EXPECT_NE(message.find("node r042"), std::string::npos) << message;
  EXPECT_NE(message.find("past its end"), std::string::npos) << message;
  const auto memory = makeMemorySource(std::vector<std::byte>(3), "mem/x.bin");
  EXPECT_NE(errorOf([&] { memory->read(2, out); }).find("mem/x.bin"), std::string::npos);
}

TEST(ByteSource, MissingAndSpecialFiles) {
  test::TempDir dir;
  const std::string missing = errorOf([&] { openFileSource(dir / "none.bin"); });
  EXPECT_NE(missing.find("none.bin"), std::string::npos) << missing;
  EXPECT_NE(missing.find("No such file"), std::string::npos) << missing;
  const std::string folder = errorOf([&] { openFileSource(dir.path()); });
  EXPECT_NE(folder.find("a regular file"), std::string::npos) << folder;
}

TEST(ByteSource, TheVersionChangesWithTheFile) {
  test::TempDir dir;
  const auto path = dir.write("data.bin", "first");
  const std::string before = openFileSource(path)->version();
  EXPECT_FALSE(before.empty());
  EXPECT_EQ(openFileSource(path)->version(), before);
  dir.write("data.bin", "second!");
  EXPECT_NE(openFileSource(path)->version(), before);
}

TEST(ByteSource, AFileThatShrankWhileReadIsAnError) {
  test::TempDir dir;
  const auto path = dir.write("data.bin", std::string(100, 'x'));
  const auto source = openFileSource(path);
  std::filesystem::resize_file(path, 10);
  std::vector<std::byte> out(50);
  const std::string message = errorOf([&] { source->read(0, out, {.element = "node r"}); });
  EXPECT_NE(message.find("shrank"), std::string::npos) << message;
}

}  // namespace
}  // namespace parallax
