// Partial outputs (io/partial_output.h): their names, and which ones a cleanup removes (the
// process in the name is gone) or leaves (it is alive).
#include "io/partial_output.h"

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <string>

#include "io/point_file.h"
#include "support/temp_dir.h"

namespace parallax {
namespace {

// The id of a process that has ended (a child started and reaped).
pid_t deadPid() {
  const pid_t child = ::fork();
  if (child == 0) ::_exit(0);
  int status = 0;
  ::waitpid(child, &status, 0);
  return child;
}

std::string partialName(const std::string& target, pid_t pid, const std::string& suffix = "") {
  return "." + target + ".partial-" + std::to_string(pid) + (suffix.empty() ? "" : "-" + suffix);
}

TEST(PartialOutput, NamesAreHiddenBesideTheTargetWithThisProcessId) {
  const std::string pid = std::to_string(::getpid());
  EXPECT_EQ(partialOutputPath("/data/scan.ply"), "/data/.scan.ply.partial-" + pid);
  EXPECT_EQ(partialOutputPath("/data/octree/"), "/data/.octree.partial-" + pid);
  EXPECT_EQ(partialOutputPath("out/a.las", "3"), "out/.a.las.partial-" + pid + "-3");
  const auto first = newPartialFilePath("x.ply"), second = newPartialFilePath("x.ply");
  EXPECT_NE(first, second);
  EXPECT_EQ(first.string().rfind(".x.ply.partial-" + pid + "-", 0), 0u) << first;
}

TEST(PartialOutput, RemovesOnlyThoseWhoseProcessIsGone) {
  test::TempDir dir;
  const pid_t dead = deadPid();
  ASSERT_FALSE(processIsAlive(dead));
  ASSERT_TRUE(processIsAlive(::getpid()));
  // A killed octree conversion (a directory with files) and a killed file writer.
  std::filesystem::create_directories(dir / partialName("scan", dead) / "chunks");
  dir.write(partialName("scan", dead) + "/chunks/0.bin", std::string(1000, 'a'));
  dir.write(partialName("scan", dead) + "/octree.bin", std::string(234, 'b'));
  dir.write(partialName("scan", dead, "7"), std::string(55, 'c'));
  // This process is alive: its partial output stays.
  dir.write(partialName("scan", ::getpid()), std::string(10, 'd'));
  // Not partial outputs of "scan": other names, and names that only look alike.
  dir.write(partialName("scan2", dead), "e");
  dir.write(".scan.partial-", "f");
  dir.write(".scan.partial-12x", "g");
  dir.write("scan", "the target itself");

  const PartialCleanup cleanup = removeStalePartialOutputs(dir / "scan");
  ASSERT_EQ(cleanup.removed.size(), 2u);
  EXPECT_EQ(cleanup.removed[0].path, dir / partialName("scan", dead));
  EXPECT_EQ(cleanup.removed[0].bytes, 1234u);
  EXPECT_EQ(cleanup.removed[0].pid, dead);
  EXPECT_EQ(cleanup.removed[1].path, dir / partialName("scan", dead, "7"));
  EXPECT_EQ(cleanup.removed[1].bytes, 55u);
  EXPECT_EQ(cleanup.freed_bytes, 1289u);
  ASSERT_EQ(cleanup.running.size(), 1u);
  EXPECT_EQ(cleanup.running[0].pid, ::getpid());
  EXPECT_FALSE(std::filesystem::exists(dir / partialName("scan", dead)));
  EXPECT_FALSE(std::filesystem::exists(dir / partialName("scan", dead, "7")));
  for (const std::string& kept :
       {partialName("scan", ::getpid()), partialName("scan2", dead), std::string(".scan.partial-"),
        std::string(".scan.partial-12x"), std::string("scan")}) {
    EXPECT_TRUE(std::filesystem::exists(dir / kept)) << kept;
  }
  // Nothing left to do the second time; a missing folder is not an error.
  EXPECT_TRUE(removeStalePartialOutputs(dir / "scan").removed.empty());
  EXPECT_TRUE(removeStalePartialOutputs(dir / "missing" / "scan").removed.empty());
}

TEST(PartialOutput, WritersUseThePartialNameAndLeaveNothingOnSuccess) {
  test::TempDir dir;
  PointCloud cloud;
  cloud.count = 1;
  cloud.positions = Column<Int3>(1);
  cloud.positions[0] = {1, 2, 3};
  for (const char* name : {"a.ply", "a.las", "a.xyz"}) {
    writePointFile(cloud, dir / name);
    EXPECT_TRUE(findPartialOutputs(dir / name).empty()) << name;
    EXPECT_TRUE(std::filesystem::exists(dir / name)) << name;
  }
}

TEST(PartialOutput, BytesAreFormattedForPeople) {
  EXPECT_EQ(formatBytes(512), "512 bytes");
  EXPECT_EQ(formatBytes(12'345), "12.3 kB");
  EXPECT_EQ(formatBytes(12'000'000), "12.0 MB");
  EXPECT_EQ(formatBytes(1'400'000'000), "1.4 GB");
}

}  // namespace
}  // namespace parallax
