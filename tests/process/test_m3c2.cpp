// --m3c2 end to end on clouds written here: a displaced plane gives the displacement along its
// normal, every value equals an independent brute-force computation of the paper's definitions,
// the bytes do not depend on --memory, and bad parameters are errors naming the step.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <functional>
#include <iterator>
#include <random>

#include "core/error.h"
#include "io/ply_writer.h"
#include "io/point_file.h"
#include "process/process_runner.h"
#include "process_test_clouds.h"
#include "support/temp_dir.h"

namespace parallax {
namespace {

using test::readPositions;
using test::TempDir;
using test::writeCloud;
using test::Xyz;

ProcessReport run(const std::filesystem::path& in, const std::filesystem::path& out,
                  const M3c2Step& step, std::uint64_t memory_mb = 2048) {
  ProcessOptions options;
  options.inputs = {ConvertInput{.path = in}};
  options.output = out;
  options.steps = {step};
  options.memory_mb = memory_mb;
  return runProcess(options);
}

// A surface z = f(x, y) sampled at random over [0, w) x [0, h), with Gaussian noise in z.
template <class F>
std::vector<Xyz> surface(std::size_t count, double w, double h, double sigma, unsigned seed, F f) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> ux(0.0, w), uy(0.0, h);
  std::normal_distribution<double> noise(0.0, sigma);
  std::vector<Xyz> points;
  for (std::size_t i = 0; i < count; ++i) {
    const double x = ux(rng), y = uy(rng);
    points.push_back({x, y, f(x, y) + noise(rng)});
  }
  return points;
}

std::vector<double> column(const PointCloud& cloud, const std::string& name) {
  const ScalarColumn* c = cloud.findScalar(name);
  EXPECT_NE(c, nullptr) << name;
  std::vector<double> out;
  for (std::size_t i = 0; c && i < cloud.count; ++i) out.push_back(c->valueAsDouble(i));
  return out;
}

// The paper's definitions computed here, independently of the process module: the normal as the
// smallest eigenvector of the covariance (eigenvalue in closed form, vector from the cross
// product of two rows of C - lambda I), the cylinder by its two inequalities, plain loops.
struct Expected {
  bool defined = false;
  double distance = NAN, uncertainty = NAN, std1 = NAN, std2 = NAN;
  std::uint32_t count1 = 0, count2 = 0;
};

Xyz smallestEigenvector(const double c[3][3]) {
  const double p1 = c[0][1] * c[0][1] + c[0][2] * c[0][2] + c[1][2] * c[1][2];
  const double q = (c[0][0] + c[1][1] + c[2][2]) / 3.0;
  const double p2 = (c[0][0] - q) * (c[0][0] - q) + (c[1][1] - q) * (c[1][1] - q) +
                    (c[2][2] - q) * (c[2][2] - q) + 2.0 * p1;
  const double p = std::sqrt(p2 / 6.0);
  double b[3][3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) b[i][j] = (c[i][j] - (i == j ? q : 0.0)) / p;
  const double det = b[0][0] * (b[1][1] * b[2][2] - b[1][2] * b[2][1]) -
                     b[0][1] * (b[1][0] * b[2][2] - b[1][2] * b[2][0]) +
                     b[0][2] * (b[1][0] * b[2][1] - b[1][1] * b[2][0]);
  const double r = std::clamp(det / 2.0, -1.0, 1.0);
  const double phi = std::acos(r) / 3.0;
  const double smallest = q + 2.0 * p * std::cos(phi + 2.0 * M_PI / 3.0);
  Xyz rows[3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) rows[i][j] = c[i][j] - (i == j ? smallest : 0.0);
  Xyz best = {0, 0, 0};
  double best_len = -1.0;
  for (int i = 0; i < 3; ++i) {
    for (int j = i + 1; j < 3; ++j) {
      const Xyz& a = rows[i];
      const Xyz& e = rows[j];
      const Xyz x = {a[1] * e[2] - a[2] * e[1], a[2] * e[0] - a[0] * e[2],
                     a[0] * e[1] - a[1] * e[0]};
      const double len = std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
      if (len > best_len) {
        best_len = len;
        best = {x[0] / len, x[1] / len, x[2] / len};
      }
    }
  }
  return best;
}

Expected bruteForce(const Xyz& q, const std::vector<Xyz>& e1, const std::vector<Xyz>& e2,
                    const M3c2Step& step) {
  Expected out;
  std::vector<Xyz> near;
  const double r = step.normal_scale / 2.0;
  for (const Xyz& p : e1) {
    const double dx = p[0] - q[0], dy = p[1] - q[1], dz = p[2] - q[2];
    if (dx * dx + dy * dy + dz * dz <= r * r) near.push_back(p);
  }
  if (near.size() < 3) return out;
  Xyz mean = {0, 0, 0};
  for (const Xyz& p : near)
    for (int a = 0; a < 3; ++a) mean[a] += p[a] / double(near.size());
  double c[3][3] = {};
  for (const Xyz& p : near)
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) c[i][j] += (p[i] - mean[i]) * (p[j] - mean[j]);
  Xyz n = smallestEigenvector(c);
  if (n[2] < 0) n = {-n[0], -n[1], -n[2]};
  out.defined = true;
  auto stats = [&](const std::vector<Xyz>& epoch, std::uint32_t& count, double& position,
                   double& sd) {
    std::vector<double> t;
    for (const Xyz& p : epoch) {
      const Xyz v = {p[0] - q[0], p[1] - q[1], p[2] - q[2]};
      const double along = v[0] * n[0] + v[1] * n[1] + v[2] * n[2];
      const Xyz w = {v[0] - along * n[0], v[1] - along * n[1], v[2] - along * n[2]};
      if (std::abs(along) <= step.half_length &&
          w[0] * w[0] + w[1] * w[1] + w[2] * w[2] <= step.cylinder_radius * step.cylinder_radius)
        t.push_back(along);
    }
    count = std::uint32_t(t.size());
    if (t.empty()) return;
    double m = 0;
    for (double x : t) m += x / double(t.size());
    double s = 0;
    for (double x : t) s += (x - m) * (x - m);
    sd = std::sqrt(s / double(t.size()));
    position = m;
    if (step.median) {
      std::sort(t.begin(), t.end());
      const std::size_t h = t.size() / 2;
      position = t.size() % 2 ? t[h] : (t[h - 1] + t[h]) / 2.0;
    }
  };
  double p1 = NAN, p2 = NAN;
  stats(e1, out.count1, p1, out.std1);
  stats(e2, out.count2, p2, out.std2);
  if (out.count1 && out.count2) {
    out.distance = p2 - p1;
    out.uncertainty =
        1.96 * (std::sqrt(out.std1 * out.std1 / out.count1 + out.std2 * out.std2 / out.count2) +
                step.registration_error);
  }
  return out;
}

