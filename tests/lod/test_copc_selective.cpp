// The COPC reader asked for some attributes (Octree::selectAttributes): every node holds exactly
// the full node's columns for those and no others, and info() describes what the nodes carry.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <memory>
#include <string>

#include "lod/copc_reader.h"
#include "support/selected_columns.h"
#include "support/test_data.h"

namespace parallax {
namespace {

using test::expectSelected;
using test::selections;

// COPC nodes read with selectAttributes equal the full nodes' asked columns; info() describes
// the columns the nodes then carry.
TEST(CopcSelective, NodesGiveTheAskedColumns) {
  for (const char* name : {"ellipsoid.copc.laz", "simple.copc.laz"}) {
    const std::filesystem::path path = test::testDataFile(std::string("laz/") + name);
    const std::unique_ptr<Octree> full = openCopc(path);
    for (std::size_t i = 0; i < full->nodes().size(); ++i) full->expandHierarchy(std::int32_t(i));
    for (const AttributeSelection& selection : selections()) {
      const std::unique_ptr<Octree> part = openCopc(path);
      part->selectAttributes(selection);
      const PointCloud prototype = part->loadNode(part->nodes()[0]);
      EXPECT_EQ(part->info().attributes, prototype.attributeNames()) << name;
      EXPECT_EQ(part->info().has_colors, prototype.hasColors()) << name;
      for (std::size_t i = 0; i < part->nodes().size(); ++i) part->expandHierarchy(std::int32_t(i));
      ASSERT_EQ(part->nodes().size(), full->nodes().size());
      for (std::size_t i = 0; i < full->nodes().size(); ++i) {
        expectSelected(full->loadNode(full->nodes()[i]), part->loadNode(part->nodes()[i]),
                       selection, std::string(name) + " node " + full->nodes()[i].name);
      }
    }
  }
}

// Picking and profiles read nodes whole (loadNodeWhole) while the drawn nodes carry only what
// the picture needs: the same points, every column, whatever was selected.
TEST(CopcSelective, WholeNodesKeepEveryColumnUnderASelection) {
  const std::filesystem::path path = test::testDataFile("laz/simple.copc.laz");
  const std::unique_ptr<Octree> full = openCopc(path);
  const std::unique_ptr<Octree> part = openCopc(path);
  part->selectAttributes(AttributeSelection::only({"red"}));
  EXPECT_EQ(std::count(part->info().attributes.begin(), part->info().attributes.end(),
                       std::string("intensity")),
            0);
  for (std::size_t i = 0; i < full->nodes().size(); ++i) {
    full->expandHierarchy(std::int32_t(i));
    part->expandHierarchy(std::int32_t(i));
  }
  ASSERT_EQ(part->nodes().size(), full->nodes().size());
  for (std::size_t i = 0; i < full->nodes().size(); ++i) {
    const PointCloud expected = full->loadNode(full->nodes()[i]);
    const PointCloud whole = part->loadNodeWhole(part->nodes()[i]);
    expectSelected(expected, whole, AttributeSelection(), "node " + full->nodes()[i].name);
    EXPECT_EQ(whole.attributeNames(), expected.attributeNames());
    EXPECT_FALSE(part->loadNode(part->nodes()[i]).hasIntensity());
  }
}

}  // namespace
}  // namespace parallax
