// A hand-made Potree 2.0 dataset written byte by byte, in the shape PotreeConverter 2 really
// writes (docs/FORMATS.md): LAS attributes with scan angle rank declared uint8 holding negative
// bytes, 16-bit colour, type 1 on an inner node, a proxy into a second chunk, an entry no chunk
// refers to (inside the first chunk and between the chunks), metadata hierarchy.depth 0.
//
//   hierarchy.bin: [0, 88)    chunk of r: r (type 1, mask 0x41), r0 (leaf), r6 (proxy, mask 0),
//                             one unreferenced entry
//                  [88, 110)  an entry nobody refers to
//                  [110, 154) chunk of r6: r6 (type 1, mask 0x02), r61 (leaf)
//   octree.bin:    r: 2 points, r0: 1, r6: 1, r61: 2 (35-byte records, in that order)
//
// Used by test_potree_reader, by potree_test_tool (the real-client test) and to seed the fuzzer.
#pragma once

#include <array>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace parallax::test {

struct PotreeTestPoint {
  std::int32_t x, y, z;
  std::uint16_t intensity;
  std::uint8_t return_number, number_of_returns, classification;
  std::uint8_t scan_angle_rank;  // LAS's signed byte, stored as PotreeConverter stores it
  std::uint8_t user_data;
  std::uint16_t point_source_id;
  double gps_time;
  std::uint16_t red, green, blue;
};

inline constexpr std::size_t kPotreeTestRecordSize = 35;
inline constexpr std::size_t kPotreeTestEntrySize = 22;

struct PotreeTestDataset {
  std::string metadata;
  std::vector<std::byte> hierarchy, octree;

  void writeTo(const std::filesystem::path& dir) const {
    std::filesystem::create_directories(dir);
    std::ofstream(dir / "metadata.json", std::ios::binary) << metadata;
    std::ofstream(dir / "hierarchy.bin", std::ios::binary)
        .write(reinterpret_cast<const char*>(hierarchy.data()), std::streamsize(hierarchy.size()));
    std::ofstream(dir / "octree.bin", std::ios::binary)
        .write(reinterpret_cast<const char*>(octree.data()), std::streamsize(octree.size()));
  }
};

// The six points, in octree.bin order: r (0, 1), r0 (2), r6 (3), r61 (4, 5).
inline std::vector<PotreeTestPoint> potreeTestPoints() {
  return {
      {1000, 2000, 3000, 0, 1, 1, 2, 0xF1, 7, 65000, 123456.789, 65535, 0, 25700},
      {8000, 9000, 9000, 65535, 2, 2, 5, 90, 0, 1, -1.5, 512, 1000, 65280},
      {2500, 2500, 2500, 1234, 1, 3, 6, 0xA6, 255, 2, 0.0, 257, 514, 771},
      {6000, 7000, 1000, 42, 3, 3, 2, 0, 1, 3, 1e9, 65535, 65535, 65535},
      {5500, 6000, 4000, 7, 1, 1, 9, 1, 2, 4, 2.25, 0, 0, 0},
      {7000, 7400, 4999, 300, 2, 2, 31, 0xFF, 3, 5, 3.5, 12850, 25700, 38550},
  };
}

template <class T>
void appendValue(std::vector<std::byte>& out, T value) {
  const auto* p = reinterpret_cast<const std::byte*>(&value);
  out.insert(out.end(), p, p + sizeof(T));
}

inline void appendEntry(std::vector<std::byte>& out, std::uint8_t type, std::uint8_t mask,
                        std::uint32_t points, std::uint64_t offset, std::uint64_t size) {
  appendValue(out, type);
  appendValue(out, mask);
  appendValue(out, points);
  appendValue(out, offset);
  appendValue(out, size);
}

// Overwrites entry `index` (counted from the start of hierarchy.bin) in place.
inline void setEntry(std::vector<std::byte>& hierarchy, std::size_t index, std::uint8_t type,
                     std::uint8_t mask, std::uint32_t points, std::uint64_t offset,
                     std::uint64_t size) {
  std::vector<std::byte> entry;
  appendEntry(entry, type, mask, points, offset, size);
  std::memcpy(hierarchy.data() + index * kPotreeTestEntrySize, entry.data(), entry.size());
}

