// A format added through the format table alone (io/point_format.h: registerPointFormat), with
// no line of Parallax changed for it: `info`, `convert` (both ways), `render` and the octree
// builder all take it. The command line runs in this process (parallax_cli), where the toy row
// is registered.
//
// The toy format: "PXTOY1\n", a little-endian uint64 count, then per point int32 x, y, z in
// millimetres and a uint8 class (13 bytes a point).
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <mutex>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "commands.h"
#include "core/error.h"
#include "io/point_file.h"
#include "io/point_format.h"
#include "lod/octree_node_batches.h"
#include "lod/potree_reader.h"
#include "render/image_file.h"
#include "support/temp_dir.h"

namespace parallax {
namespace {

constexpr char kMagic[] = "PXTOY1\n";
constexpr std::size_t kMagicBytes = 7;
constexpr std::size_t kHeaderBytes = kMagicBytes + 8;
constexpr std::size_t kRecordBytes = 13;
const Quantization kMillimetres{{0.001, 0.001, 0.001}, {0, 0, 0}};

std::vector<char> fileBytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::uint64_t toyCount(const std::vector<char>& bytes, const std::filesystem::path& path) {
  if (bytes.size() < kHeaderBytes) {
    throw InputError({.file = path.string(), .expected = "a toy header", .found = "less"});
  }
  std::uint64_t count = 0;
  std::memcpy(&count, bytes.data() + kMagicBytes, 8);
  if (count > (bytes.size() - kHeaderBytes) / kRecordBytes) {
    throw InputError({.file = path.string(),
                      .byte_offset = kMagicBytes,
                      .expected = "a count the file holds",
                      .found = std::to_string(count)});
  }
  return count;
}

// Points [first, first + n) of the file's records.
PointCloud toyPoints(const std::vector<char>& bytes, std::uint64_t first, std::uint64_t n) {
  PointCloud cloud;
  cloud.count = n;
  cloud.quantization = kMillimetres;
  cloud.positions = Column<Int3>(n);
  cloud.classification = Column<std::uint8_t>(n);
  for (std::uint64_t i = 0; i < n; ++i) {
    const char* record = bytes.data() + kHeaderBytes + (first + i) * kRecordBytes;
    std::memcpy(&cloud.positions[i], record, 12);
    std::memcpy(&cloud.classification[i], record + 12, 1);
  }
  cloud.computeBounds();
  return cloud;
}

class ToyChunkSource final : public PointChunkSource {
 public:
  explicit ToyChunkSource(const std::filesystem::path& path)
      : bytes_(fileBytes(path)), count_(toyCount(bytes_, path)) {}
  std::uint64_t pointCount() const override { return count_; }
  const Quantization& quantization() const override { return kMillimetres; }
  bool next(PointCloud& chunk, std::size_t max_points) override {
    const std::uint64_t n = std::min<std::uint64_t>(max_points, count_ - next_);
    chunk = toyPoints(bytes_, next_, n);
    next_ += n;
    return n > 0;
  }
  bool canSkip() const override { return true; }
  void skip(std::uint64_t count) override { next_ += std::min(count, count_ - next_); }