M3c2Step stepWith(const std::filesystem::path& epoch2, double d, double r, double h) {
  M3c2Step step;
  step.epoch2 = epoch2;
  step.normal_scale = d;
  step.cylinder_radius = r;
  step.half_length = h;
  return step;
}

TEST(ProcessM3c2, DisplacedPlaneGivesTheDisplacementAlongItsNormal) {
  // Epoch 2: another sampling of the same tilted plane, moved by v; where it is missing (x > 14)
  // the distance is NaN.
  TempDir dir;
  const double sigma = 0.005;
  auto plane = [](double x, double y) { return 0.1 * x + 0.05 * y; };
  const Xyz v = {0.04, -0.03, 0.25};
  std::vector<Xyz> e2 = surface(24000, 20.0, 20.0, sigma, 2, plane);
  std::erase_if(e2, [](const Xyz& p) { return p[0] > 14.0; });
  for (Xyz& p : e2)
    for (int a = 0; a < 3; ++a) p[a] += v[a];
  const auto in = writeCloud(dir, "e1.ply", surface(24000, 20.0, 20.0, sigma, 1, plane));
  M3c2Step step = stepWith(writeCloud(dir, "e2.ply", e2), 2.0, 0.5, 1.0);
  step.registration_error = 0.001;
  run(in, dir / "out.ply", step);
  const PointCloud out = readPointFile(dir / "out.ply");
  ASSERT_EQ(out.count, 24000u);
  const double len = std::sqrt(0.01 + 0.0025 + 1.0);
  const Xyz n = {-0.1 / len, -0.05 / len, 1.0 / len};
  const double expected = v[0] * n[0] + v[1] * n[1] + v[2] * n[2];
  const auto distance = column(out, "m3c2_distance"), lod = column(out, "m3c2_uncertainty");
  const auto count1 = column(out, "m3c2_count1"), count2 = column(out, "m3c2_count2");
  const auto std1 = column(out, "m3c2_std1"), std2 = column(out, "m3c2_std2");
  const auto significant = column(out, "m3c2_significant");
  std::size_t measured = 0, missing = 0;
  for (std::size_t i = 0; i < out.count; ++i) {
    const double x = out.worldX(i);
    if (count2[i] == 0) {
      EXPECT_GT(x, 14.0 - 0.6) << i;
      EXPECT_TRUE(std::isnan(distance[i]) && std::isnan(lod[i])) << i;
      EXPECT_EQ(significant[i], 0.0);
      ++missing;
      continue;
    }
    // The mean of n1 and n2 noisy projections: within 5 standard errors (plus the normal's own
    // tilt error times the displacement across the normal, well under a millimetre here).
    const double standard_error = sigma * std::sqrt(1.0 / count1[i] + 1.0 / count2[i]);
    if (count1[i] >= 20 && count2[i] >= 20) {
      EXPECT_NEAR(distance[i], expected, 5.0 * standard_error + 5e-4) << i;
      ++measured;
    }
    EXPECT_DOUBLE_EQ(
        lod[i],
        1.96 * (std::sqrt(std1[i] * std1[i] / count1[i] + std2[i] * std2[i] / count2[i]) + 0.001));
    EXPECT_EQ(significant[i], std::abs(distance[i]) > lod[i] ? 1.0 : 0.0);
    EXPECT_EQ(significant[i], 1.0);
    EXPECT_NEAR(std1[i], sigma * n[2], 0.5 * sigma);
  }
  EXPECT_GT(measured, 16000u);
  EXPECT_GT(missing, 6000u);
}

