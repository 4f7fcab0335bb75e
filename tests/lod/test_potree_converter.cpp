// The conversion to a Potree 2.0 directory (lod/potree_converter.h), read back here with a
// minimal independent walker of hierarchy.bin that follows Potree's loader (OctreeLoader.js):
// every input point exactly once, in memory and out of core; a consistent hierarchy with proxy
// chunks; metadata as Potree clients read it; no finished-looking output after a failure.
#include <gtest/gtest.h>

#include <cstring>
#include <deque>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "core/error.h"
#include "io/point_file.h"
#include "lod/potree_converter.h"
#include "lod/potree_layout.h"
#include "lod_test_clouds.h"
#include "support/file_bytes.h"
#include "support/temp_dir.h"

namespace parallax::test {
namespace {

struct WalkedNode {
  std::string name;
  int type = 0;
  std::uint8_t mask = 0;
  std::uint32_t count = 0;
  std::uint64_t offset = 0, size = 0;
};

struct WalkedOctree {
  nlohmann::json metadata;
  std::string octree;
  std::vector<WalkedNode> nodes;  // real nodes (proxies replaced by their chunk's first entry)
  int proxies = 0;
};

// Reads a directory as Potree's loader does: the first chunk, then each proxy's chunk, whose
// first entry is the proxy node again. Fails the test on any inconsistency.
WalkedOctree walk(const std::filesystem::path& dir) {
  WalkedOctree result;
  result.metadata = nlohmann::json::parse(fileBytes(dir / "metadata.json"));
  result.octree = fileBytes(dir / "octree.bin");
  const std::string hierarchy = fileBytes(dir / "hierarchy.bin");
  auto entry = [&](std::uint64_t at) {
    WalkedNode node;
    EXPECT_LE(at + 22, hierarchy.size());
    node.type = std::uint8_t(hierarchy[at]);
    node.mask = std::uint8_t(hierarchy[at + 1]);
    std::memcpy(&node.count, hierarchy.data() + at + 2, 4);
    std::memcpy(&node.offset, hierarchy.data() + at + 6, 8);
    std::memcpy(&node.size, hierarchy.data() + at + 14, 8);
    return node;
  };
  struct Chunk {
    std::string name;
    std::uint64_t offset, size;
    std::uint8_t mask;
    std::uint32_t count;
  };
  std::deque<Chunk> chunks{{"r", 0, result.metadata["hierarchy"]["firstChunkSize"], 0, 0}};
  bool first = true;
  while (!chunks.empty()) {
    const Chunk chunk = chunks.front();
    chunks.pop_front();
    EXPECT_EQ(chunk.size % 22, 0u);
    std::deque<std::string> names{chunk.name};
    for (std::uint64_t at = chunk.offset; at < chunk.offset + chunk.size; at += 22) {
      EXPECT_FALSE(names.empty()) << "more entries than the masks announce in " << chunk.name;
      if (names.empty()) break;
      WalkedNode node = entry(at);
      node.name = names.front();
      names.pop_front();
      if (at == chunk.offset && !first) {
        EXPECT_NE(node.type, 2) << node.name;
        EXPECT_EQ(node.mask, chunk.mask) << "proxy and chunk disagree on " << node.name;
        EXPECT_EQ(node.count, chunk.count) << node.name;
      }
      first = false;
      if (node.type == 2 && at != chunk.offset) {
        ++result.proxies;
        EXPECT_NE(node.mask, 0) << "a proxy without children: " << node.name;
        chunks.push_back({node.name, node.offset, node.size, node.mask, node.count});
        continue;
      }
      EXPECT_EQ(node.type, node.mask ? 0 : 1) << node.name;
      for (int c = 0; c < 8; ++c) {
        if (node.mask & (1 << c)) names.push_back(node.name + char('0' + c));
      }
      result.nodes.push_back(node);
    }
    EXPECT_TRUE(names.empty()) << "children announced but not listed below " << chunk.name;
  }
  return result;
}

// Every point of a walked octree, decoded with `layout`.
PointCloud decodeAll(const WalkedOctree& walked, const PotreeLayout& layout) {
  Quantization q;
  for (int axis = 0; axis < 3; ++axis) {
    q.scale[std::size_t(axis)] = walked.metadata["scale"][axis];
    q.offset[std::size_t(axis)] = walked.metadata["offset"][axis];
  }
  std::string records;
  for (const WalkedNode& node : walked.nodes) records.append(walked.octree, node.offset, node.size);
  return layout.decode(reinterpret_cast<const std::byte*>(records.data()),
                       records.size() / layout.recordSize(), q);
}

void expectConsistent(const WalkedOctree& walked, std::size_t record_size, std::uint64_t points) {
  std::uint64_t sum = 0;
  std::map<std::uint64_t, std::uint64_t> ranges;  // offset -> size, of nodes with points
  for (const WalkedNode& node : walked.nodes) {
    sum += node.count;
    EXPECT_EQ(node.size, std::uint64_t(node.count) * record_size) << node.name;
    EXPECT_LE(node.offset + node.size, walked.octree.size()) << node.name;
    if (node.mask == 0) {
      EXPECT_GT(node.count, 0u) << "empty leaf " << node.name;
    }
    if (node.size > 0) ranges[node.offset] = node.size;
  }
  EXPECT_EQ(sum, points);
  EXPECT_EQ(walked.metadata["points"], points);
  // The ranges tile octree.bin: no overlap, no gap.
  std::uint64_t expected = 0;
  for (const auto& [offset, size] : ranges) {
    EXPECT_EQ(offset, expected);
    expected = offset + size;
  }
  EXPECT_EQ(expected, walked.octree.size());
}

struct ConverterCase {
  const char* label;
  std::uint64_t max_chunk_points;  // 0: from the memory budget
  SamplingMethod sampling;
  std::uint64_t memory_bytes = 2048ull << 20;
  bool one_chunk = false;
};

class PotreeConverterRoundTrip : public ::testing::TestWithParam<ConverterCase> {};

TEST_P(PotreeConverterRoundTrip, KeepsEveryPointExactlyOnceInAConsistentHierarchy) {
  TempDir dir;
  PointCloud cloud = makeSurfaceCloud(30'000);
  addDenseCluster(cloud);
  writePointFile(cloud, dir / "in.ply");
  PotreeConvertOptions options;
  options.build.sampling = GetParam().sampling;
  options.build.max_node_points = 300;
  options.build.max_chunk_points = GetParam().max_chunk_points;
  options.build.memory_bytes = GetParam().memory_bytes;
  const PotreeConvertResult result = convertToPotree({{dir / "in.ply", {}}}, dir / "out", options);
  EXPECT_EQ(result.points, 30'000u);
  if (GetParam().one_chunk) {
    EXPECT_EQ(result.chunks, 1u);
  } else {
    EXPECT_GT(result.chunks, 4u);
  }
  const WalkedOctree walked = walk(dir / "out");
  EXPECT_EQ(walked.nodes.size(), result.nodes);
  EXPECT_GT(walked.proxies, 0);  // deeper than one chunk of 4 levels
  const PotreeLayout layout = PotreeLayout::fromCloud(cloud);
  expectConsistent(walked, layout.recordSize(), 30'000);
  EXPECT_EQ(pointMultiset(decodeAll(walked, layout)), pointMultiset(cloud));
  // The nodes above the chunks lie between the two sides of the chunks (topLevelsSplit): the
  // root is followed by the upper side's chunks unless there is one chunk.
  for (const WalkedNode& node : walked.nodes) {
    if (node.name != "r") continue;
    if (GetParam().one_chunk) {
      EXPECT_EQ(node.offset + node.size, walked.octree.size());
    } else {
      EXPECT_LT(node.offset + node.size, walked.octree.size());
      EXPECT_GT(node.offset, 0u);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(
    Cases, PotreeConverterRoundTrip,
    ::testing::Values(ConverterCase{"in_memory", 0, SamplingMethod::Poisson, 2048ull << 20, true},
                      ConverterCase{"out_of_core", 2000, SamplingMethod::Poisson},
                      ConverterCase{"out_of_core_random", 2000, SamplingMethod::Random},
                      // A 1 MB budget: chunks of at most ~5 900 points, batches of ~1 500.
                      ConverterCase{"tiny_memory", 0, SamplingMethod::Poisson, 1u << 20}),
    [](const auto& param_info) { return std::string(param_info.param.label); });

TEST(PotreeConverter, WritesMetadataAsPotreeClientsReadIt) {
  TempDir dir;
  writePointFile(makeSurfaceCloud(2000), dir / "in.ply");
  // What the reader makes of the file (its quantization is chosen from float positions).
  const PointCloud cloud = readPointFile(dir / "in.ply");
  convertToPotree({{dir / "in.ply", {}}}, dir / "out");
  const auto metadata = nlohmann::json::parse(fileBytes(dir / "out" / "metadata.json"));
  EXPECT_EQ(metadata["version"], "2.0");
  EXPECT_EQ(metadata["encoding"], "DEFAULT");
  EXPECT_EQ(metadata["name"], "out");
  EXPECT_EQ(metadata["points"], 2000);
  EXPECT_EQ(metadata["hierarchy"]["stepSize"], 4);
  EXPECT_EQ(metadata["hierarchy"]["firstChunkSize"], 22);  // 2000 points: the root alone
  // The cube: tight minimum, largest extent on every axis; spacing = edge / 128.
  const auto& box = metadata["boundingBox"];
  const double edge = double(box["max"][0]) - double(box["min"][0]);
  for (int axis = 0; axis < 3; ++axis) {
    EXPECT_DOUBLE_EQ(box["min"][axis], cloud.bounds.min[std::size_t(axis)]);
    EXPECT_DOUBLE_EQ(double(box["max"][axis]) - double(box["min"][axis]), edge);
  }
  EXPECT_DOUBLE_EQ(metadata["spacing"], edge / 128.0);
  // Positions keep the source's quantization (one input, the cube fits it).
  for (int axis = 0; axis < 3; ++axis) {
    EXPECT_EQ(metadata["scale"][axis], cloud.quantization.scale[std::size_t(axis)]);
    EXPECT_EQ(metadata["offset"][axis], cloud.quantization.offset[std::size_t(axis)]);
  }
  std::vector<std::string> names, types;
  std::vector<int> sizes, elements;
  for (const auto& attribute : metadata["attributes"]) {
    names.push_back(attribute["name"]);
    types.push_back(attribute["type"]);
    sizes.push_back(attribute["size"]);
    elements.push_back(attribute["numElements"]);
    EXPECT_EQ(attribute["min"].size(), attribute["numElements"]);
    EXPECT_EQ(attribute["size"], int(attribute["numElements"]) * int(attribute["elementSize"]));
  }
  EXPECT_EQ(names, (std::vector<std::string>{"position", "rgb", "intensity", "NormalX", "NormalY",
                                             "NormalZ", "quality"}));
  EXPECT_EQ(types, (std::vector<std::string>{"int32", "uint16", "uint16", "float", "float", "float",
                                             "float"}));
  EXPECT_EQ(sizes, (std::vector<int>{12, 6, 2, 4, 4, 4, 4}));
  EXPECT_EQ(elements, (std::vector<int>{3, 3, 1, 1, 1, 1, 1}));
  // Position min/max are the tight bounds in world units; rgb is 8-bit * 257.
  EXPECT_DOUBLE_EQ(metadata["attributes"][0]["max"][2], cloud.bounds.max[2]);
  EXPECT_EQ(metadata["attributes"][1]["max"][0], 255 * 257);
  // The root's records: the first point's bytes as a client decodes them.
  const std::string octree = fileBytes(dir / "out" / "octree.bin");
  EXPECT_EQ(octree.size(), 2000u * 36u);
}

TEST(PotreeConverter, StreamsATextFileInBatchesLikeTheOtherFormats) {
  TempDir dir;
  // Over the 64 Ki points a text reader parses whole for its quantization.
  writePointFile(makeSurfaceCloud(70'000), dir / "in.xyz");
  const PointCloud cloud = readPointFile(dir / "in.xyz");
  PotreeConvertOptions options;
  options.build.max_node_points = 2000;
  options.build.memory_bytes = 1u << 20;  // batches of about 1 500 points, chunks of ~5 900
  const PotreeConvertResult result = convertToPotree({{dir / "in.xyz", {}}}, dir / "out", options);
  EXPECT_EQ(result.points, 70'000u);
  EXPECT_GT(result.chunks, 4u);
  const WalkedOctree walked = walk(dir / "out");
  const PotreeLayout layout = PotreeLayout::fromCloud(cloud);
  expectConsistent(walked, layout.recordSize(), 70'000);
  EXPECT_EQ(pointMultiset(decodeAll(walked, layout)), pointMultiset(cloud));
  // One input: its own (decimal, exact) quantization.
  for (int axis = 0; axis < 3; ++axis) {
    EXPECT_EQ(walked.metadata["scale"][axis], cloud.quantization.scale[std::size_t(axis)]);
    EXPECT_EQ(walked.metadata["offset"][axis], cloud.quantization.offset[std::size_t(axis)]);
  }
}

TEST(PotreeConverter, MergesSeveralInputsIntoOneOctree) {
  TempDir dir;
  const PointCloud a = makeSurfaceCloud(3000, 1);
  const PointCloud b = makeSurfaceCloud(2000, 7);
  writePointFile(a, dir / "a.ply");
  writePointFile(b, dir / "b.ply");
  PotreeConvertOptions options;
  options.build.max_node_points = 300;
  options.build.max_chunk_points = 1000;
  const auto result =
      convertToPotree({{dir / "a.ply", {}}, {dir / "b.ply", {}}}, dir / "out", options);
  EXPECT_EQ(result.points, 5000u);
  const WalkedOctree walked = walk(dir / "out");
  const PotreeLayout layout = PotreeLayout::fromCloud(a);
  expectConsistent(walked, layout.recordSize(), 5000);
  std::vector<PointKey> expected = pointMultiset(a);
  const std::vector<PointKey> second = pointMultiset(b);
  expected.insert(expected.end(), second.begin(), second.end());
  std::sort(expected.begin(), expected.end());
  EXPECT_EQ(pointMultiset(decodeAll(walked, layout)), expected);
}

TEST(PotreeConverter, KeepsLasAttributesUnderPotreeNames) {
  TempDir dir;
  const PointCloud cloud = makeLasLikeCloud(4000, 19);
  writePointFile(cloud, dir / "in.las");
  const PointCloud las = readPointFile(dir / "in.las");
  PotreeConvertOptions options;
  options.build.max_node_points = 300;
  options.build.max_chunk_points = 1000;
  convertToPotree({{dir / "in.las", {}}}, dir / "out", options);
  const WalkedOctree walked = walk(dir / "out");
  std::vector<std::string> names, types;
  for (const auto& attribute : walked.metadata["attributes"]) {
    names.push_back(attribute["name"]);
    types.push_back(attribute["type"]);
  }
  // The LAS reader's own columns, each under the name Potree's viewer knows, in its LAS type.
  const PotreeLayout layout = PotreeLayout::fromCloud(las);
  ASSERT_EQ(names.size(), layout.attributes().size());
  for (std::size_t a = 0; a < names.size(); ++a) {
    EXPECT_EQ(names[a], layout.attributes()[a].name);
    EXPECT_EQ(types[a], potreeTypeName(layout.attributes()[a].type));
  }
  EXPECT_NE(std::find(names.begin(), names.end(), "return number"), names.end());
  EXPECT_NE(std::find(names.begin(), names.end(), "gps-time"), names.end());
  EXPECT_NE(std::find(names.begin(), names.end(), "classification"), names.end());
  EXPECT_EQ(names[2], "intensity");
  EXPECT_EQ(types[2], "uint16");
  // The LAS integers are kept as they are: same scale and offset as the file's header.
  EXPECT_EQ(walked.metadata["scale"][0], las.quantization.scale[0]);
  expectConsistent(walked, layout.recordSize(), 4000);
  EXPECT_EQ(pointMultiset(decodeAll(walked, layout)), pointMultiset(las));
}

TEST(PotreeConverter, InterruptedConversionLeavesNothingThatLooksComplete) {
  TempDir dir;
  const PointCloud cloud = makeSurfaceCloud(20'000);
  writePointFile(cloud, dir / "in.ply");
  PotreeConvertOptions options;
  options.build.max_node_points = 300;
  options.build.max_chunk_points = 2000;
  options.fail_after_octree_bytes = 20'000u * 36u / 2;  // half of octree.bin
  EXPECT_THROW(convertToPotree({{dir / "in.ply", {}}}, dir / "out", options), std::runtime_error);
  EXPECT_FALSE(std::filesystem::exists(dir / "out"));
  // Only the input is left: the temporary directory is gone too.
  std::vector<std::string> left;
  for (const auto& entry : std::filesystem::directory_iterator(dir.path()))
    left.push_back(entry.path().filename().string());
  EXPECT_EQ(left, std::vector<std::string>{"in.ply"});

  // An earlier complete output under the same name survives a failed rerun unchanged.
  options.fail_after_octree_bytes = 0;
  convertToPotree({{dir / "in.ply", {}}}, dir / "out", options);
  const std::string before = fileBytes(dir / "out" / "hierarchy.bin");
  options.fail_after_octree_bytes = 1000;
  EXPECT_THROW(convertToPotree({{dir / "in.ply", {}}}, dir / "out", options), std::runtime_error);
  EXPECT_EQ(fileBytes(dir / "out" / "hierarchy.bin"), before);
}

TEST(PotreeConverter, RefusesToReplaceSomethingElse) {
  TempDir dir;
  writePointFile(makeSurfaceCloud(10), dir / "in.ply");
  std::filesystem::create_directories(dir / "photos");
  dir.write("photos/holiday.jpg", "not a point cloud");
  try {
    convertToPotree({{dir / "in.ply", {}}}, dir / "photos");
    FAIL() << "expected an InputError";
  } catch (const InputError& error) {
    EXPECT_EQ(error.info().found, "a directory with other files");
  }
  EXPECT_TRUE(std::filesystem::exists(dir / "photos" / "holiday.jpg"));
}

}  // namespace
}  // namespace parallax::test
