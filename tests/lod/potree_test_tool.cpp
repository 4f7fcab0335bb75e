// Helper of the real-client test (tests/lod/js) and of the fuzz corpus:
//   potree_test_tool write-handmade DIR     writes the hand-made dataset (potree_test_dataset.h)
//   potree_test_tool dump DIR OUT.json      what Parallax's reader gives for a Potree directory:
//                                           every node (the whole hierarchy read), its point
//                                           count, world positions, colours, normals and every
//                                           other column, as JSON for check_potree_client.cjs
//   potree_test_tool write-fuzz-seeds DIR   seeds for fuzz/fuzz_potree_reader.cpp (its framing)
//   potree_test_tool bench DIR              opens DIR, reads the whole hierarchy and loads every
//                                           node on one thread; prints the times and rates
// Exit status 0 on success, 1 with the message on an InputError, 2 on bad usage.
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "core/error.h"
#include "lod/potree_reader.h"
#include "lod/potree_test_dataset.h"

namespace parallax {
namespace {

using Json = nlohmann::ordered_json;

Json dumpOctree(Octree& octree) {
  for (std::size_t i = 0; i < octree.nodes().size(); ++i) {
    if (octree.nodes()[i].hierarchy_pending) octree.expandHierarchy(std::int32_t(i));
  }
  Json nodes = Json::array();
  std::uint64_t total = 0;
  for (const OctreeNode& node : octree.nodes()) {
    const PointCloud cloud = octree.loadNode(node);
    total += cloud.count;
    Json positions = Json::array(), colors = Json::array(), normals = Json::array();
    for (std::size_t i = 0; i < cloud.count; ++i) {
      positions.push_back({cloud.worldX(i), cloud.worldY(i), cloud.worldZ(i)});
      if (cloud.hasColors()) {
        colors.push_back({cloud.colors[i].r, cloud.colors[i].g, cloud.colors[i].b});
      }
      if (cloud.hasNormals()) {
        normals.push_back({cloud.normals[i].x, cloud.normals[i].y, cloud.normals[i].z});
      }
    }
    Json columns = Json::object();
    if (cloud.hasIntensity()) {
      columns["intensity"] = std::vector<float>(cloud.intensity.begin(), cloud.intensity.end());
    }
    if (cloud.hasClassification()) {
      columns["classification"] =
          std::vector<int>(cloud.classification.begin(), cloud.classification.end());
    }
    for (const auto& column : cloud.scalars) {
      Json values = Json::array();
      for (std::size_t i = 0; i < cloud.count; ++i) values.push_back(column.valueAsDouble(i));
      columns[column.name] = values;
    }
    nodes.push_back({{"name", node.name},
                     {"points", node.point_count},
                     {"positions", positions},
                     {"colors", cloud.hasColors() ? colors : Json(nullptr)},
                     {"normals", cloud.hasNormals() ? normals : Json(nullptr)},
                     {"columns", columns}});
  }
  return {{"points", total}, {"nodes", nodes}};
}

void writeSeed(const std::filesystem::path& file, const test::PotreeTestDataset& d) {
  std::ofstream out(file, std::ios::binary);
  const std::uint32_t lengths[2] = {std::uint32_t(d.metadata.size()),
                                    std::uint32_t(d.hierarchy.size())};
  out.write(reinterpret_cast<const char*>(lengths), sizeof lengths);
  out << d.metadata;
  out.write(reinterpret_cast<const char*>(d.hierarchy.data()), std::streamsize(d.hierarchy.size()));
  out.write(reinterpret_cast<const char*>(d.octree.data()), std::streamsize(d.octree.size()));
}

void writeFuzzSeeds(const std::filesystem::path& dir) {
  std::filesystem::create_directories(dir);
  writeSeed(dir / "handmade.bin", test::potreeTestDataset());
  // The proxy pointing back at the first chunk (a cycle).
  test::PotreeTestDataset cycle = test::potreeTestDataset();
  test::setEntry(cycle.hierarchy, 2, 2, 0, 1, 0, 88);
  writeSeed(dir / "proxy_cycle.bin", cycle);
  // One node with normals as NormalX/Y/Z and 8-bit colour in a uint8 rgb.
  test::PotreeTestDataset normals;
  Json m = test::potreeTestMetadata(2, test::kPotreeTestEntrySize);
  m["attributes"] = Json::array({test::potreeTestAttribute("position", 3, 4, "int32", {}, {}),
                                 test::potreeTestAttribute("rgb", 3, 1, "uint8", {}, {}),
                                 test::potreeTestAttribute("NormalX", 1, 4, "float", {}, {}),
                                 test::potreeTestAttribute("NormalY", 1, 4, "float", {}, {}),
                                 test::potreeTestAttribute("NormalZ", 1, 4, "float", {}, {}),
                                 test::potreeTestAttribute("big", 1, 8, "uint64", {}, {})});
  normals.metadata = m.dump();
  for (int p = 0; p < 2; ++p) {
    for (std::int32_t v : {p, 2 * p, 3 * p}) test::appendValue(normals.octree, v);
    for (std::uint8_t v : {std::uint8_t(10), std::uint8_t(20), std::uint8_t(30)}) {
      test::appendValue(normals.octree, v);
    }
    for (float v : {0.0f, 0.6f, 0.8f}) test::appendValue(normals.octree, v);
    test::appendValue(normals.octree, std::uint64_t(p));
  }
  test::appendEntry(normals.hierarchy, 1, 0, 2, 0, normals.octree.size());
  writeSeed(dir / "normals.bin", normals);
}

void bench(const std::filesystem::path& dir) {
  using Clock = std::chrono::steady_clock;
  const auto seconds = [](Clock::time_point since) {
    return std::chrono::duration<double>(Clock::now() - since).count();
  };
  const auto start = Clock::now();
  auto octree = openPotree(dir);
  for (std::size_t i = 0; i < octree->nodes().size(); ++i) {
    if (octree->nodes()[i].hierarchy_pending) octree->expandHierarchy(std::int32_t(i));
  }
  const double hierarchy_seconds = seconds(start);
  const auto load_start = Clock::now();
  std::uint64_t points = 0, bytes = 0;
  for (const OctreeNode& node : octree->nodes()) {
    points += octree->loadNode(node).count;
    bytes += node.byte_size;
  }
  const double load_seconds = seconds(load_start);
  std::printf(
      "%zu nodes: open + hierarchy %.4f s; %llu points (%.1f MB) loaded in %.3f s: "
      "%.1f M points/s, %.0f MB/s (one thread)\n",
      octree->nodes().size(), hierarchy_seconds, static_cast<unsigned long long>(points),
      bytes / 1e6, load_seconds, points / load_seconds / 1e6, bytes / load_seconds / 1e6);
}

int run(int argc, char** argv) {
  const std::string command = argc > 1 ? argv[1] : "";
  if (command == "write-handmade" && argc == 3) {
    test::potreeTestDataset().writeTo(argv[2]);
    return 0;
  }
  if (command == "write-fuzz-seeds" && argc == 3) {
    writeFuzzSeeds(argv[2]);
    return 0;
  }
  if (command == "bench" && argc == 3) {
    bench(argv[2]);
    return 0;
  }
  if (command == "dump" && argc == 4) {
    auto octree = openPotree(argv[2]);
    std::ofstream(argv[3]) << dumpOctree(*octree).dump() << "\n";
    return 0;
  }
  std::fprintf(
      stderr,
      "usage: %s write-handmade DIR | dump DIR OUT.json | write-fuzz-seeds DIR | bench DIR\n",
      argv[0]);
  return 2;
}

}  // namespace
}  // namespace parallax

int main(int argc, char** argv) {
  try {
    return parallax::run(argc, argv);
  } catch (const parallax::InputError& e) {
    std::fprintf(stderr, "potree_test_tool: %s\n", e.what());
    return 1;
  }
}