TEST(ProcessM3c2, EqualsABruteForceComputationOfThePapersDefinitions) {
  // A bumpy surface and its eroded copy (a bump removed, noise elsewhere), sparse enough that
  // some cylinders are nearly empty; core points every input point, then a separate core file.
  TempDir dir;
  auto bumpy = [](double x, double y) { return 0.3 * std::sin(x) * std::cos(0.7 * y); };
  const auto in = writeCloud(dir, "e1.ply", surface(1500, 10.0, 8.0, 0.01, 3, bumpy));
  std::vector<Xyz> e2raw = surface(1800, 10.0, 8.0, 0.01, 4, bumpy);
  for (Xyz& p : e2raw) p[2] -= 0.2 * std::exp(-((p[0] - 5) * (p[0] - 5) + (p[1] - 4) * (p[1] - 4)));
  M3c2Step step = stepWith(writeCloud(dir, "e2.ply", e2raw), 1.2, 0.4, 0.8);
  step.registration_error = 0.002;
  const std::vector<Xyz> e1 = readPositions(in), e2 = readPositions(step.epoch2);
  auto check = [&](const std::vector<Xyz>& cores, const PointCloud& out) {
    ASSERT_EQ(out.count, cores.size());
    const auto distance = column(out, "m3c2_distance"), lod = column(out, "m3c2_uncertainty");
    const auto count1 = column(out, "m3c2_count1"), count2 = column(out, "m3c2_count2");
    const auto std1 = column(out, "m3c2_std1"), std2 = column(out, "m3c2_std2");
    const auto significant = column(out, "m3c2_significant");
    std::size_t compared = 0;
    for (std::size_t i = 0; i < cores.size(); ++i) {
      const Expected e = bruteForce(cores[i], e1, e2, step);
      ASSERT_EQ(count1[i], e.count1) << i;
      ASSERT_EQ(count2[i], e.count2) << i;
      auto same = [&](double got, double want, const char* what) {
        if (std::isnan(want)) {
          EXPECT_TRUE(std::isnan(got)) << what << " " << i;
        } else {
          EXPECT_NEAR(got, want, 1e-9) << what << " " << i;
        }
      };
      same(distance[i], e.distance, "distance");
      same(lod[i], e.uncertainty, "uncertainty");
      same(std1[i], e.std1, "std1");
      same(std2[i], e.std2, "std2");
      if (!std::isnan(e.distance) && std::abs(std::abs(e.distance) - e.uncertainty) > 1e-9) {
        EXPECT_EQ(significant[i], std::abs(e.distance) > e.uncertainty ? 1.0 : 0.0) << i;
        ++compared;
      }
    }
    EXPECT_GT(compared, cores.size() / 2);
  };
  run(in, dir / "out.ply", step);
  check(e1, readPointFile(dir / "out.ply"));

  // --core-points: the processed cloud is the core points, epoch 1 read as another cloud.
  const auto cores = writeCloud(dir, "cores.ply", surface(300, 10.0, 8.0, 0.0, 5, bumpy));
  M3c2Step with_cores = step;
  with_cores.epoch1 = {in};
  run(cores, dir / "cores_out.ply", with_cores);
  check(readPositions(cores), readPointFile(dir / "cores_out.ply"));

  step.median = true;
  run(in, dir / "median.ply", step);
  check(e1, readPointFile(dir / "median.ply"));
}

