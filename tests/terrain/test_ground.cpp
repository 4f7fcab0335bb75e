// `process --ground smrf` end to end on an analytic terrain whose labels are known by
// construction: a sloped plane with a hill, three flat-roofed buildings (roof points only, as an
// airborne scan sees them) and trees (points 4-10 m above the ground, the ground beneath them
// still seen). Exact labels point by point, the same bytes at any --memory, --keep-classes, and
// bad parameters naming the step.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <sstream>
#include <stdexcept>

#include "io/las_writer.h"
#include "io/point_file.h"
#include "process/process_runner.h"
#include "support/temp_dir.h"
#include "terrain/ground_triangulation.h"

namespace parallax {
namespace {

using test::TempDir;

// A uniform number in [0, 1) from `n` (SplitMix64): the same scene on every platform.
double unit(std::uint64_t n) {
  std::uint64_t z = (n + 1) * 0x9E3779B97F4A7C15ull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  z ^= z >> 31;
  return double(z >> 11) / 9007199254740992.0;
}

double groundZ(double x, double y) {
  const double dx = x - 45.0, dy = y - 35.0;
  return 100.0 + 0.04 * x + 0.02 * y + 2.5 * std::exp(-(dx * dx + dy * dy) / (2.0 * 18.0 * 18.0));
}

struct Building {
  double x0, y0, x1, y1, height;
  bool covers(double x, double y) const { return x >= x0 && x < x1 && y >= y0 && y < y1; }
};
constexpr std::array<Building, 3> kBuildings = {
    Building{70, 10, 86, 26, 6.0}, Building{15, 55, 27, 69, 8.0}, Building{95, 45, 110, 58, 5.0}};
constexpr std::array<std::array<double, 2>, 8> kTrees = {
    {{10, 10}, {30, 20}, {55, 65}, {60, 15}, {85, 50}, {105, 20}, {110, 72}, {40, 45}}};

struct Scene {
  std::vector<std::array<double, 3>> points;
  std::vector<std::uint8_t> label;  // 2 ground, 1 roof or tree, 7 low noise
  std::vector<int> building;        // the building a roof point is on, -1 otherwise
};

// Ground and roofs on a 0.5 m lattice jittered by up to 0.1 m; 60 points a tree; with `noise`,
// 25 points 10 m below the ground.
Scene scene(bool noise) {
  Scene s;
  std::uint64_t n = 0;
  auto add = [&](double x, double y, double z, std::uint8_t label, int building) {
    s.points.push_back({x, y, z});
    s.label.push_back(label);
    s.building.push_back(building);
  };
  for (int j = 0; j < 160; ++j) {
    for (int i = 0; i < 240; ++i) {
      const double x = 0.25 + 0.5 * i + 0.2 * (unit(n++) - 0.5);
      const double y = 0.25 + 0.5 * j + 0.2 * (unit(n++) - 0.5);
      int on = -1;
      for (std::size_t b = 0; b < kBuildings.size(); ++b) {
        if (kBuildings[b].covers(x, y)) on = int(b);
      }
      if (on < 0) {
        add(x, y, groundZ(x, y), 2, -1);
      } else {
        const Building& b = kBuildings[std::size_t(on)];
        add(x, y, groundZ((b.x0 + b.x1) / 2, (b.y0 + b.y1) / 2) + b.height, 1, on);
      }
    }
  }
  for (const auto& t : kTrees) {
    for (int k = 0; k < 60; ++k) {
      // A point in the crown's ball of radius 3 around 7 m above the ground.
      const double a = 2.0 * 3.14159265358979 * unit(n++), e = 2.0 * unit(n++) - 1.0;
      const double r = 3.0 * std::cbrt(unit(n++)), h = std::sqrt(1.0 - e * e);
      const double x = t[0] + r * h * std::cos(a), y = t[1] + r * h * std::sin(a);
      add(x, y, groundZ(t[0], t[1]) + 7.0 + r * e, 1, -1);
    }
  }
  if (noise) {
    for (int k = 0; k < 25; ++k) {
      const double x = 2.0 + 40.0 * unit(n++), y = 2.0 + 40.0 * unit(n++);
      add(x, y, groundZ(x, y) - 10.0, 7, -1);
    }
  }
  return s;
}

// The scene as LAS (millimetres), every point of class `initial(i)`.
template <class Initial>
std::filesystem::path writeScene(const TempDir& dir, const std::string& name, const Scene& s,
                                 Initial&& initial) {
  PointCloud cloud;
  cloud.count = s.points.size();
  cloud.quantization.scale = {0.001, 0.001, 0.001};
  cloud.positions = Column<Int3>(cloud.count);
  cloud.classification = Column<std::uint8_t>(cloud.count);
  for (std::size_t i = 0; i < cloud.count; ++i) {
    for (int a = 0; a < 3; ++a) {
      (&cloud.positions[i].x)[a] = cloud.quantization.toQuantized(a, s.points[i][std::size_t(a)]);
    }
    cloud.classification[i] = initial(i);
  }
  cloud.computeBounds();
  const std::filesystem::path path = dir / name;
  writeLas(cloud, path);
  return path;
}

ProcessReport run(const std::filesystem::path& in, const std::filesystem::path& out,
                  const std::string& ground, bool keep_classes, std::uint64_t memory_mb = 2048) {
  ProcessOptions options;
  options.inputs = {ConvertInput{.path = in}};
  options.output = out;
  GroundStep step = parseGround(ground);
  step.keep_classes = keep_classes;
  options.steps = {step};
  options.memory_mb = memory_mb;
  return runProcess(options);
}

std::string bytesOf(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST(GroundSmrf, AnalyticTerrainGetsExactlyItsLabels) {
  TempDir dir;
  const Scene s = scene(false);
  const auto in = writeScene(dir, "scene.las", s, [](std::size_t) { return std::uint8_t(0); });
  run(in, dir / "out.las", "smrf", false);
  const PointCloud out = readPointFile(dir / "out.las");
  ASSERT_EQ(out.count, s.points.size());
  ASSERT_TRUE(out.hasClassification());
  std::size_t ground = 0, rest = 0, wrong = 0;
  for (std::size_t i = 0; i < out.count; ++i) {
    ground += out.classification[i] == 2;
    rest += out.classification[i] == 1;
    wrong += out.classification[i] != s.label[i];
  }
  // 38 400 lattice points less 2 476 under the roofs; 480 tree points.
  EXPECT_EQ(ground, 35924u);
  EXPECT_EQ(rest, 2476u + 480u);
  EXPECT_EQ(wrong, 0u);
}

TEST(GroundSmrf, SameBytesAtAnyMemoryBudget) {
  TempDir dir;
  const Scene s = scene(false);
  const auto in = writeScene(dir, "scene.las", s, [](std::size_t) { return std::uint8_t(0); });
  const ProcessReport small = run(in, dir / "small.las", "smrf:cell=1.5,window=20", false, 1);
  const ProcessReport large = run(in, dir / "large.las", "smrf:cell=1.5,window=20", false, 2048);
  EXPECT_GT(small.tiles, 5u);
  EXPECT_EQ(large.tiles, 1u);
  const std::string a = bytesOf(dir / "small.las"), b = bytesOf(dir / "large.las");
  EXPECT_GT(a.size(), 38000u * 20u);
  EXPECT_TRUE(a == b) << "the output depends on --memory";
  for (const char* other : {"pmf", "csf:resolution=1"}) {
    run(in, dir / "small.las", other, false, 1);
    run(in, dir / "large.las", other, false, 2048);
    EXPECT_TRUE(bytesOf(dir / "small.las") == bytesOf(dir / "large.las"))
        << other << ": the output depends on --memory";
  }
}

TEST(GroundSmrf, KeepClassesClassifiesOnlyClassZeroAndOneAndLeavesNoiseOutOfTheSurface) {
  TempDir dir;
  const Scene s = scene(true);
  // The second building's roof already class 6 (building), the noise class 7; the rest 1.
  const auto in = writeScene(dir, "scene.las", s, [&](std::size_t i) {
    return std::uint8_t(s.label[i] == 7 ? 7 : s.building[i] == 1 ? 6 : 1);
  });
  run(in, dir / "out.las", "smrf", true);
  const PointCloud out = readPointFile(dir / "out.las");
  ASSERT_EQ(out.count, s.points.size());
  std::size_t counts[8] = {};
  std::size_t wrong = 0;
  for (std::size_t i = 0; i < out.count; ++i) {
    ++counts[std::min<std::uint8_t>(out.classification[i], 7)];
    const std::uint8_t expected = s.label[i] == 7 ? 7 : s.building[i] == 1 ? 6 : s.label[i];
    wrong += out.classification[i] != expected;
  }
  EXPECT_EQ(counts[2], 35924u);
  EXPECT_EQ(counts[1], 480u + 2476u - 672u);  // the other roofs and the trees
  EXPECT_EQ(counts[6], 672u);                 // 12 m x 14 m at 4 points a square metre
  EXPECT_EQ(counts[7], 25u);
  EXPECT_EQ(wrong, 0u);
  // Without --keep-classes the noise 10 m down is the minimum surface where it falls: the
  // ground above it is then taken for objects (the reason noise is left out).
  run(in, dir / "all.las", "smrf", false);
  const PointCloud all = readPointFile(dir / "all.las");
  std::size_t missed = 0;
  for (std::size_t i = 0; i < all.count; ++i)
    missed += s.label[i] == 2 && all.classification[i] != 2;
  EXPECT_GT(missed, 0u);
}

// Ground called object and object called ground, by kind of object.
struct Confusion {
  std::size_t ground_missed = 0, roofs_taken = 0, trees_taken = 0;
};

Confusion confusion(const Scene& s, const PointCloud& out) {
  Confusion c;
  for (std::size_t i = 0; i < out.count; ++i) {
    const bool ground = out.classification[i] == 2;
    if (s.label[i] == 2) {
      c.ground_missed += !ground;
    } else if (s.building[i] >= 0) {
      c.roofs_taken += ground;
    } else {
      c.trees_taken += ground;
    }
  }
  return c;
}

TEST(GroundCsf, AnalyticTerrainClothSettlesOnTheGroundAndSpansTheRoofs) {
  TempDir dir;
  const Scene s = scene(false);
  const auto in = writeScene(dir, "scene.las", s, [](std::size_t) { return std::uint8_t(0); });
  auto classify = [&](const std::string& parameters) {
    run(in, dir / "out.las", parameters, false);
    const Confusion c = confusion(s, readPointFile(dir / "out.las"));
    std::printf("%s: ground missed %zu, roof points taken %zu, tree points taken %zu\n",
                parameters.c_str(), c.ground_missed, c.roofs_taken, c.trees_taken);
    return c;
  };
  // A 1 m cloth, stiff (3, flat terrain) or less (2, relief), with or without slope smoothing:
  // every label right. The 16 m roofs are pits 5-8 m deep in the upside-down cloud: the cloth
  // spans them; the trees are above ground points of their own cells, which the cloth rests on.
  for (const char* parameters : {"csf:resolution=1", "csf:resolution=1,rigidness=2",
                                 "csf:resolution=1,slope_smoothing=false"}) {
    const Confusion c = classify(parameters);
    EXPECT_EQ(c.ground_missed, 0u) << parameters;
    EXPECT_EQ(c.roofs_taken, 0u) << parameters;
    EXPECT_EQ(c.trees_taken, 0u) << parameters;
  }
  // The softest cloth (rigidness 1, for steep slopes) sags into the roofs' pits.
  EXPECT_GT(classify("csf:resolution=1,rigidness=1").roofs_taken, 100u);
  // Three time steps: the cloth has not come down to the ground yet.
  EXPECT_GT(classify("csf:resolution=1,iterations=3").ground_missed, 35000u);
  // A threshold below the cloth's distance between cells' lowest points and the others.
  EXPECT_GT(classify("csf:resolution=1,class_threshold=0.02").ground_missed, 10000u);
}

ProcessReport runWithHeight(const std::filesystem::path& in, const std::filesystem::path& out,
                            std::uint64_t memory_mb) {
  ProcessOptions options;
  options.inputs = {ConvertInput{.path = in}};
  options.output = out;
  options.steps = {parseGround("smrf"), HeightAboveGroundStep{}};
  options.memory_mb = memory_mb;
  return runProcess(options);
}

TEST(HeightAboveGround, AnalyticTerrainHeightsAndTheSameBytesAtAnyMemory) {
  TempDir dir;
  const Scene s = scene(false);
  const auto in = writeScene(dir, "scene.las", s, [](std::size_t) { return std::uint8_t(0); });
  const ProcessReport tiled = runWithHeight(in, dir / "small.las", 1);
  runWithHeight(in, dir / "large.las", 2048);
  EXPECT_GT(tiled.tiles, 5u);
  EXPECT_TRUE(bytesOf(dir / "small.las") == bytesOf(dir / "large.las"))
      << "the heights depend on --memory";
  const PointCloud out = readPointFile(dir / "large.las");
  const ScalarColumn* hag = out.findScalar("height_above_ground");
  ASSERT_NE(hag, nullptr);
  ASSERT_EQ(hag->type, ScalarType::Float32);
  double worst_ground = 0, worst_tree = 0, worst_roof = 0;
  for (std::size_t i = 0; i < out.count; ++i) {
    const double h = hag->as<float>()[i];
    // Against the analytic ground under the point (the LAS file's millimetres allowed for).
    const double expected = s.points[i][2] - groundZ(s.points[i][0], s.points[i][1]);
    const double error = std::abs(h - expected);
    if (s.label[i] == 2) {
      worst_ground = std::max(worst_ground, std::abs(h));  // a vertex of the triangulation
    } else if (s.building[i] < 0) {
      worst_tree = std::max(worst_tree, error);
    } else {
      worst_roof = std::max(worst_roof, error);
    }
  }
  std::printf(
      "height above ground: worst |h| of ground points %.3g, worst error under trees "
      "%.3g, under roofs %.3g\n",
      worst_ground, worst_tree, worst_roof);
  EXPECT_LT(worst_ground, 1e-4);
  EXPECT_LT(worst_tree, 0.01);  // linear between ground points 0.5 m apart, millimetres in the file
  EXPECT_LT(worst_roof, 0.1);   // linear across a roof 12-16 m wide (measured 0.046)
  EXPECT_GT(worst_roof, 0.0);
}

// The disc an answer depends on (what --height-above-ground clips to the ground's box before it
// decides whether a tile's halo holds every ground point that matters): the triangle's
// circumcircle inside the hull, the disc through the nearest ground point outside it.
TEST(HeightAboveGround, AnswersNameTheDiscTheyDependOn) {
  const std::array<std::array<double, 3>, 3> ground{{{0, 0, 1}, {4, 0, 2}, {0, 3, 3}}};
  const GroundTriangulation triangulation(ground, true);
  const GroundTriangulation::Answer inside = triangulation.at(1, 1);
  // The right triangle's circumcentre is its hypotenuse's midpoint (2, 1.5), radius 2.5.
  EXPECT_NEAR(inside.centre_x, 2.0, 1e-12);
  EXPECT_NEAR(inside.centre_y, 1.5, 1e-12);
  EXPECT_NEAR(inside.radius, 2.5, 1e-12);
  EXPECT_NEAR(inside.reach, std::sqrt(1.25) + 2.5, 1e-12);
  EXPECT_NEAR(inside.z, 1.0 + 0.25 * 1.0 + (1.0 / 3.0) * 2.0, 1e-12);  // linear: 1 + x/4 + 2y/3
  const GroundTriangulation::Answer outside = triangulation.at(10, 10);
  EXPECT_EQ(outside.z, 2.0);  // (4, 0) is the nearest: sqrt(136) against sqrt(149)
  EXPECT_EQ(outside.centre_x, 10.0);
  EXPECT_EQ(outside.centre_y, 10.0);
  EXPECT_NEAR(outside.radius, std::sqrt(136.0), 1e-12);
  // Without the whole hull, an answer outside could depend on any point: no disc.
  const GroundTriangulation partial(ground, false);
  EXPECT_TRUE(std::isinf(partial.at(10, 10).radius));
}

TEST(HeightAboveGround, NoGroundIsAnErrorNamingTheStep) {
  TempDir dir;
  const Scene s = scene(false);
  const auto in = writeScene(dir, "scene.las", s, [](std::size_t) { return std::uint8_t(1); });
  ProcessOptions options;
  options.inputs = {ConvertInput{.path = in}};
  options.output = dir / "out.las";
  options.steps = {HeightAboveGroundStep{}};
  try {
    runProcess(options);
    ADD_FAILURE() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("--height-above-ground: no ground point (class 2)"),
              std::string::npos)
        << e.what();
  }
  EXPECT_FALSE(std::filesystem::exists(dir / "out.las"));
}

TEST(GroundSmrf, BadParametersAreErrorsNamingTheStep) {
  auto message = [](const std::string& value) {
    try {
      parseGround(value);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message("smrf:cell=-1"),
            "--ground smrf:cell=-1: cell must be a positive number, got '-1'");
  EXPECT_EQ(message("smrf:slope=abc"),
            "--ground smrf:slope=abc: slope must be a positive number, got 'abc'");
  EXPECT_EQ(message("smrf:size=3"),
            "--ground smrf:size=3: unknown key 'size' (smrf takes cell, slope, window, scalar, "
            "threshold)");
  EXPECT_EQ(message("smrf:cell"),
            "--ground smrf:cell: expected key=value (cell, slope, window, "
            "scalar, threshold), got 'cell'");
  EXPECT_EQ(message("tin"),
            "--ground tin: expected smrf[:key=value,...], pmf[:key=value,...] or "
            "csf[:key=value,...], got 'tin'");
  EXPECT_EQ(message("csf:rigidness=4"),
            "--ground csf:rigidness=4: rigidness must be a whole number from 1 to 3, got '4'");
  EXPECT_EQ(message("csf:time_step=0"),
            "--ground csf:time_step=0: time_step must be a positive number, got '0'");
  EXPECT_EQ(message("pmf:base=1"), "--ground pmf:base=1: base must be above 1, got '1'");
  EXPECT_EQ(message("pmf:exponential=yes"),
            "--ground pmf:exponential=yes: exponential must be true or false, got 'yes'");
  EXPECT_EQ(message("pmf:cell=2"),
            "--ground pmf:cell=2: unknown key 'cell' (pmf takes max_window_size, slope, "
            "initial_distance, max_distance, cell_size, base, exponential)");
  const GroundStep step = parseGround("smrf:window=12,threshold=0.3");
  EXPECT_EQ(step.smrf.window, 12.0);
  EXPECT_EQ(step.smrf.threshold, 0.3);
  EXPECT_EQ(step.smrf.cell, 1.0);
  EXPECT_EQ(step.smrf.slope, 0.15);
  EXPECT_EQ(step.smrf.scalar, 1.25);
  // A grid over the budget names the step and the way out, and writes nothing.
  TempDir dir;
  const Scene s = scene(false);
  const auto in = writeScene(dir, "scene.las", s, [](std::size_t) { return std::uint8_t(0); });
  try {
    run(in, dir / "out.las", "smrf:cell=0.05", false, 1);
    ADD_FAILURE() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("--ground smrf:cell=0.05,slope=0.15,window=18,scalar="
                                         "1.25,threshold=0.5: the cloud's extent at cell"),
              std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("over --memory 1"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(std::filesystem::exists(dir / "out.las"));
  // A cell so small that the count passes 2^64 (the scene is about 120 x 80: 9.6e21 cells at 1e-9): it was
  // converted to an integer out of range and the message gave the cell as 0.000000 and a wrapped
  // count. The count and its MB are read back from the message and checked against the extent.
  try {
    run(in, dir / "out.las", "smrf:cell=1e-9", false, 2048);
    ADD_FAILURE() << "no error";
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    const std::string lead = "the cloud's extent at cell 1e-09 is ";
    const std::size_t at = what.find(lead);
    ASSERT_NE(at, std::string::npos) << what;
    std::istringstream rest(what.substr(at + lead.size()));
    double cells = 0.0, mb = 0.0;
    std::string word;
    rest >> cells >> word >> mb;
    EXPECT_GT(cells, 100e9 * 60e9) << what;
    EXPECT_LT(cells, 140e9 * 100e9) << what;
    EXPECT_NEAR(mb, cells * 64 / 1048576.0, 1e-5 * mb) << what;
  }
}

}  // namespace
}  // namespace parallax