 private:
  std::vector<char> bytes_;
  std::uint64_t count_ = 0;
  std::uint64_t next_ = 0;
};

void writeToy(const PointCloud& cloud, const std::filesystem::path& path,
              const PointWriteOptions&) {
  OutputFile out(path);
  out.write(kMagic, kMagicBytes);
  out.write(&cloud.count, 8);
  for (std::size_t i = 0; i < cloud.count; ++i) {
    std::array<std::int32_t, 3> mm;
    for (int axis = 0; axis < 3; ++axis) {
      const double world = cloud.quantization.toWorld(axis, (&cloud.positions[i].x)[axis]);
      mm[std::size_t(axis)] = kMillimetres.toQuantized(axis, world);
    }
    const std::uint8_t cls = cloud.hasClassification() ? cloud.classification[i] : 0;
    out.write(mm.data(), 12);
    out.write(&cls, 1);
  }
  out.commit();
}

PointFormatEntry toyRow() {
  PointFormatEntry row;
  row.id = "toy";
  row.name = "toy";
  row.description = "toy (a test's own format; .toy)";
  row.extensions = {".toy"};
  row.detect = [](std::span<const std::byte> head) {
    return head.size() >= kMagicBytes && std::memcmp(head.data(), kMagic, kMagicBytes) == 0;
  };
  row.header = [](const std::filesystem::path& path) {
    PointFileHeader header;
    header.point_count = toyCount(fileBytes(path), path);
    header.attributes = {"x", "y", "z", "classification"};
    return header;
  };
  row.read = [](const std::filesystem::path& path, const PointReadOptions&) {
    const std::vector<char> bytes = fileBytes(path);
    return toyPoints(bytes, 0, toyCount(bytes, path));
  };
  row.open_chunks = [](const std::filesystem::path& path, const ChunkSourceOptions&) {
    return std::unique_ptr<PointChunkSource>(std::make_unique<ToyChunkSource>(path));
  };
  row.write = writeToy;
  row.write_losses = [](const PointCloud& cloud, const std::filesystem::path&,
                        const PointWriteOptions&) {
    std::vector<std::string> losses;
    if (cloud.hasColors()) losses.push_back("colours (toy has none)");
    return losses;
  };
  return row;
}

void registerToyOnce() {
  static std::once_flag once;
  std::call_once(once, [] { registerPointFormat(toyRow()); });
}

// A small hill of points in millimetres, classes 1 to 6, far from the origin as real data is.
PointCloud hill(std::size_t side) {
  PointCloud cloud;
  cloud.count = side * side;
  cloud.quantization = kMillimetres;
  cloud.quantization.offset = {500000.0, 600000.0, 0.0};
  cloud.positions = Column<Int3>(cloud.count);
  cloud.classification = Column<std::uint8_t>(cloud.count);
  for (std::size_t i = 0; i < cloud.count; ++i) {
    const std::int32_t x = std::int32_t(i % side) * 250;
    const std::int32_t y = std::int32_t(i / side) * 250;
    const std::int32_t z =
        10000 - (x - 5000) * (x - 5000) / 20000 - (y - 5000) * (y - 5000) / 20000;
    cloud.positions[i] = {x, y, z};
    cloud.classification[i] = std::uint8_t(1 + i % 6);
  }
  cloud.computeBounds();
  return cloud;
}

struct CommandRun {
  int exit_code = 0;
  std::string out;
};

CommandRun parallaxHere(std::vector<std::string> args) {
  args.insert(args.begin(), "parallax");
  std::vector<char*> argv;
  for (std::string& arg : args) argv.push_back(arg.data());
  testing::internal::CaptureStdout();
  CommandRun run;
  run.exit_code = cli::runCommandLine(int(argv.size()), argv.data());
  run.out = testing::internal::GetCapturedStdout();
  return run;
}

void expectSamePoints(const PointCloud& a, const PointCloud& b) {
  ASSERT_EQ(a.count, b.count);
  ASSERT_TRUE(b.hasClassification());
  for (std::size_t i = 0; i < a.count; ++i) {
    ASSERT_DOUBLE_EQ(a.worldX(i), b.worldX(i)) << "point " << i;
    ASSERT_DOUBLE_EQ(a.worldY(i), b.worldY(i)) << "point " << i;
    ASSERT_DOUBLE_EQ(a.worldZ(i), b.worldZ(i)) << "point " << i;
    ASSERT_EQ(a.classification[i], b.classification[i]) << "point " << i;
  }
}

// docs/FORMATS.md's list of formats is the table's (`parallax info --formats`): the built-in
// rows, whatever this test adds.
TEST(FormatTable, TheDocsListIsTheTable) {
  std::ifstream in(std::filesystem::path(PARALLAX_SOURCE_DIR) / "docs" / "FORMATS.md");
  const std::string docs{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  const std::string begin = "<!-- parallax info --formats -->\n";
  const std::size_t from = docs.find(begin);
  const std::size_t to = docs.find("<!-- end of parallax info --formats -->");
  ASSERT_NE(from, std::string::npos);
  ASSERT_NE(to, std::string::npos);
  std::string table;
  std::istringstream lines(pointFormatsMarkdown());
  for (std::string line; std::getline(lines, line);) {
    if (line.find("| `toy` |") == std::string::npos) table += line + "\n";
  }
  EXPECT_EQ(docs.substr(from + begin.size(), to - from - begin.size()), table)
      << "docs/FORMATS.md: paste `parallax info --formats` between the markers";
}

TEST(ToyFormat, TheTableDetectsReadsAndWritesIt) {
  registerToyOnce();
  test::TempDir dir;
  const PointCloud cloud = hill(40);
  writePointFile(cloud, dir / "hill.toy");  // by its extension
  EXPECT_EQ(detectPointFormat(dir / "hill.toy"), PointFormat("toy"));
  EXPECT_EQ(formatForExtension(dir / "x.TOY"), PointFormat("toy"));
  EXPECT_EQ(headerPointCount(dir / "hill.toy"), 1600u);
  EXPECT_NE(supportedFormatsText().find("toy (a test's own format; .toy)"), std::string::npos);
  EXPECT_NE(pointFormatsMarkdown().find("`toy`"), std::string::npos);
  EXPECT_THROW(registerPointFormat(toyRow()), std::invalid_argument);  // ids are unique
  expectSamePoints(cloud, readPointFile(dir / "hill.toy"));
  // No preview: the table says so, and the preview reader names the formats that have one.
  EXPECT_FALSE(hasPointFilePreview(PointFormat("toy")));
  EXPECT_THROW(readPointFilePreview(dir / "hill.toy", 10), InputError);
}

TEST(ToyFormat, InfoDescribesIt) {
  registerToyOnce();
  test::TempDir dir;
  const PointCloud cloud = hill(40);
  writePointFile(cloud, dir / "hill.toy");
  const CommandRun run = parallaxHere({"info", "--json", "-q", (dir / "hill.toy").string()});
  ASSERT_EQ(run.exit_code, 0);
  const auto json = nlohmann::json::parse(run.out);
  EXPECT_EQ(json["format"], "toy");
  EXPECT_EQ(json["points"], 1600);
  EXPECT_DOUBLE_EQ(json["bounds"]["min"][0].get<double>(), 500000.0);
  EXPECT_DOUBLE_EQ(json["bounds"]["max"][0].get<double>(), 500009.75);
  EXPECT_DOUBLE_EQ(json["bounds"]["max"][2].get<double>(), 10.0);
  EXPECT_EQ(json["attribute_ranges"]["classification"]["min"], 1);
  EXPECT_EQ(json["attribute_ranges"]["classification"]["max"], 6);
  // And the list of formats, which docs/FORMATS.md holds, lists it.
  const CommandRun formats = parallaxHere({"info", "--formats"});
  EXPECT_NE(formats.out.find("| toy (a test's own format; .toy) | `toy` | `.toy` |"),
            std::string::npos)
      << formats.out;
}

TEST(ToyFormat, ConvertTakesItInAndOut) {
  registerToyOnce();
  test::TempDir dir;
  const PointCloud cloud = hill(40);
  writePointFile(cloud, dir / "hill.toy");
  ASSERT_EQ(parallaxHere(
                {"convert", "-q", (dir / "hill.toy").string(), "-o", (dir / "hill.las").string()})
                .exit_code,
            0);
  expectSamePoints(cloud, readPointFile(dir / "hill.las"));
  ASSERT_EQ(parallaxHere(
                {"convert", "-q", (dir / "hill.las").string(), "-o", (dir / "back.toy").string()})
                .exit_code,
            0);
  expectSamePoints(cloud, readPointFile(dir / "back.toy"));
  // A filter on the way: the clip box keeps the points of x <= 500005 m (21 columns of 40).
  ASSERT_EQ(
      parallaxHere({"convert", "-q", (dir / "hill.toy").string(), "-o", (dir / "cut.toy").string(),
                    "--clip-box", "499999,599999,-1,500005,600011,11"})
          .exit_code,
      0);
  EXPECT_EQ(readPointFile(dir / "cut.toy").count, 21u * 40u);
}

TEST(ToyFormat, TheOctreeBuilderTakesIt) {
  registerToyOnce();
  test::TempDir dir;
  const PointCloud cloud = hill(60);
  writePointFile(cloud, dir / "hill.toy");
  ASSERT_EQ(parallaxHere({"convert", "-q", (dir / "hill.toy").string(), "-o",
                          (dir / "octree").string() + "/"})
                .exit_code,
            0);
  // Every point once (additive LOD), classes kept: the nodes' points together are the cloud's.
  std::unique_ptr<Octree> octree = openPotree(dir / "octree");
  expandWholeOctree(*octree);
  EXPECT_EQ(octree->info().point_count, 3600u);
  std::uint64_t points = 0;
  std::array<std::uint64_t, 7> per_class{};
  for (const auto& node : octree->nodes()) {
    const PointCloud points_of_node = octree->loadNode(node);
    points += points_of_node.count;
    for (std::size_t i = 0; i < points_of_node.count; ++i) {
      ++per_class[points_of_node.classification[i]];
    }
  }
  EXPECT_EQ(points, 3600u);
  for (int c = 1; c <= 6; ++c) EXPECT_EQ(per_class[std::size_t(c)], 600u) << "class " << c;
}

TEST(ToyFormat, RenderDrawsItAsItDrawsTheSamePointsFromLas) {
  registerToyOnce();
  test::TempDir dir;
  const PointCloud cloud = hill(40);
  writePointFile(cloud, dir / "hill.toy");
  writePointFile(cloud, dir / "hill.las");
  for (const char* name : {"hill.toy", "hill.las"}) {
    ASSERT_EQ(parallaxHere({"render", "-q", (dir / name).string(), "-o",
                            (dir / (std::string(name) + ".png")).string(), "--width", "96",
                            "--height", "64", "--color", "classification", "--point-size", "3"})
                  .exit_code,
              0)
        << name;
  }
  const RgbaImage toy = readPng(dir / "hill.toy.png");
  const RgbaImage las = readPng(dir / "hill.las.png");
  ASSERT_EQ(toy.width, 96);
  ASSERT_EQ(toy.height, 64);
  EXPECT_EQ(toy.pixels, las.pixels);
  // And something was drawn: not every pixel is the first one's (the background).
  bool drawn = false;
  for (std::size_t i = 4; i < toy.pixels.size(); i += 4) {
    drawn = drawn || std::memcmp(&toy.pixels[i], &toy.pixels[0], 4) != 0;
  }
  EXPECT_TRUE(drawn);
}

}  // namespace
}  // namespace parallax
