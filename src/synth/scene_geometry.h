// The synthetic site the generator scans: a rolling terrain with a road, gabled and flat-roofed
// buildings, and trees (trunk and a porous crown), in local metres near the origin (x east, y
// north, z up) so that float32 output keeps sub-millimetre precision.
//
// Everything here is deterministic for a seed and free of global state: a Site is built once,
// then read concurrently by any number of threads, each with its own Random.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "core/point_cloud.h"

namespace parallax::synth {

struct Vec3 {
  double x = 0, y = 0, z = 0;
};
inline Vec3 operator+(Vec3 a, Vec3 b) {
  return {a.x + b.x, a.y + b.y, a.z + b.z};
}
inline Vec3 operator-(Vec3 a, Vec3 b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
inline Vec3 operator*(Vec3 a, double s) {
  return {a.x * s, a.y * s, a.z * s};
}
inline double dot(Vec3 a, Vec3 b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
inline Vec3 normalized(Vec3 a) {
  return a * (1.0 / std::sqrt(dot(a, a)));
}

// sin and cos of x together, to about 1e-9 absolute for |x| < 1e6: Taylor polynomials on
// [-pi/4, pi/4] after reduction by quadrant. The generator spends most of its time in trig (terrain
// waves, beam directions); this is several times cheaper than libm's correctly rounded sincos and
// far more precise than the output's float32.
inline void fastSinCos(double x, double& s, double& c) {
  // Round to nearest by truncation of x * 2/pi +- 0.5: an inline conversion, where nearbyint and
  // floor are library calls on baseline x86-64.
  double scaled = x * 0.63661977236758134;  // 2 / pi
  double quadrant = double(static_cast<long long>(scaled + (scaled >= 0 ? 0.5 : -0.5)));
  double r = x - quadrant * 1.5707963267948966;
  r -= quadrant * 6.123233995736766e-17;  // the rest of pi / 2
  double r2 = r * r;
  // Reciprocals spelled as products: a division by a constant stays a division without
  // -ffast-math, and two of them in the chain cost more than the rest of the polynomial.
  double sr =
      r * (1 + r2 * (-1.0 / 6 + r2 * (1.0 / 120 + r2 * (-1.0 / 5040 + r2 * (1.0 / 362880)))));
  double cr =
      1 +
      r2 * (-0.5 + r2 * (1.0 / 24 + r2 * (-1.0 / 720 + r2 * (1.0 / 40320 - r2 * (1.0 / 3628800)))));
  // Quadrant fix-up as selects, not a switch: the quadrant is random per beam, and mispredicted
  // jumps would cost more than the polynomials.
  long long q = static_cast<long long>(quadrant);
  bool swap = (q & 1) != 0;
  double sign = (q & 2) != 0 ? -1.0 : 1.0;
  s = (swap ? cr : sr) * sign;
  c = (swap ? -sr : cr) * sign;
}
inline double fastSin(double x) {
  double s, c;
  fastSinCos(x, s, c);
  return s;
}

// splitmix64 (Steele, Lea and Flood, "Fast splittable pseudorandom number generators", 2014):
// one 64-bit state, good enough statistics for scene noise, and trivially seeded per block.
class Random {
 public:
  explicit Random(std::uint64_t seed) : state_(seed) {}
  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  double uniform() { return double(next() >> 11) * 0x1p-53; }  // [0, 1)
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  // Approximately standard normal (Irwin-Hall of four uniforms): no log or trig in the hot loop,
  // and the tails are bounded at 3.5 sigma, which suits range noise.
  double normal() {
    return (uniform() + uniform() + uniform() + uniform() - 2.0) * 1.7320508075688772;
  }

 private:
  std::uint64_t state_;
};

// Mixes a seed and a stream index into an independent seed (for blocks, sites, stations).
std::uint64_t mixSeed(std::uint64_t seed, std::uint64_t stream);

enum class Surface : std::uint8_t { Grass, Road, Wall, Window, Roof, FlatRoof, Bark, Foliage };

// Height z = sum of plane waves: smooth, cheap, with an analytic gradient (true normals).
struct Terrain {
  static constexpr int kWaves = 4;
  std::array<double, kWaves> amplitude{}, kx{}, ky{}, phase{};
  double min_height = 0, max_height = 0;  // bounds of the sum, for ray bracketing
  // Road: the band |x * road_nx + y * road_ny - road_c| < road_half_width.
  double road_nx = 1, road_ny = 0, road_c = 0, road_half_width = 3;

  double height(double x, double y) const;
  double height(double x, double y, double& dhdx, double& dhdy) const;
};

// A convex house: walls |x'| <= half_x, |y'| <= half_y in its rotated frame, a floor at base_z,
// and a gable roof z + slope * |x'| <= ridge_z (flat when slope is 0).
struct Building {
  double cx = 0, cy = 0, cos_a = 1, sin_a = 0;
  double half_x = 5, half_y = 8;
  double base_z = 0, ground_z = 0, eave_z = 3, ridge_z = 3, slope = 0;
  double radius = 0;  // of the footprint's bounding circle
  std::array<std::uint8_t, 3> wall_color{}, roof_color{};
};

struct Tree {
  double cx = 0, cy = 0, ground_z = 0;
  double trunk_radius = 0.25, trunk_top = 3;  // trunk from below ground to trunk_top (absolute z)
  double crown_z = 5, crown_radius = 3, crown_height = 4;  // ellipsoid centre and semi-axes
  double radius = 0;                                       // bounding circle in plan
  std::array<std::uint8_t, 3> leaf_color{};
};

struct Hit {
  double t = 0;
  Vec3 normal;  // unit, outward
  Surface surface = Surface::Grass;
  std::uint32_t object = 0;  // index into Site::objects' owner (building or tree), when relevant
};

// Height of a terrestrial scanner's optical centre above the ground.
constexpr double kStationHeight = 1.8;

struct Site {
  static constexpr double kHalfSize = 100.0;  // the site is [-100, 100] m in x and y
  Terrain terrain;
  std::vector<Building> buildings;
  std::vector<Tree> trees;
  std::vector<Vec3> stations;  // terrestrial scanner positions (optical centre, ~1.8 m up)

  // Objects are numbered buildings first, then trees.
  std::size_t objectCount() const { return buildings.size() + trees.size(); }
  // Bounding circle in plan of object i: centre x, y and radius.
  std::array<double, 3> objectCircle(std::size_t i) const;
};

// A site for `seed`: terrain waves, stations on a ring around the centre, buildings and trees
// placed without overlapping each other or a station.
Site buildSite(std::uint64_t seed, int station_count = 5);

// Nearest surface hit by the ray o + t d (d unit) with 0 < t <= max_t, among the terrain and the
// listed objects; false when it leaves the site or the range. `ground_hint` is a guess of the
// terrain's height where the ray lands (the station's ground), where the search starts. Crowns are
// porous (some rays pass through, the rest stop a random depth inside), which consumes values from
// `random`.
bool castRay(const Site& site, Vec3 o, Vec3 d, double max_t, double ground_hint,
             std::span<const std::uint16_t> objects, Random& random, Hit& hit);

// Colour of the surface at p (plausible materials, patterns, Lambert shading, per-point noise).
Rgba8 surfaceColor(const Site& site, const Hit& hit, Vec3 p, Random& random);

}  // namespace parallax::synth