std::string bytesOf(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST(ProcessM3c2, SameBytesAtAnyMemoryBudget) {
  // 30 000 points a epoch: 4 096-point slabs at --memory 1, cylinders reaching across them.
  TempDir dir;
  auto bumpy = [](double x, double y) { return 0.3 * std::sin(0.5 * x) + 0.1 * std::cos(y); };
  const auto in = writeCloud(dir, "e1.ply", surface(30000, 60.0, 10.0, 0.02, 6, bumpy));
  const auto e2 = writeCloud(dir, "e2.ply", surface(30000, 60.0, 10.0, 0.02, 7, bumpy));
  const M3c2Step step = stepWith(e2, 1.5, 0.6, 2.0);
  const ProcessReport small = run(in, dir / "small.ply", step, 1);
  const ProcessReport large = run(in, dir / "large.ply", step, 4096);
  EXPECT_GE(small.tiles, 7u);
  EXPECT_EQ(large.tiles, 1u);
  EXPECT_EQ(bytesOf(dir / "small.ply"), bytesOf(dir / "large.ply"));
  const auto cores = writeCloud(dir, "cores.ply", surface(5000, 60.0, 10.0, 0.0, 8, bumpy));
  M3c2Step with_cores = step;
  with_cores.epoch1 = {in};
  run(cores, dir / "cores_small.las", with_cores, 1);
  run(cores, dir / "cores_large.las", with_cores, 4096);
  EXPECT_EQ(bytesOf(dir / "cores_small.las"), bytesOf(dir / "cores_large.las"));
}

std::string thrownMessage(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(ProcessM3c2, BadParametersAreErrorsNamingTheStep) {
  M3c2Step step = stepWith("e2.ply", 1.0, 0.5, 1.0);
  EXPECT_NO_THROW(checkM3c2(step));
  step.cylinder_radius = 0.0;
  EXPECT_EQ(thrownMessage([&] { checkM3c2(step); }),
            "--m3c2 e2.ply: --cylinder-radius R must be a positive number, got 0");
  step = stepWith("e2.ply", -1.0, 0.5, 1.0);
  EXPECT_EQ(thrownMessage([&] { checkM3c2(step); }),
            "--m3c2 e2.ply: --normal-radius D (the normal scale, a diameter) must be a positive "
            "number, got -1");
  step = stepWith("e2.ply", 1.0, 0.5, NAN);
  EXPECT_EQ(thrownMessage([&] { checkM3c2(step); }),
            "--m3c2 e2.ply: --cylinder-half-length H must be a positive number, got nan");
  step = stepWith("e2.ply", 1.0, 0.5, 1.0);
  step.registration_error = -0.1;
  EXPECT_EQ(thrownMessage([&] { checkM3c2(step); }),
            "--m3c2 e2.ply: --registration-error must be a number of at least 0, got -0.1");
  step.registration_error = 0.0;
  step.orientation = NormalOrientation::kSensor;
  EXPECT_EQ(thrownMessage([&] { checkM3c2(step); }),
            "--m3c2 e2.ply: the normals' orientation must be up or X,Y,Z (sensor and propagate "
            "are for --normals)");

  TempDir dir;
  const auto in =
      writeCloud(dir, "e1.ply", surface(100, 5.0, 5.0, 0.0, 9, [](double, double) { return 0.0; }));
  const M3c2Step missing = stepWith(dir / "missing.ply", 1.0, 0.5, 1.0);
  const std::string message = thrownMessage([&] { run(in, dir / "out.ply", missing); });
  EXPECT_NE(message.find("missing.ply"), std::string::npos) << message;
  EXPECT_FALSE(std::filesystem::exists(dir / "out.ply"));
}

}  // namespace
}  // namespace parallax
