// libFuzzer target for the Potree 2.0 reader: any three files must give an octree whose every
// node loads, or an InputError; never a crash, a hang, an out-of-bounds read or an allocation
// beyond what the input's size justifies.
//
// Input framing (seeds in fuzz/corpus/potree/, written by tests/lod/potree_test_tool):
//   uint32 little endian  metadata.json length M
//   uint32 little endian  hierarchy.bin length H
//   M bytes metadata.json, H bytes hierarchy.bin, the rest octree.bin
// (lengths past the end of the input are cut to what is there).
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "core/error.h"
#include "lod/potree_reader.h"

namespace {

std::uint32_t readLength(const std::uint8_t* data) {
  std::uint32_t value;
  std::memcpy(&value, data, sizeof value);
  return value;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 8) return 0;
  const std::size_t rest = size - 8;
  const std::size_t metadata_size = std::min<std::size_t>(readLength(data), rest);
  const std::size_t hierarchy_size =
      std::min<std::size_t>(readLength(data + 4), rest - metadata_size);
  const auto* p = reinterpret_cast<const std::byte*>(data + 8);
  std::string metadata(reinterpret_cast<const char*>(p), metadata_size);
  std::vector<std::byte> hierarchy(p + metadata_size, p + metadata_size + hierarchy_size);
  std::vector<std::byte> octree(p + metadata_size + hierarchy_size, p + rest);
  try {
    auto octree_reader = parallax::openPotreeFromMemory(std::move(metadata), std::move(hierarchy),
                                                        std::move(octree), "fuzz");
    // Expanding appends; the loop reaches the nodes appended too.
    for (std::size_t i = 0; i < octree_reader->nodes().size(); ++i) {
      try {
        if (octree_reader->nodes()[i].hierarchy_pending) {
          octree_reader->expandHierarchy(std::int32_t(i));
        }
      } catch (const parallax::InputError&) {
      }
      try {
        const parallax::PointCloud cloud = octree_reader->loadNode(octree_reader->nodes()[i]);
        if (cloud.count != octree_reader->nodes()[i].point_count) __builtin_trap();
      } catch (const parallax::InputError&) {
      }
    }
  } catch (const parallax::InputError&) {
  }
  return 0;
}
