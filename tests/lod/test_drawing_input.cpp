// A file drawn whole, read with some attributes and the others later (lod/drawing_input.h
// readMissingAttributes): what `view` does for a LAZ of formats 6-10. The columns read first
// and those read later are exactly a full read's; the positions are not replaced.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <string>
#include <vector>

#include "core/attribute_selection.h"
#include "core/error.h"
#include "io/las_header.h"
#include "io/laz_reader.h"
#include "io/point_file.h"
#include "lod/drawing_input.h"
#include "support/selected_columns.h"
#include "support/test_data.h"

namespace parallax {
namespace {

using test::expectSelected;

class DrawingInputAttributes : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("parallax-drawing-input-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  // Real records (colour, GPS time, extra bytes with descriptions) as a layered LAZ of `format`
  // in chunks of 333 points, so that the reads cross chunks.
  std::filesystem::path layered(const std::string& source, int format) {
    const std::filesystem::path in = test::testDataFile("laz/" + source);
    const std::filesystem::path out = dir_ / (source + "." + std::to_string(format) + ".laz");
    writePointFile(readLaz(in), out,
                   {.las_point_format = format, .laz_chunk_points = 333, .source = in});
    EXPECT_EQ(readLasHeader(out).point_format, format);
    return out;
  }

  std::filesystem::path dir_;
};

TEST_F(DrawingInputAttributes, LayersAskedLaterArriveAsAFullReadHasThem) {
  for (const auto& [source, format] : std::vector<std::pair<std::string, int>>{
           {"extrabytes.laz", 7}, {"point-color-time.las.laz", 8}, {"point-time.las.laz", 6}}) {
    const std::filesystem::path path = layered(source, format);
    SCOPED_TRACE(path.filename().string());
    const PointCloud full = readPointFile(path);
    const std::vector<std::string> file_attributes = readPointFileHeader(path).attributes;
    EXPECT_EQ(file_attributes, full.attributeNames());

    // The first picture's read: what the default look draws.
    AttributeSelection asked = AttributeSelection::only({"red", "intensity", "classification"});
    PointCloud cloud = readPointFile(path, {.attributes = asked});
    expectSelected(full, cloud, asked, "first read");
    ASSERT_FALSE(cloud.findScalar("gps_time")) << "the GPS time layer was decoded at first";
    const Int3* positions = cloud.positions.data();

    // A filter on GPS time, then a pick (every attribute): each arrives as the full read has it.
    EXPECT_EQ(
        readMissingAttributes(path, file_attributes, AttributeSelection::only({"gps_time"}), cloud),
        std::vector<std::string>{"gps_time"});
    asked.add("gps_time");
    expectSelected(full, cloud, asked, "gps_time added");
    // Asked again: nothing is read.
    EXPECT_TRUE(readMissingAttributes(path, file_attributes, asked, cloud).empty());

    const std::vector<std::string> rest =
        readMissingAttributes(path, file_attributes, AttributeSelection{}, cloud);
    EXPECT_FALSE(rest.empty());
    expectSelected(full, cloud, AttributeSelection{}, "every attribute added");
    EXPECT_EQ(cloud.attributeNames(), full.attributeNames());  // scalars in the file's order
    EXPECT_EQ(cloud.source.color, full.source.color);
    EXPECT_EQ(cloud.source.intensity, full.source.intensity);
    EXPECT_EQ(cloud.positions.data(), positions) << "the positions were replaced";
  }
}

TEST_F(DrawingInputAttributes, AFileChangedOnDiskIsAnInputError) {
  const std::filesystem::path path = layered("point-color-time.las.laz", 7);
  const std::vector<std::string> file_attributes = readPointFileHeader(path).attributes;
  PointCloud cloud = readPointFile(path, {.attributes = AttributeSelection::only({})});
  // The same name now holds another file (1 247 points).
  std::filesystem::copy_file(test::testDataFile("laz/1815.laz"), path,
                             std::filesystem::copy_options::overwrite_existing);
  try {
    readMissingAttributes(path, file_attributes, AttributeSelection{}, cloud);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("1065 points"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("1247"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(cloud.hasColors()) << "a failed read added columns";
}

}  // namespace
}  // namespace parallax
