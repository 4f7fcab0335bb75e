// `process --ground pmf` against PCL's pcl::ProgressiveMorphologicalFilter (Debian's pcl-tools,
// installed by scripts/install-deps.sh: pcl_progressive_morphological_filter) with the same
// parameters on the same points: a gridded cloud (one point a cell, where the grid filter and
// PCL's point filter are the same definition, terrain/pmf.h) of a sloped plane with a hill, two
// buildings and a tree. The test fails, naming the package, where the tool is missing.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <set>
#include <utility>

#include "io/point_file.h"
#include "process/process_runner.h"
#include "support/temp_dir.h"
#include "terrain/pmf.h"

namespace parallax {
namespace {

using test::TempDir;
using Cell = std::pair<float, float>;

// Heights in 1/64 m: exact as floats, so both programs read the same values and their
// differences are exact in float and in double.
std::filesystem::path writeLattice(const TempDir& dir) {
  const std::filesystem::path path = dir / "lattice.pcd";
  std::ofstream out(path);
  out << "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 9600\nHEIGHT 1\n"
         "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS 9600\nDATA ascii\n";
  for (int j = 0; j < 80; ++j) {
    for (int i = 0; i < 120; ++i) {
      const double dx = i - 45.0, dy = j - 35.0;
      double z =
          100.0 + 0.04 * i + 0.02 * j + 2.5 * std::exp(-(dx * dx + dy * dy) / (2.0 * 18.0 * 18.0));
      if (i >= 70 && i < 86 && j >= 10 && j < 26) z += 6.0;
      if (i >= 15 && i < 27 && j >= 55 && j < 69) z += 8.0;
      if ((i - 10) * (i - 10) + (j - 12) * (j - 12) <= 4) z += 7.0;
      out << i << ' ' << j << ' ' << std::round(z * 64.0) / 64.0 << '\n';
    }
  }
  return path;
}

std::set<Cell> cells(const PointCloud& cloud, bool ground_only) {
  std::set<Cell> out;
  for (std::size_t i = 0; i < cloud.count; ++i) {
    if (ground_only && cloud.classification[i] != 2) continue;
    out.insert({float(cloud.worldX(i)), float(cloud.worldY(i))});
  }
  return out;
}

void expectSameGroundAsPcl(const std::string& pcl_options, const std::string& ours,
                           std::size_t expected_ground) {
  TempDir dir;
  const std::filesystem::path lattice = writeLattice(dir);
  const std::string command = "pcl_progressive_morphological_filter " + lattice.string() + " " +
                              (dir / "pcl.pcd").string() + " " + pcl_options + " > " +
                              (dir / "pcl.log").string() + " 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0)
      << command << " failed: pcl_progressive_morphological_filter comes from the Debian "
      << "package pcl-tools (scripts/install-deps.sh)";
  ProcessOptions options;
  options.inputs = {ConvertInput{.path = lattice}};
  options.output = dir / "ours.las";
  options.steps = {parseGround(ours)};
  options.memory_mb = 1;  // several tiles
  const ProcessReport report = runProcess(options);
  EXPECT_GT(report.tiles, 1u);
  const std::set<Cell> pcl = cells(readPointFile(dir / "pcl.pcd"), false);
  const PointCloud result = readPointFile(dir / "ours.las");
  ASSERT_EQ(result.count, 9600u);
  const std::set<Cell> parallax = cells(result, true);
  EXPECT_EQ(pcl.size(), expected_ground);
  EXPECT_EQ(parallax.size(), expected_ground);
  EXPECT_TRUE(pcl == parallax) << "PCL and Parallax take different cells for ground";
}

TEST(GroundPmf, SameGroundAsPclWithItsDefaults) {
  // Windows 3, 5, 9, 17, 33; thresholds 0.15, 1.55, 2.95, 5.75, 10.
  expectSameGroundAsPcl("", "pmf", 9183);
}

TEST(GroundPmf, SameGroundAsPclWithLinearWindowsAndOtherThresholds) {
  expectSameGroundAsPcl(
      "-max_window_size 21 -slope 0.3 -initial_distance 0.5 -max_distance 3 -base 3 "
      "-exponential 0",
      "pmf:max_window_size=21,slope=0.3,initial_distance=0.5,max_distance=3,base=3,"
      "exponential=false",
      9163);
}

TEST(GroundPmf, WindowSeriesIsPcls) {
  const std::vector<PmfIteration> series = pmfIterations(PmfParameters{});
  ASSERT_EQ(series.size(), 5u);
  const double windows[] = {3, 5, 9, 17, 33}, thresholds[] = {0.15, 1.55, 2.95, 5.75, 10.0};
  for (std::size_t k = 0; k < 5; ++k) {
    EXPECT_EQ(series[k].window, windows[k]);
    EXPECT_EQ(series[k].radius, std::size_t(windows[k]) / 2);
    EXPECT_NEAR(series[k].threshold, thresholds[k], 1e-12);
  }
}

}  // namespace
}  // namespace parallax