inline nlohmann::ordered_json potreeTestAttribute(const std::string& name, int elements,
                                                  int element_size, const std::string& type,
                                                  std::vector<double> min,
                                                  std::vector<double> max) {
  return {{"name", name},
          {"description", ""},
          {"size", elements * element_size},
          {"numElements", elements},
          {"elementSize", element_size},
          {"type", type},
          {"min", min},
          {"max", max}};
}

// The metadata as PotreeConverter 2 writes it (its key order and attribute names).
inline nlohmann::ordered_json potreeTestMetadata(std::uint64_t points, std::uint64_t first_chunk) {
  using Json = nlohmann::ordered_json;
  Json attributes = Json::array();
  attributes.push_back(
      potreeTestAttribute("position", 3, 4, "int32", {1001, 2002, 31}, {1008, 2009, 39}));
  attributes.push_back(potreeTestAttribute("intensity", 1, 2, "uint16", {0}, {65535}));
  attributes.push_back(potreeTestAttribute("return number", 1, 1, "uint8", {1}, {3}));
  attributes.push_back(potreeTestAttribute("number of returns", 1, 1, "uint8", {1}, {3}));
  attributes.push_back(potreeTestAttribute("classification", 1, 1, "uint8", {2}, {31}));
  attributes.push_back(potreeTestAttribute("scan angle rank", 1, 1, "uint8", {0}, {255}));
  attributes.push_back(potreeTestAttribute("user data", 1, 1, "uint8", {0}, {255}));
  attributes.push_back(potreeTestAttribute("point source id", 1, 2, "uint16", {1}, {65000}));
  attributes.push_back(potreeTestAttribute("gps-time", 1, 8, "double", {-1.5}, {1e9}));
  attributes.push_back(
      potreeTestAttribute("rgb", 3, 2, "uint16", {0, 0, 0}, {65535, 65535, 65535}));
  return {{"version", "2.0"},
          {"name", "handmade"},
          {"description", ""},
          {"points", points},
          {"projection", ""},
          {"hierarchy", {{"firstChunkSize", first_chunk}, {"stepSize", 4}, {"depth", 0}}},
          {"offset", {1000, 2000, 30}},
          {"scale", {0.001, 0.001, 0.001}},
          {"spacing", 0.5},
          {"boundingBox", {{"min", {1000, 2000, 30}}, {"max", {1010, 2010, 40}}}},
          {"encoding", "DEFAULT"},
          {"attributes", attributes}};
}

inline PotreeTestDataset potreeTestDataset() {
  PotreeTestDataset d;
  for (const auto& p : potreeTestPoints()) {
    appendValue(d.octree, p.x);
    appendValue(d.octree, p.y);
    appendValue(d.octree, p.z);
    appendValue(d.octree, p.intensity);
    appendValue(d.octree, p.return_number);
    appendValue(d.octree, p.number_of_returns);
    appendValue(d.octree, p.classification);
    appendValue(d.octree, p.scan_angle_rank);
    appendValue(d.octree, p.user_data);
    appendValue(d.octree, p.point_source_id);
    appendValue(d.octree, p.gps_time);
    appendValue(d.octree, p.red);
    appendValue(d.octree, p.green);
    appendValue(d.octree, p.blue);
  }
  constexpr std::uint64_t R = kPotreeTestRecordSize;
  // Chunk of r: the root is inner but typed 1 (leaf), as PotreeConverter writes it.
  appendEntry(d.hierarchy, 1, 0x41, 2, 0, 2 * R);
  appendEntry(d.hierarchy, 1, 0x00, 1, 2 * R, R);
  appendEntry(d.hierarchy, 2, 0x00, 1, 110, 44);   // r6: proxy into the chunk at 110
  appendEntry(d.hierarchy, 1, 0x00, 9, 0, 9 * R);  // unreferenced, inside the first chunk
  appendEntry(d.hierarchy, 0, 0xFF, 5, 999, 1);    // unreferenced, between the chunks
  // Chunk of r6: r6 again, then its child r61.
  appendEntry(d.hierarchy, 1, 0x02, 1, 3 * R, R);
  appendEntry(d.hierarchy, 1, 0x00, 2, 4 * R, 2 * R);
  d.metadata = potreeTestMetadata(6, 4 * kPotreeTestEntrySize).dump(2);
  return d;
}

}  // namespace parallax::test
