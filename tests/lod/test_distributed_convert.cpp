// The distributed conversion's tasks (lod/distributed_tasks.h) run in this process, stage by
// stage: the same bytes as convertToPotree for any number of ranges and groups, tasks that can
// run again, inputs read in ranges (PointStream::restrictTo), and the errors of missing or
// damaged task files.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "core/error.h"
#include "io/ply_writer.h"
#include "io/point_file.h"
#include "lod/distributed_plan.h"
#include "lod/distributed_task_files.h"
#include "lod/distributed_tasks.h"
#include "lod/potree_converter.h"
#include "lod_test_clouds.h"
#include "support/file_bytes.h"
#include "support/temp_dir.h"

namespace parallax::test {
namespace {

OctreeBuildOptions smallChunks() {
  OctreeBuildOptions options;
  options.max_node_points = 300;
  options.max_chunk_points = 700;  // many chunks, so groups hold several
  return options;
}

// Every task of every stage, in order, as the driver runs them; with `until`, the stages before
// that one only.
void runAllTasks(const DistributedPlan& plan, const std::vector<ConvertInput>& inputs,
                 std::string_view until = {}) {
  for (std::string_view stage : distributedStages()) {
    if (stage == until) return;
    const std::size_t parts = distributedStageParts(plan, stage);
    for (std::size_t part = 0; part < parts; ++part) runDistributedTask(plan, inputs, stage, part);
  }
}

struct Inputs {
  TempDir dir;
  std::vector<ConvertInput> inputs;
  Inputs() {
    writePointFile(makeSurfaceCloud(3000, 1), dir / "a.ply");
    writePointFile(makeSurfaceCloud(2000, 7), dir / "b.las");
    PlyWriteOptions ascii;
    ascii.format = PlyFormat::Ascii;
    writePly(makeSurfaceCloud(1500, 3), dir / "c.ply", ascii);
    inputs = {{dir / "a.ply", {}}, {dir / "b.las", {}}, {dir / "c.ply", {}}};
  }
};

TEST(DistributedConvert, WritesTheLocalBytesForAnyNumberOfTasks) {
  Inputs in;
  PotreeConvertOptions local;
  local.build = smallChunks();
  convertToPotree(in.inputs, in.dir / "local" / "octree", local);
  for (std::size_t tasks : {1u, 3u, 8u, 40u}) {
    SCOPED_TRACE("tasks " + std::to_string(tasks));
    const auto root = in.dir / ("tasks" + std::to_string(tasks));
    const DistributedPlan plan =
        makeDistributedPlan(in.inputs, root / "octree", root / "work", smallChunks(), tasks);
    writeDistributedPlan(plan);
    // The ranges cover each input once, in order; all three inputs (PLY binary and ascii,
    // LAS) are split when there are more tasks than inputs.
    std::vector<std::uint64_t> covered(in.inputs.size(), 0);
    for (const InputRange& range : plan.ranges) {
      EXPECT_EQ(range.first, covered[range.input]);
      covered[range.input] = range.last;
    }
    EXPECT_EQ(covered, (std::vector<std::uint64_t>{3000, 2000, 1500}));
    EXPECT_GE(plan.ranges.size(), std::max<std::size_t>(3, tasks * 3 / 4));
    const DistributedPlan read = readDistributedPlan(planPath(root / "work"));
    EXPECT_EQ(read.ranges.size(), plan.ranges.size());
    runAllTasks(read, in.inputs);
    expectSameOctree(in.dir / "local" / "octree", root / "octree");
    EXPECT_GT(distributedStageParts(read, "build"), tasks > 1 ? 1u : 0u);
  }
}

// The local build of `in` (the reference, in local/octree) and the plan of `tasks` tasks for the
// same inputs (to out/octree, work directory work/), written.
DistributedPlan planBesideTheLocalBuild(const Inputs& in, std::size_t tasks) {
  PotreeConvertOptions local;
  local.build = smallChunks();
  convertToPotree(in.inputs, in.dir / "local" / "octree", local);
  DistributedPlan plan = makeDistributedPlan(in.inputs, in.dir / "out" / "octree", in.dir / "work",
                                             smallChunks(), tasks);
  writeDistributedPlan(plan);
  return plan;
}

TEST(DistributedConvert, TasksRunAgainGiveTheSameOctree) {
  Inputs in;
  const DistributedPlan plan = planBesideTheLocalBuild(in, 4);
  runAllTasks(plan, in.inputs);
  // Every task again (a retry after a crash, or a second run of a task Dask thought lost),
  // then the finish again over the finished output.
  runAllTasks(plan, in.inputs);
  expectSameOctree(in.dir / "local" / "octree", in.dir / "out" / "octree");
  // No temporary name is left in the work directory.
  for (const auto& entry : std::filesystem::recursive_directory_iterator(in.dir / "work")) {
    EXPECT_EQ(entry.path().filename().string().find(".tmp-"), std::string::npos) << entry.path();
  }
}

// Whether the build of `group` wrote in place (in a fresh work directory: a part file then).
bool builtInPlace(const DistributedPlan& plan, std::size_t group) {
  const bool placed = readGroupPartHead(groupNodesPath(plan, group)).placed;
  EXPECT_NE(placed, std::filesystem::exists(groupPartPath(plan, group))) << "group " << group;
  return placed;
}

TEST(DistributedConvert, BuildsWriteStraightIntoOctreeBinWhenTheyKnowTheirPlace) {
  Inputs in;
  const DistributedPlan plan = planBesideTheLocalBuild(in, 8);

  // From both ends, as the driver's two lanes run them: each group's neighbours towards its
  // end of the file are done, so every build writes in place and the place stage has no copy.
  runAllTasks(plan, in.inputs, "build");
  const ChunkGroups groups = readChunkGroups(chunksFilePath(plan));
  const std::size_t count = groups.groups.size();
  ASSERT_GT(groups.split, 1u);
  ASSERT_LT(groups.split, count - 1);
  EXPECT_EQ(groups.groups[groups.split].first, topLevelsSplit(groups.chunks));
  for (std::size_t low = 0, high = count; low < groups.split || high > groups.split;) {
    if (low < groups.split) runDistributedTask(plan, in.inputs, "build", low++);
    if (high > groups.split) runDistributedTask(plan, in.inputs, "build", --high);
  }
  for (std::size_t g = 0; g < count; ++g) EXPECT_TRUE(builtInPlace(plan, g)) << "group " << g;
  for (std::size_t g = 0; g < count; ++g) runDistributedTask(plan, in.inputs, "place", g);
  runDistributedTask(plan, in.inputs, "finish", 0);
  expectSameOctree(in.dir / "local" / "octree", in.dir / "out" / "octree");

  // Up from the split: the upper side's groups but the last do not know their place yet and
  // write parts. Once the lower side has run too, the finish copies the parts the place stage
  // did not (none ran here).
  std::filesystem::remove_all(in.dir / "out");
  clearTaskFiles(plan.work_dir);
  runAllTasks(plan, in.inputs, "build");
  for (std::size_t g = groups.split; g < count; ++g)
    runDistributedTask(plan, in.inputs, "build", g);
  for (std::size_t g = 0; g < groups.split; ++g) runDistributedTask(plan, in.inputs, "build", g);
  for (std::size_t g = 0; g < count; ++g) {
    EXPECT_EQ(builtInPlace(plan, g), g < groups.split || g == count - 1) << "group " << g;
  }
  runDistributedTask(plan, in.inputs, "finish", 0);
  expectSameOctree(in.dir / "local" / "octree", in.dir / "out" / "octree");

  // The same with the place stage: it copies the parts and marks them, and the finish copies
  // nothing again.
  std::filesystem::remove_all(in.dir / "out");
  clearTaskFiles(plan.work_dir);
  runAllTasks(plan, in.inputs, "build");
  // Down from the last group: the lower side's groups but the first write parts.
  for (std::size_t g = count; g-- > 0;) runDistributedTask(plan, in.inputs, "build", g);
  for (std::size_t g = 0; g < count; ++g) {
    EXPECT_EQ(builtInPlace(plan, g), g == 0 || g >= groups.split) << "group " << g;
  }
  for (std::size_t g = 0; g < count; ++g) runDistributedTask(plan, in.inputs, "place", g);
  for (std::size_t g = 0; g < count; ++g) {
    EXPECT_EQ(std::filesystem::exists(groupPlacedPath(plan, g)), g > 0 && g < groups.split)
        << "group " << g;
  }
  runDistributedTask(plan, in.inputs, "finish", 0);
  expectSameOctree(in.dir / "local" / "octree", in.dir / "out" / "octree");
}

// Sets the part size a nodes file states (after its 8-byte tag), as a damaged file might.
void statePartBytes(const std::filesystem::path& nodes, std::uint64_t bytes) {
  std::fstream file(nodes, std::ios::in | std::ios::out | std::ios::binary);
  file.seekp(8);
  file.write(reinterpret_cast<const char*>(&bytes), sizeof bytes);
  ASSERT_TRUE(file.good()) << nodes;
}

TEST(DistributedConvert, PartSizesThatCannotFitAreAnErrorEvenWhereTheirSumWrapsAround) {
  Inputs in;
  const DistributedPlan plan = planBesideTheLocalBuild(in, 8);
  runAllTasks(plan, in.inputs, "place");
  const ChunkGroups groups = readChunkGroups(chunksFilePath(plan));
  ASSERT_GE(groups.split, 3u);
  // Group 0's part said to be 2^64 minus group 1's: the two add up to 0 in 64 bits, which
  // would put group 2 at the start of the file, over group 0.
  const std::uint64_t second = readGroupPartHead(groupNodesPath(plan, 1)).part_bytes;
  ASSERT_GT(second, 0u);
  statePartBytes(groupNodesPath(plan, 0), std::uint64_t(0) - second);
  for (const char* stage : {"build", "finish"}) {
    SCOPED_TRACE(stage);
    try {
      runDistributedTask(plan, in.inputs, stage, stage == std::string("build") ? 2 : 0);
      FAIL() << "no error";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find("the groups' parts take more than the chunks'"),
                std::string::npos)
          << e.what();
    }
  }
  EXPECT_FALSE(std::filesystem::exists(in.dir / "out" / "octree"));
}

TEST(DistributedConvert, RangesOfAFileHoldItsPointsInOrder) {
  Inputs in;
  for (const auto& input : in.inputs) {
    SCOPED_TRACE(input.path.string());
    PointStream whole(input.path, {});
    PointCloud all;
    ASSERT_TRUE(whole.next(all, 1u << 20));
    ASSERT_TRUE(whole.canSkip());
    // Ranges that start inside the reader's own 512 KB ranges and at their ends.
    for (auto [first, last] : std::vector<std::pair<std::uint64_t, std::uint64_t>>{
             {0, 1}, {1, 2}, {17, 1001}, {999, all.count}, {all.count, all.count}}) {
      PointStream part(input.path, {}, &whole.quantization());
      part.restrictTo(first, last);
      std::uint64_t at = first;
      PointCloud batch;
      while (part.next(batch, 100)) {
        for (std::uint64_t i = 0; i < batch.count; ++i, ++at) {
          ASSERT_LT(at, last);
          EXPECT_EQ(batch.positions[i].x, all.positions[at].x) << "point " << at;
          EXPECT_EQ(batch.positions[i].z, all.positions[at].z) << "point " << at;
        }
      }
      EXPECT_EQ(at, last);
    }
  }
}

TEST(DistributedConvert, MissingOrDamagedTaskFilesAreNamed) {
  Inputs in;
  const DistributedPlan plan =
      makeDistributedPlan(in.inputs, in.dir / "out" / "octree", in.dir / "work", smallChunks(), 3);
  writeDistributedPlan(plan);
  // The cube before the scans ran.
  try {
    runDistributedTask(plan, in.inputs, "cube", 0);
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("scan/range_0.json"), std::string::npos) << e.what();
  }
  for (std::size_t r = 0; r < plan.ranges.size(); ++r)
    runDistributedTask(plan, in.inputs, "scan", r);
  runDistributedTask(plan, in.inputs, "cube", 0);
  for (std::size_t r = 0; r < plan.ranges.size(); ++r) {
    runDistributedTask(plan, in.inputs, "count", r);
  }
  // A count file cut short.
  const auto count = countFilePath(plan, 1);
  std::filesystem::resize_file(count, std::filesystem::file_size(count) - 5);
  try {
    runDistributedTask(plan, in.inputs, "chunks", 0);
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(count.string() + ": a damaged task file"),
              std::string::npos)
        << e.what();
  }
  // A count that is no whole number (a fuzzed chunks.json: converting 1e36 was undefined).
  const auto chunks = chunksFilePath(plan);
  writeFileAtomically(chunks, R"({"chunks":[["r0",5]],"groups":[[0,1e36]],"split":0})");
  try {
    readChunkGroups(chunks);
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(chunks.string() + ": a damaged task file"),
              std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("1e+36 where a whole number"), std::string::npos)
        << e.what();
  }
  EXPECT_THROW(runDistributedTask(plan, in.inputs, "scan", plan.ranges.size()),
               std::invalid_argument);
  EXPECT_THROW(runDistributedTask(plan, in.inputs, "sort", 0), std::invalid_argument);
  EXPECT_FALSE(std::filesystem::exists(in.dir / "out" / "octree"));
}

TEST(DistributedConvert, APlanThatIsNotOneIsAnInputError) {
  TempDir dir;
  std::ofstream(dir / "plan.json") << R"({"format": "parallax-convert-plan", "version": 1})";
  try {
    readDistributedPlan(dir / "plan.json");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("plan.json"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("conversion plan"), std::string::npos) << e.what();
  }
  EXPECT_THROW(readDistributedPlan(dir / "missing.json"), InputError);
}

}  // namespace
}  // namespace parallax::test
