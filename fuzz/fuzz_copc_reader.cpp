// libFuzzer target for the COPC reader: any bytes must give an octree whose every page reads and
// every node loads with the points its entry says, or an InputError; never a crash, a hang, an
// out-of-bounds read or an allocation beyond what the input's size justifies.
//
// The input is a whole file. Seeds: a small file written by Parallax with child pages three levels
// deep (fuzz/corpus/copc/) and the two real COPC files of PARALLAX_TEST_DATA/laz
// (fuzz/CMakeLists.txt lists them).
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/error.h"
#include "lod/copc_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto* p = reinterpret_cast<const std::byte*>(data);
  std::vector<std::byte> bytes(p, p + size);
  try {
    auto octree = parallax::openCopcFromMemory(std::move(bytes), "fuzz.copc.laz");
    // Expanding appends; the loop reaches the nodes appended too.
    for (std::size_t i = 0; i < octree->nodes().size(); ++i) {
      try {
        if (octree->nodes()[i].hierarchy_pending) octree->expandHierarchy(std::int32_t(i));
      } catch (const parallax::InputError&) {
      }
      try {
        const parallax::OctreeNode node = octree->nodes()[i];
        const parallax::PointCloud cloud = octree->loadNode(node);
        if (!node.hierarchy_pending && cloud.count != node.point_count) __builtin_trap();
      } catch (const parallax::InputError&) {
      }
    }
  } catch (const parallax::InputError&) {
  }
  return 0;
}
