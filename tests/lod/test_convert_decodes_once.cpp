// The octree builder decodes each point of a slow input once (lod/point_spill.h): the scan keeps
// the decoded points for the count and distribute passes, in memory or in a scratch file, and
// the octree is the one the input's cheaply reread twin gives.
#include <gtest/gtest.h>

#include <atomic>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>

#include "core/error.h"
#include "io/point_file.h"
#include "io/point_format.h"
#include "lod/convert_stages.h"
#include "lod/potree_converter.h"
#include "lod_test_clouds.h"
#include "support/file_bytes.h"
#include "support/temp_dir.h"

namespace parallax::test {
namespace {

std::vector<std::string> namesIn(const std::filesystem::path& dir) {
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(dir))
    names.push_back(std::filesystem::relative(entry.path(), dir).string());
  std::sort(names.begin(), names.end());
  return names;
}

TEST(ConvertDecodesOnce, LazGivesTheOctreeOfItsLasTwin) {
  TempDir dir;
  const PointCloud cloud = makeLasLikeCloud(30'000, 19);
  writePointFile(cloud, dir / "in.las");
  writePointFile(cloud, dir / "in.laz");
  const auto las = convertToPotree({{dir / "in.las", {}}}, dir / "from_las", smallChunks());
  const auto laz = convertToPotree({{dir / "in.laz", {}}}, dir / "from_laz", smallChunks());
  // LAS is read again by each pass; the LAZ's decoded points are kept, here all in memory.
  EXPECT_EQ(las.kept_points, 0u);
  EXPECT_EQ(laz.kept_points, 30'000u);
  EXPECT_GT(laz.kept_memory_bytes, 30'000u * 12u);
  EXPECT_EQ(laz.kept_file_bytes, 0u);
  EXPECT_GT(laz.chunks, 4u);
  expectSameOctree(dir / "from_las", dir / "from_laz");
  // Nothing of the scratch is left beside the octree.
  EXPECT_EQ(namesIn(dir / "from_laz"),
            (std::vector<std::string>{"hierarchy.bin", "metadata.json", "octree.bin"}));
}

TEST(ConvertDecodesOnce, SmallMemorySpillsToAScratchFileAndGivesTheSameOctree) {
  TempDir dir;
  const PointCloud cloud = makeLasLikeCloud(60'000, 19);
  writePointFile(cloud, dir / "in.laz");
  const auto roomy = convertToPotree({{dir / "in.laz", {}}}, dir / "roomy", smallChunks());
  EXPECT_EQ(roomy.kept_file_bytes, 0u);

  PotreeConvertOptions tight = smallChunks();
  tight.build.memory_bytes = 1u << 20;  // 512 KB for kept points: most go to the file
  const std::filesystem::path partial = partialPathFor(dir / "tight");
  bool saw_scratch_file = false;
  tight.progress = [&](const std::string& stage, std::uint64_t) -> std::unique_ptr<Progress> {
    if (stage == "distributing") {
      saw_scratch_file = std::filesystem::exists(partial / "decoded" / "decoded-0.columns");
    }
    return nullptr;
  };
  const auto spilled = convertToPotree({{dir / "in.laz", {}}}, dir / "tight", tight);
  EXPECT_TRUE(saw_scratch_file);
  EXPECT_EQ(spilled.kept_points, 60'000u);
  EXPECT_LE(spilled.kept_memory_bytes, 512u << 10);
  EXPECT_GT(spilled.kept_file_bytes, 60'000u * 12u);
  EXPECT_EQ(spilled.kept_memory_bytes + spilled.kept_file_bytes, roomy.kept_memory_bytes);
  expectSameOctree(dir / "roomy", dir / "tight");
  EXPECT_EQ(namesIn(dir / "tight"),
            (std::vector<std::string>{"hierarchy.bin", "metadata.json", "octree.bin"}));
  EXPECT_FALSE(std::filesystem::exists(partial));
}

TEST(ConvertDecodesOnce, AFailureRemovesTheScratchFile) {
  TempDir dir;
  writePointFile(makeLasLikeCloud(40'000, 19), dir / "in.laz");
  PotreeConvertOptions options = smallChunks();
  options.build.memory_bytes = 1u << 20;
  const std::filesystem::path partial = partialPathFor(dir / "out");
  bool saw_scratch_file = false;
  // Fails between the count and the distribute pass, while the scratch file is there.
  options.progress = [&](const std::string& stage, std::uint64_t) -> std::unique_ptr<Progress> {
    if (stage == "distributing") {
      saw_scratch_file = std::filesystem::exists(partial / "decoded" / "decoded-0.columns");
      throw std::runtime_error("stopped by the test");
    }
    return nullptr;
  };
  EXPECT_THROW(convertToPotree({{dir / "in.laz", {}}}, dir / "out", options), std::runtime_error);
  EXPECT_TRUE(saw_scratch_file);
  EXPECT_EQ(namesIn(dir.path()), std::vector<std::string>{"in.laz"});
}

// A format of this test alone ("PXONCE1\n", a uint64 count, int32 x, y, z per point, in
// millimetres), whose reader counts the points it decodes and refuses a second reading of a
// file: its row says nothing of rereading cheaply, as a compressed format would.
constexpr char kOnceMagic[] = "PXONCE1\n";
const Quantization kMillimetres{{0.001, 0.001, 0.001}, {0, 0, 0}};
std::atomic<std::uint64_t> g_decoded_points{0};
std::map<std::string, int>& opensByFile() {
  static std::map<std::string, int> opens;
  return opens;
}

class OnceSource final : public PointChunkSource {
 public:
  explicit OnceSource(const std::filesystem::path& path) : bytes_(fileBytes(path)) {
    if (++opensByFile()[path.string()] > 1) {
      throw InputError(
          {.file = path.string(), .expected = "to be read once", .found = "a second reading"});
    }
    std::memcpy(&count_, bytes_.data() + 8, 8);
  }
  std::uint64_t pointCount() const override { return count_; }
  const Quantization& quantization() const override { return kMillimetres; }
  bool next(PointCloud& chunk, std::size_t max_points) override {
    const std::uint64_t n = std::min<std::uint64_t>(max_points, count_ - next_);
    chunk = PointCloud{};
    if (n == 0) return false;  // and no memcpy from past the end (UBSan: null source)
    chunk.count = n;
    chunk.quantization = kMillimetres;
    chunk.positions = Column<Int3>(n);
    std::memcpy(chunk.positions.data(), bytes_.data() + 16 + next_ * 12, n * 12);
    chunk.computeBounds();
    next_ += n;
    g_decoded_points += n;
    return true;
  }

 private:
  std::string bytes_;
  std::uint64_t count_ = 0;
  std::uint64_t next_ = 0;
};

void registerOnceFormat() {
  static const bool registered = [] {
    PointFormatEntry row;
    row.id = "pxonce";
    row.name = "read-once test format";
    row.description = "read-once test format (.pxonce)";
    row.extensions = {".pxonce"};
    row.detect = [](std::span<const std::byte> head) {
      return head.size() >= 8 && std::memcmp(head.data(), kOnceMagic, 8) == 0;
    };
    row.open_chunks = [](const std::filesystem::path& path, const ChunkSourceOptions&) {
      return std::unique_ptr<PointChunkSource>(std::make_unique<OnceSource>(path));
    };
    registerPointFormat(std::move(row));
    return true;
  }();
  (void)registered;
}

void writeOnceFile(const PointCloud& cloud, const std::filesystem::path& path) {
  std::ofstream out(path, std::ios::binary);
  out.write(kOnceMagic, 8);
  out.write(reinterpret_cast<const char*>(&cloud.count), 8);
  for (std::uint64_t i = 0; i < cloud.count; ++i) {
    for (int axis = 0; axis < 3; ++axis) {
      const double world = cloud.quantization.toWorld(axis, (&cloud.positions[i].x)[axis]);
      const std::int32_t mm = kMillimetres.toQuantized(axis, world);
      out.write(reinterpret_cast<const char*>(&mm), 4);
    }
  }
}

TEST(ConvertDecodesOnce, EachPointOfASlowInputIsDecodedOnce) {
  registerOnceFormat();
  TempDir dir;
  const PointCloud cloud = makeSurfaceCloud(25'000);
  writeOnceFile(cloud, dir / "a.pxonce");
  writeOnceFile(makeSurfaceCloud(15'000, 7), dir / "b.pxonce");
  g_decoded_points = 0;
  PotreeConvertOptions options = smallChunks();
  options.build.memory_bytes = 1u << 20;  // both kinds of keeping: memory, then the file
  const auto result =
      convertToPotree({{dir / "a.pxonce", {}}, {dir / "b.pxonce", {}}}, dir / "out", options);
  EXPECT_EQ(result.points, 40'000u);
  EXPECT_EQ(result.kept_points, 40'000u);
  EXPECT_EQ(g_decoded_points.load(), 40'000u);
  EXPECT_EQ(opensByFile()[(dir / "a.pxonce").string()], 1);
  EXPECT_EQ(opensByFile()[(dir / "b.pxonce").string()], 1);

  // The same passes reading the file again (no scratch directory: nothing kept) are refused by
  // this reader: the check above would have seen a second decoding.
  writeOnceFile(cloud, dir / "c.pxonce");
  ConvertPlan plan = scanInputs({{dir / "c.pxonce", {}}}, options.build, nullptr);
  EXPECT_THROW(countChunks(plan, {{dir / "c.pxonce", {}}}, nullptr), InputError);
}

}  // namespace
}  // namespace parallax::test
