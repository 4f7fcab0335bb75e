#include "lod/potree_reader.h"

#include <gtest/gtest.h>

#include <cstring>
#include <functional>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "lod/potree_hierarchy_reader.h"
#include "lod/potree_test_dataset.h"
#include "support/temp_dir.h"

namespace parallax {
namespace {

using test::potreeTestDataset;
using test::PotreeTestDataset;
using test::setEntry;
using Json = nlohmann::ordered_json;
constexpr std::uint64_t R = test::kPotreeTestRecordSize;

std::unique_ptr<Octree> openMemory(const PotreeTestDataset& d) {
  return openPotreeFromMemory(d.metadata, d.hierarchy, d.octree, "cloud");
}

// The message of the InputError `open` throws (fails the test when none is thrown).
template <class F>
std::string errorOf(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no InputError";
  return {};
}

void expectContains(const std::string& text, const std::vector<std::string>& parts) {
  for (const auto& part : parts) {
    EXPECT_NE(text.find(part), std::string::npos) << "'" << part << "' not in: " << text;
  }
}

PotreeTestDataset withMetadata(const std::function<void(Json&)>& edit) {
  PotreeTestDataset d = potreeTestDataset();
  Json json = Json::parse(d.metadata);
  edit(json);
  d.metadata = json.dump();
  return d;
}

template <class T>
T scalarAt(const PointCloud& cloud, const std::string& name, std::size_t i) {
  const ScalarColumn* column = cloud.findScalar(name);
  EXPECT_NE(column, nullptr) << name;
  return column ? column->as<T>()[i] : T{};
}

std::int32_t childOf(const Octree& octree, std::int32_t node, int child) {
  return octree.nodes()[std::size_t(node)].children[std::size_t(child)];
}

TEST(PotreeReader, HandMadeDatasetReadsBackExactValues) {
  test::TempDir dir;
  potreeTestDataset().writeTo(dir.path());
  ASSERT_TRUE(isPotreeDirectory(dir.path()));
  ASSERT_TRUE(isPotreeDirectory(dir / "metadata.json"));
  auto octree = openPotree(dir.path());

  const OctreeInfo& info = octree->info();
  EXPECT_EQ(info.point_count, 6u);
  EXPECT_EQ(info.cube.min, (std::array<double, 3>{1000, 2000, 30}));
  EXPECT_EQ(info.cube.max, (std::array<double, 3>{1010, 2010, 40}));
  EXPECT_EQ(info.bounds.min, (std::array<double, 3>{1001, 2002, 31}));
  EXPECT_EQ(info.bounds.max, (std::array<double, 3>{1008, 2009, 39}));
  EXPECT_EQ(info.quantization.scale, (std::array<double, 3>{0.001, 0.001, 0.001}));
  EXPECT_EQ(info.quantization.offset, (std::array<double, 3>{1000, 2000, 30}));
  EXPECT_EQ(info.spacing, 0.5);
  EXPECT_EQ(info.attributes, (std::vector<std::string>{
                                 "x", "y", "z", "red", "green", "blue", "intensity",
                                 "classification", "return_number", "number_of_returns",
                                 "scan_angle_rank", "user_data", "point_source_id", "gps_time"}));
  EXPECT_TRUE(info.has_colors && info.has_intensity && info.has_classification);
  EXPECT_FALSE(info.has_normals);

  // The first chunk: r (typed leaf, yet with children), r0, and the proxy r6; the entry after
  // them is no node's.
  auto nodes = octree->nodes();
  ASSERT_EQ(nodes.size(), 3u);
  EXPECT_EQ(nodes[0].name, "r");
  EXPECT_EQ(nodes[0].child_mask, 0x41);
  EXPECT_EQ(nodes[0].point_count, 2u);
  EXPECT_EQ(nodes[0].parent, -1);
  EXPECT_EQ(nodes[0].children, (std::array<std::int32_t, 8>{1, -1, -1, -1, -1, -1, 2, -1}));
  EXPECT_EQ(nodes[1].name, "r0");
  EXPECT_EQ(nodes[1].level, 1);
  EXPECT_EQ(nodes[1].parent, 0);
  EXPECT_EQ(nodes[1].spacing, 0.25);
  EXPECT_EQ(nodes[1].box.min, (std::array<double, 3>{1000, 2000, 30}));
  EXPECT_EQ(nodes[1].box.max, (std::array<double, 3>{1005, 2005, 35}));
  EXPECT_FALSE(nodes[1].hierarchy_pending);
  EXPECT_EQ(nodes[2].name, "r6");  // bits 4 (+x) and 2 (+y)
  EXPECT_EQ(nodes[2].box.min, (std::array<double, 3>{1005, 2005, 30}));
  EXPECT_EQ(nodes[2].box.max, (std::array<double, 3>{1010, 2010, 35}));
  EXPECT_TRUE(nodes[2].hierarchy_pending);
  EXPECT_EQ(nodes[2].point_count, 1u);

  const auto points = test::potreeTestPoints();
  const PointCloud root = octree->loadNode(nodes[0]);
  ASSERT_EQ(root.count, 2u);
  EXPECT_EQ(root.quantization, info.quantization);
  EXPECT_EQ(root.positions[0], (Int3{1000, 2000, 3000}));
  EXPECT_EQ(root.positions[1], (Int3{8000, 9000, 9000}));
  EXPECT_DOUBLE_EQ(root.worldX(0), 1001.0);
  EXPECT_EQ(root.bounds.min, (std::array<double, 3>{1001, 2002, 33}));
  // 16-bit colour (max above 255): rounded value / 257.
  EXPECT_EQ(root.colors[0], (Rgba8{255, 0, 100, 255}));
  EXPECT_EQ(root.colors[1], (Rgba8{2, 4, 254, 255}));
  EXPECT_EQ(root.source.color, ScalarType::UInt16);
  EXPECT_EQ(root.intensity[0], 0.0f);
  EXPECT_EQ(root.intensity[1], 65535.0f);
  EXPECT_EQ(root.source.intensity, ScalarType::UInt16);
  EXPECT_EQ(root.classification[0], 2);
  EXPECT_EQ(root.classification[1], 5);
  EXPECT_EQ(scalarAt<std::uint8_t>(root, "return_number", 1), 2);
  EXPECT_EQ(scalarAt<std::uint8_t>(root, "number_of_returns", 1), 2);
  // Declared uint8, holding LAS's signed byte: read as int8.
  EXPECT_EQ(root.findScalar("scan_angle_rank")->type, ScalarType::Int8);
  EXPECT_EQ(scalarAt<std::int8_t>(root, "scan_angle_rank", 0), -15);
  EXPECT_EQ(scalarAt<std::int8_t>(root, "scan_angle_rank", 1), 90);
  EXPECT_EQ(scalarAt<std::uint8_t>(root, "user_data", 0), 7);
  EXPECT_EQ(scalarAt<std::uint16_t>(root, "point_source_id", 0), 65000);
  EXPECT_EQ(scalarAt<double>(root, "gps_time", 0), 123456.789);
  EXPECT_EQ(scalarAt<double>(root, "gps_time", 1), -1.5);

  const PointCloud r0 = octree->loadNode(nodes[1]);
  ASSERT_EQ(r0.count, 1u);
  EXPECT_EQ(r0.positions[0], (Int3{2500, 2500, 2500}));
  EXPECT_EQ(r0.colors[0], (Rgba8{1, 2, 3, 255}));
  EXPECT_EQ(scalarAt<std::int8_t>(r0, "scan_angle_rank", 0), -90);

  // A pending proxy loads before its chunk is read (its own entry opens that chunk).
  const PointCloud r6_pending = octree->loadNode(nodes[2]);
  ASSERT_EQ(r6_pending.count, 1u);
  EXPECT_EQ(r6_pending.positions[0], (Int3{6000, 7000, 1000}));

  octree->expandHierarchy(2);
  nodes = octree->nodes();
  ASSERT_EQ(nodes.size(), 4u);
  EXPECT_FALSE(nodes[2].hierarchy_pending);
  EXPECT_EQ(nodes[2].child_mask, 0x02);
  EXPECT_EQ(nodes[2].byte_offset, 3 * R);
  EXPECT_EQ(nodes[2].byte_size, R);
  EXPECT_EQ(childOf(*octree, 2, 1), 3);
  EXPECT_EQ(nodes[3].name, "r61");
  EXPECT_EQ(nodes[3].level, 2);
  EXPECT_EQ(nodes[3].parent, 2);
  EXPECT_EQ(nodes[3].spacing, 0.125);
  EXPECT_EQ(nodes[3].box.min, (std::array<double, 3>{1005, 2005, 32.5}));
  EXPECT_EQ(nodes[3].box.max, (std::array<double, 3>{1007.5, 2007.5, 35}));

  const PointCloud r6 = octree->loadNode(nodes[2]);
  EXPECT_EQ(r6.positions[0], r6_pending.positions[0]);
  EXPECT_EQ(r6.colors[0], (Rgba8{255, 255, 255, 255}));
  EXPECT_EQ(scalarAt<double>(r6, "gps_time", 0), 1e9);

  const PointCloud r61 = octree->loadNode(nodes[3]);
  ASSERT_EQ(r61.count, 2u);
  EXPECT_EQ(r61.positions[1], (Int3{7000, 7400, 4999}));
  EXPECT_EQ(r61.colors[1], (Rgba8{50, 100, 150, 255}));
  EXPECT_EQ(r61.intensity[1], 300.0f);
  EXPECT_EQ(r61.classification[1], 31);
  EXPECT_EQ(scalarAt<std::int8_t>(r61, "scan_angle_rank", 1), -1);
  EXPECT_EQ(scalarAt<std::uint16_t>(r61, "point_source_id", 1), 5);
  EXPECT_EQ(scalarAt<double>(r61, "gps_time", 0), 2.25);

  // Expanding a node that is not pending changes nothing.
  octree->expandHierarchy(3);
  EXPECT_EQ(octree->nodes().size(), 4u);
}

TEST(PotreeReader, MemoryAndDiskGiveTheSameNodes) {
  test::TempDir dir;
  potreeTestDataset().writeTo(dir.path());
  auto disk = openPotree(dir / "metadata.json");
  auto memory = openMemory(potreeTestDataset());
  ASSERT_EQ(disk->nodes().size(), memory->nodes().size());
  for (std::size_t i = 0; i < disk->nodes().size(); ++i) {
    const auto a = disk->loadNode(disk->nodes()[i]);
    const auto b = memory->loadNode(memory->nodes()[i]);
    ASSERT_EQ(a.count, b.count);
    for (std::size_t p = 0; p < a.count; ++p) EXPECT_EQ(a.positions[p], b.positions[p]);
  }
}

TEST(PotreeReader, EightBitColourInSixteenBitFieldsIsKeptAsItIs) {
  PotreeTestDataset d = withMetadata([](Json& m) { m["attributes"][9]["max"] = {255, 255, 255}; });
  // Rewrite the colours of r0 to 0-255 values; the others are not loaded.
  const std::uint16_t rgb[3] = {1, 128, 255};
  std::memcpy(d.octree.data() + 2 * R + 29, rgb, sizeof rgb);
  auto octree = openMemory(d);
  const PointCloud r0 = octree->loadNode(octree->nodes()[1]);
  EXPECT_EQ(r0.colors[0], (Rgba8{1, 128, 255, 255}));
  EXPECT_EQ(r0.source.color, ScalarType::UInt8);
}

// A single-chunk dataset of one root node with the given attributes and raw records.
PotreeTestDataset oneNode(const Json& attributes, const std::vector<std::byte>& records,
                          std::uint32_t points) {
  PotreeTestDataset d;
  Json m = test::potreeTestMetadata(points, test::kPotreeTestEntrySize);
  m["attributes"] = attributes;
  d.metadata = m.dump();
  d.octree = records;
  test::appendEntry(d.hierarchy, 1, 0, points, 0, records.size());
  return d;
}

TEST(PotreeReader, NormalsUnderPotreesNamesAndOtherTypes) {
  Json position = test::potreeTestAttribute("position", 3, 4, "int32", {}, {});
  std::vector<std::byte> records;
  for (std::int32_t v : {1, 2, 3}) test::appendValue(records, v);
  // NormalX/Y/Z as three floats (Potree's and three-loader's naming).
  for (float v : {0.5f, -0.25f, 1.0f}) test::appendValue(records, v);
  test::appendValue(records, std::int64_t(-1234567890123));
  test::appendValue(records, std::uint64_t(1) << 52);
  test::appendValue(records, std::int16_t(-7));
  test::appendValue(records, std::int16_t(8));
  Json attributes =
      Json::array({position, test::potreeTestAttribute("NormalX", 1, 4, "float", {}, {}),
                   test::potreeTestAttribute("NormalY", 1, 4, "float", {}, {}),
                   test::potreeTestAttribute("NormalZ", 1, 4, "float", {}, {}),
                   test::potreeTestAttribute("big", 1, 8, "int64", {}, {}),
                   test::potreeTestAttribute("huge", 1, 8, "uint64", {}, {}),
                   test::potreeTestAttribute("pair", 2, 2, "int16", {}, {})});
  auto octree = openMemory(oneNode(attributes, records, 1));
  EXPECT_TRUE(octree->info().has_normals);
  EXPECT_FALSE(octree->info().has_colors);
  EXPECT_EQ(octree->info().attributes,
            (std::vector<std::string>{"x", "y", "z", "nx", "ny", "nz", "big", "huge", "pair[0]",
                                      "pair[1]"}));
  const PointCloud cloud = octree->loadNode(octree->nodes()[0]);
  EXPECT_EQ(cloud.normals[0], (Float3{0.5f, -0.25f, 1.0f}));
  EXPECT_EQ(scalarAt<double>(cloud, "big", 0), -1234567890123.0);
  EXPECT_EQ(scalarAt<double>(cloud, "huge", 0), 4503599627370496.0);
  EXPECT_EQ(scalarAt<std::int16_t>(cloud, "pair[0]", 0), -7);
  EXPECT_EQ(scalarAt<std::int16_t>(cloud, "pair[1]", 0), 8);

  // One 3-element "normal" attribute of doubles.
  records.clear();
  for (std::int32_t v : {1, 2, 3}) test::appendValue(records, v);
  for (double v : {0.0, 1.0, -1.0}) test::appendValue(records, v);
  attributes = Json::array({position, test::potreeTestAttribute("normal", 3, 8, "double", {}, {})});
  auto doubles = openMemory(oneNode(attributes, records, 1));
  EXPECT_EQ(doubles->loadNode(doubles->nodes()[0]).normals[0], (Float3{0.0f, 1.0f, -1.0f}));
}

// ---------------------------------------------------------------------------------------------
// Hostile input: each a clear InputError naming the file, the byte offset, the node, what was
// expected and what was found.

TEST(PotreeReaderErrors, DataRangePastTheEndOfOctreeBin) {
  PotreeTestDataset d = potreeTestDataset();
  setEntry(d.hierarchy, 1, 1, 0, 1, 1000, R);  // r0 at byte 1000 of a 210-byte octree.bin
  expectContains(errorOf([&] { openMemory(d); }),
                 {"cloud/hierarchy.bin", "byte offset 22", "node r0",
                  "inside cloud/octree.bin (210 bytes)", "bytes 1000 to 1000 + 35"});
  // The same in the proxy's chunk: found when it is expanded.
  d = potreeTestDataset();
  setEntry(d.hierarchy, 6, 1, 0, 2, 4 * R, 3 * R);  // r61 says 2 points but 3 records
  auto octree = openMemory(d);
  expectContains(errorOf([&] { octree->expandHierarchy(2); }),
                 {"cloud/hierarchy.bin", "byte offset 132", "node r61", "byteSize = 2 points x 35",
                  "found byteSize 105"});
}

TEST(PotreeReaderErrors, CountsThatLie) {
  PotreeTestDataset d = potreeTestDataset();
  setEntry(d.hierarchy, 0, 1, 0x41, 3, 0, 2 * R);  // r says 3 points in 2 records
  expectContains(
      errorOf([&] { openMemory(d); }),
      {"byte offset 0", "node r", "byteSize = 3 points x 35 bytes = 105", "found byteSize 70"});
  // A proxy's count that its chunk's entry contradicts: loading it before expansion says so.
  d = potreeTestDataset();
  setEntry(d.hierarchy, 2, 2, 0, 5, 110, 44);
  auto proxied = openMemory(d);
  expectContains(errorOf([&] { proxied->loadNode(proxied->nodes()[2]); }),
                 {"cloud/hierarchy.bin", "byte offset 110", "node r6",
                  "5 points, as the proxy entry of the node says", "found 1 in its chunk's entry"});
  // metadata's total disagrees with the nodes: found once the whole hierarchy is read.
  d = withMetadata([](Json& m) { m["points"] = 7; });
  auto octree = openMemory(d);
  expectContains(errorOf([&] { octree->expandHierarchy(2); }),
                 {"cloud/hierarchy.bin", "7 points in all", "found 6 points in 4 nodes"});
}

TEST(PotreeReaderErrors, ANodeWhoseRangeIsTamperedWithFailsToLoad) {
  auto octree = openMemory(potreeTestDataset());
  OctreeNode node = octree->nodes()[1];
  node.byte_offset = 200;  // 35 bytes from 200 run past the 210-byte octree.bin
  expectContains(errorOf([&] { octree->loadNode(node); }),
                 {"cloud/octree.bin", "byte offset 200", "node r0", "inside cloud/octree.bin"});
}

TEST(PotreeReaderErrors, HierarchyChunksOutsideTheFileOrNotWholeEntries) {
  PotreeTestDataset d = potreeTestDataset();
  setEntry(d.hierarchy, 2, 2, 0, 1, 150, 44);  // proxy r6 runs past the 154-byte file
  expectContains(errorOf([&] { openMemory(d); }),
                 {"cloud/hierarchy.bin", "byte offset 44", "node r6", "inside hierarchy.bin (154",
                  "bytes 150 to 150 + 44"});
  setEntry(d.hierarchy, 2, 2, 0, 1, 110, 30);  // not whole entries
  expectContains(errorOf([&] { openMemory(d); }),
                 {"byte offset 44", "node r6", "whole 22-byte entries", "found 30 bytes"});
  d = withMetadata([](Json& m) { m["hierarchy"]["firstChunkSize"] = 1100; });
  expectContains(errorOf([&] { openMemory(d); }),
                 {"cloud/hierarchy.bin", "hierarchy.firstChunkSize", "inside hierarchy.bin"});
  d = potreeTestDataset();
  d.hierarchy.resize(60);  // the first chunk cut short: r6's entry is missing
  d.metadata = test::potreeTestMetadata(6, 50).dump();
  expectContains(errorOf([&] { openMemory(d); }), {"firstChunkSize", "whole 22-byte entries"});
  d.metadata = test::potreeTestMetadata(6, 44).dump();
  expectContains(errorOf([&] { openMemory(d); }),
                 {"byte offset 44", "node r6", "an entry for every node the child masks name",
                  "the chunk ends after 2 entries"});
}

TEST(PotreeReaderErrors, ProxyCyclesEndWithAnError) {
  // r6 points at the first chunk (its own chunk).
  PotreeTestDataset d = potreeTestDataset();
  setEntry(d.hierarchy, 2, 2, 0, 1, 0, 88);
  auto octree = openMemory(d);
  expectContains(errorOf([&] { octree->expandHierarchy(2); }),
                 {"cloud/hierarchy.bin", "byte offset 0", "node r6", "a cycle"});
  // A chunk whose first entry is a proxy pointing at itself: expand and load both end.
  d = potreeTestDataset();
  setEntry(d.hierarchy, 5, 2, 0, 1, 110, 44);
  octree = openMemory(d);
  expectContains(errorOf([&] { octree->loadNode(octree->nodes()[2]); }),
                 {"node r6", "a chain of proxies"});
  expectContains(errorOf([&] { octree->expandHierarchy(2); }), {"node r6", "a cycle"});
}

TEST(PotreeReaderErrors, TreesDeeperThanInt32PositionsResolve) {
  // A chain r, r0, r00, ... one child each, empty nodes.
  PotreeTestDataset d;
  const int entries = kPotreeMaxLevel + 2;
  for (int i = 0; i < entries; ++i) test::appendEntry(d.hierarchy, 0, 0x01, 0, 0, 0);
  d.metadata = test::potreeTestMetadata(0, d.hierarchy.size()).dump();
  expectContains(errorOf([&] { openMemory(d); }),
                 {"byte offset " + std::to_string(kPotreeMaxLevel * 22), "at most 31 levels",
                  "children at level 32"});
}

TEST(PotreeReaderErrors, UnknownNodeType) {
  PotreeTestDataset d = potreeTestDataset();
  setEntry(d.hierarchy, 1, 7, 0, 1, 2 * R, R);
  expectContains(errorOf([&] { openMemory(d); }),
                 {"byte offset 22", "node r0", "type 0, 1 or 2", "found type 7"});
}

TEST(PotreeReaderErrors, MissingFiles) {
  test::TempDir dir;
  expectContains(errorOf([&] { openPotree(dir / "nothing"); }),
                 {"nothing", "a Potree 2.0 directory", "found nothing"});
  EXPECT_FALSE(isPotreeDirectory(dir.path()));
  potreeTestDataset().writeTo(dir.path());
  std::filesystem::remove(dir / "octree.bin");
  expectContains(errorOf([&] { openPotree(dir.path()); }),
                 {"octree.bin", "No such file", "metadata.json, hierarchy.bin and octree.bin"});
  std::filesystem::remove(dir / "metadata.json");
  expectContains(errorOf([&] { openPotree(dir.path()); }), {"metadata.json", "No such file"});
}

TEST(PotreeReaderErrors, MalformedMetadata) {
  PotreeTestDataset d = potreeTestDataset();
  d.metadata = "{\"version\": \"2.0\",\n \"points\": }";
  expectContains(errorOf([&] { openMemory(d); }),
                 {"cloud/metadata.json", "byte offset 30", "expected JSON"});

  d.metadata = "{\"points\": 5555555E5555555555}";  // a number no type holds (found by fuzzing)
  expectContains(errorOf([&] { openMemory(d); }),
                 {"cloud/metadata.json", "expected JSON", "number overflow"});

  struct Case {
    std::function<void(Json&)> edit;
    std::vector<std::string> message;
  };
  const std::vector<Case> cases = {
      {[](Json& m) { m.erase("scale"); }, {"element 'scale'", "expected the field", "found none"}},
      {[](Json& m) {
         m["scale"] = {0.001, 0, 0.001};
       },
       {"'scale'", "positive numbers", "found 0"}},
      {[](Json& m) { m["points"] = -3; }, {"'points'", "an integer from 0", "found '-3'"}},
      {[](Json& m) { m["offset"] = "here"; }, {"'offset'", "an array of 3 numbers"}},
      {[](Json& m) { m["boundingBox"]["max"][1] = 2000; }, {"boundingBox", "min below max"}},
      {[](Json& m) { m["hierarchy"].erase("firstChunkSize"); },
       {"'hierarchy.firstChunkSize'", "found none"}},
      {[](Json& m) { m["version"] = "1.8"; }, {"'version'", "\"2.0\"", "PotreeConverter 2"}},
      {[](Json& m) { m["encoding"] = "BROTLI"; },
       {"'encoding'", "\"DEFAULT\"", "found 'BROTLI'", "--encoding DEFAULT"}},
      {[](Json& m) { m["attributes"][2]["type"] = "int128"; },
       {"'attributes[2].type'", "one of int8", "found 'int128'"}},
      {[](Json& m) { m["attributes"][9]["size"] = 5; },
       {"'attributes[9].size'", "6 (numElements 3 x 2 bytes of uint16)", "found 5"}},
      {[](Json& m) { m["attributes"][0]["type"] = "float"; },
       {"attributes.position", "int32 x 3", "found float x 3"}},
      {[](Json& m) { m["attributes"].erase(0); }, {"an attribute named \"position\""}},
      {[](Json& m) { m["attributes"] = Json::array(); }, {"'attributes'", "a non-empty array"}},
      {[](Json& m) {
         m["attributes"][1]["min"] = {1, 2};
       },
       {"'attributes[1].min'", "an array of 1 numbers"}},
  };
  for (const auto& c : cases) {
    const PotreeTestDataset bad = withMetadata(c.edit);
    SCOPED_TRACE(bad.metadata.substr(0, 200));
    const std::string message = errorOf([&] { openMemory(bad); });
    expectContains(message, c.message);
    expectContains(message, {"cloud/metadata.json"});
  }
}

TEST(PotreeReaderErrors, RecordSizeChangesEveryNodesExpectedSize) {
  // An attribute more in metadata than in octree.bin: every byte size now disagrees.
  PotreeTestDataset d = withMetadata([](Json& m) {
    m["attributes"].push_back(test::potreeTestAttribute("extra", 1, 4, "float", {}, {}));
  });
  expectContains(errorOf([&] { openMemory(d); }),
                 {"node r", "byteSize = 2 points x 39 bytes = 78", "found byteSize 70"});
}

}  // namespace
}  // namespace parallax
