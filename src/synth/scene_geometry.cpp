#include "synth/scene_geometry.h"

#include <algorithm>
#include <limits>
#include <numbers>

namespace parallax::synth {
namespace {

constexpr double kNoHit = std::numeric_limits<double>::infinity();

// Ray against the terrain by safeguarded Newton iteration inside the bracket where the ray's
// height lies within the terrain's height bounds. Finds a root, usually the first: a ray that
// grazes one hill and lands behind it may miss that hill's occlusion, which only matters for
// near-horizontal rays far from the scanner.
// `gradient` receives the terrain's gradient at the hit (for its normal). Newton steps where they
// stay inside the bracket, Illinois false position where they do not (grazing beams far from
// the scanner, where f' is nearly zero): bisection alone would need some 25 steps there.
double hitTerrain(const Terrain& terrain, Vec3 o, Vec3 d, double max_t, double ground_hint,
                  std::array<double, 2>& gradient) {
  if (d.z > -1e-4) return kNoHit;  // level or upward rays: the waves are gentle, no hit in range
  double a = std::max(0.0, (o.z - terrain.max_height) / -d.z);
  double b = std::min(max_t, (o.z - terrain.min_height) / -d.z);
  if (a >= b) return kNoHit;
  auto f = [&](double t, double& df) {
    double h = terrain.height(o.x + t * d.x, o.y + t * d.y, gradient[0], gradient[1]);
    df = d.z - gradient[0] * d.x - gradient[1] * d.y;
    return o.z + t * d.z - h;
  };
  // Converged at 1 um: well below the range noise and the output's float32 resolution.
  constexpr double kTolerance = 1e-6;
  double df;
  // Start where the ray meets the hinted ground level: close to the root for gentle terrain.
  double t = std::clamp((o.z - ground_hint) / -d.z, a, b);
  double value = f(t, df);
  double fa = o.z + a * d.z - terrain.max_height;  // >= f(a): the ray is above every wave there
  double fb;
  if (value > 0) {
    a = t, fa = value;
    double db;
    fb = f(b, db);
    if (fb > 0) return kNoHit;  // still above ground at the end of the range
  } else {
    b = t, fb = value;
  }
  int stale = 0;  // Illinois: which end has been kept twice in a row (-1 a, +1 b)
  for (int iteration = 0; iteration < 60; ++iteration) {
    if (std::abs(value) < kTolerance) return t;
    double next = df < 0 ? t - value / df : a - 1.0;
    if (!(next > a && next < b)) {
      double wa = stale == -1 ? 0.5 : 1.0, wb = stale == 1 ? 0.5 : 1.0;
      next = (a * fb * wb - b * fa * wa) / (fb * wb - fa * wa);
      if (!(next > a && next < b)) next = 0.5 * (a + b);
    }
    t = next;
    value = f(t, df);
    if (value > 0) {
      a = t, fa = value;
      stale = 1;  // b kept
    } else {
      b = t, fb = value;
      stale = -1;  // a kept
    }
    if (b - a < kTolerance) return t;
  }
  return t;
}

// Ray against a convex house: the largest entering and smallest leaving plane distances (slab
// method generalised to any convex polytope). Returns t and the entering plane's index.
double hitBuilding(const Building& building, Vec3 o, Vec3 d, int& plane) {
  // Into the building's frame: x' along its width (across the ridge), y' along the ridge.
  double px = o.x - building.cx, py = o.y - building.cy;
  Vec3 lo{px * building.cos_a + py * building.sin_a, -px * building.sin_a + py * building.cos_a,
          o.z};
  Vec3 ld{d.x * building.cos_a + d.y * building.sin_a, -d.x * building.sin_a + d.y * building.cos_a,
          d.z};
  // Planes n . p <= c, in order: +x, -x, +y, -y, floor, roof at +x, roof at -x.
  const double s = building.slope;
  const std::array<Vec3, 7> normals = {
      {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, -1}, {s, 0, 1}, {-s, 0, 1}}};
  const std::array<double, 7> limits = {building.half_x, building.half_x,  building.half_y,
                                        building.half_y, -building.base_z, building.ridge_z,
                                        building.ridge_z};
  double t_near = 0, t_far = kNoHit;
  plane = -1;
  for (int i = 0; i < 7; ++i) {
    double denom = dot(normals[i], ld);
    double num = limits[i] - dot(normals[i], lo);
    if (denom == 0) {
      if (num < 0) return kNoHit;
      continue;
    }
    double t = num / denom;
    if (denom < 0) {
      if (t > t_near) t_near = t, plane = i;
    } else {
      t_far = std::min(t_far, t);
    }
    if (t_near > t_far) return kNoHit;
  }
  return plane < 0 ? kNoHit : t_near;  // plane < 0: the origin is inside
}

Vec3 buildingNormal(const Building& building, int plane) {
  double nx = 0, ny = 0, nz = 0;
  switch (plane) {
    case 0:
      nx = 1;
      break;
    case 1:
      nx = -1;
      break;
    case 2:
      ny = 1;
      break;
    case 3:
      ny = -1;
      break;
    case 4:
      nz = -1;
      break;
    case 5:
      nx = building.slope, nz = 1;
      break;
    default:
      nx = -building.slope, nz = 1;
      break;
  }
  // Back to the world frame (rotation by +a about z).
  return normalized(
      {nx * building.cos_a - ny * building.sin_a, nx * building.sin_a + ny * building.cos_a, nz});
}

// Vertical trunk: the side of the cylinder between ground and trunk top (caps are hidden in the
// ground and the crown).
double hitTrunk(const Tree& tree, Vec3 o, Vec3 d) {
  double ox = o.x - tree.cx, oy = o.y - tree.cy;
  double a = d.x * d.x + d.y * d.y;
  if (a < 1e-12) return kNoHit;
  double b = ox * d.x + oy * d.y;
  double c = ox * ox + oy * oy - tree.trunk_radius * tree.trunk_radius;
  double disc = b * b - a * c;
  if (disc < 0 || c < 0) return kNoHit;
  double t = (-b - std::sqrt(disc)) / a;
  if (t <= 0) return kNoHit;
  double z = o.z + t * d.z;
  return z >= tree.ground_z - 0.5 && z <= tree.trunk_top ? t : kNoHit;
}

// Crown ellipsoid: entry and exit distances.
bool hitCrown(const Tree& tree, Vec3 o, Vec3 d, double& t_in, double& t_out) {
  double ir = 1.0 / tree.crown_radius, iz = 1.0 / tree.crown_height;
  Vec3 so{(o.x - tree.cx) * ir, (o.y - tree.cy) * ir, (o.z - tree.crown_z) * iz};
  Vec3 sd{d.x * ir, d.y * ir, d.z * iz};
  double a = dot(sd, sd), b = dot(so, sd), c = dot(so, so) - 1.0;
  double disc = b * b - a * c;
  if (disc < 0 || c < 0) return false;
  double root = std::sqrt(disc);
  t_in = (-b - root) / a;
  t_out = (-b + root) / a;
  return t_in > 0;
}

}  // namespace

std::uint64_t mixSeed(std::uint64_t seed, std::uint64_t stream) {
  Random random(seed ^ (stream * 0xD1B54A32D192ED03ull));
  random.next();
  return random.next();
}

double Terrain::height(double x, double y) const {
  double h = 0;
  for (int i = 0; i < kWaves; ++i) h += amplitude[i] * fastSin(kx[i] * x + ky[i] * y + phase[i]);
  return h;
}

double Terrain::height(double x, double y, double& dhdx, double& dhdy) const {
  double h = 0, gx = 0, gy = 0;
  for (int i = 0; i < kWaves; ++i) {
    double sin_arg, cos_arg;
    fastSinCos(kx[i] * x + ky[i] * y + phase[i], sin_arg, cos_arg);
    h += amplitude[i] * sin_arg;
    double slope = amplitude[i] * cos_arg;
    gx += slope * kx[i];
    gy += slope * ky[i];
  }
  dhdx = gx, dhdy = gy;
  return h;
}

std::array<double, 3> Site::objectCircle(std::size_t i) const {
  if (i < buildings.size()) return {buildings[i].cx, buildings[i].cy, buildings[i].radius};
  const Tree& tree = trees[i - buildings.size()];
  return {tree.cx, tree.cy, tree.radius};
}

Site buildSite(std::uint64_t seed, int station_count) {
  Site site;
  Random random(mixSeed(seed, 0x517E));

  // Rolling hills: long gentle waves plus shorter ones; slopes stay under about 0.3 so that
  // Newton's method on rays converges in a few steps.
  const std::array<double, Terrain::kWaves> wavelengths = {160, 70, 30, 11};
  const std::array<double, Terrain::kWaves> amplitudes = {2.4, 1.0, 0.3, 0.06};
  Terrain& terrain = site.terrain;
  for (int i = 0; i < Terrain::kWaves; ++i) {
    double angle = random.uniform(0, 2 * std::numbers::pi);
    double k = 2 * std::numbers::pi / wavelengths[i];
    terrain.kx[i] = k * std::cos(angle);
    terrain.ky[i] = k * std::sin(angle);
    terrain.phase[i] = random.uniform(0, 2 * std::numbers::pi);
    terrain.amplitude[i] = amplitudes[i] * random.uniform(0.8, 1.2);
    terrain.max_height += terrain.amplitude[i];
  }
  terrain.min_height = -terrain.max_height;
  double road_angle = random.uniform(0, std::numbers::pi);
  terrain.road_nx = std::cos(road_angle), terrain.road_ny = std::sin(road_angle);
  terrain.road_c = random.uniform(-15, 15);

  // Stations: one near the centre, the others on a ring, as a survey crew would set them up.
  for (int i = 0; i < station_count; ++i) {
    double r = i == 0 ? random.uniform(0, 8) : random.uniform(45, 65);
    double angle = (i == 0 ? random.uniform(0, 2 * std::numbers::pi)
                           : 2 * std::numbers::pi * (i - 1) / std::max(1, station_count - 1)) +
                   random.uniform(-0.3, 0.3);
    double x = r * std::cos(angle), y = r * std::sin(angle);
    site.stations.push_back({x, y, terrain.height(x, y) + kStationHeight});
  }

  struct Circle {
    double x, y, r;
  };
  std::vector<Circle> taken;
  for (const auto& s : site.stations) taken.push_back({s.x, s.y, 2.0});
  auto isFree = [&taken](double x, double y, double r, double gap) {
    for (const auto& c : taken) {
      if (std::hypot(x - c.x, y - c.y) < r + c.r + gap) return false;
    }
    return std::abs(x) + r < Site::kHalfSize && std::abs(y) + r < Site::kHalfSize;
  };

  static constexpr std::array<std::array<std::uint8_t, 3>, 5> kWallColors = {
      {{214, 204, 180}, {226, 222, 212}, {168, 92, 66}, {196, 176, 150}, {185, 190, 186}}};
  static constexpr std::array<std::array<std::uint8_t, 3>, 4> kRoofColors = {
      {{152, 64, 46}, {128, 54, 40}, {78, 80, 88}, {104, 62, 50}}};
  for (int attempt = 0; attempt < 400 && site.buildings.size() < 12; ++attempt) {
    Building b;
    b.cx = random.uniform(-88, 88), b.cy = random.uniform(-88, 88);
    double angle = random.uniform(0, std::numbers::pi);
    b.cos_a = std::cos(angle), b.sin_a = std::sin(angle);
    b.half_x = random.uniform(4, 8), b.half_y = random.uniform(5, 13);
    b.radius = std::hypot(b.half_x, b.half_y);
    if (!isFree(b.cx, b.cy, b.radius, 4.0)) continue;
    double lowest = kNoHit;
    for (double sx : {-1.0, 1.0}) {
      for (double sy : {-1.0, 1.0}) {
        double x = b.cx + sx * b.half_x * b.cos_a - sy * b.half_y * b.sin_a;
        double y = b.cy + sx * b.half_x * b.sin_a + sy * b.half_y * b.cos_a;
        lowest = std::min(lowest, terrain.height(x, y));
      }
    }
    b.ground_z = terrain.height(b.cx, b.cy);
    b.base_z = lowest - 0.5;  // sunk into the slope, so no gap shows under the walls
    int floors = 1 + int(random.uniform() * 3);
    b.eave_z = b.ground_z + 3.0 * floors + 0.4;
    bool gabled = random.uniform() < 0.7;
    b.slope = gabled ? std::tan(random.uniform(0.45, 0.7)) : 0.0;
    b.ridge_z = b.eave_z + b.slope * b.half_x;
    b.wall_color = kWallColors[random.next() % kWallColors.size()];
    b.roof_color = kRoofColors[random.next() % kRoofColors.size()];
    taken.push_back({b.cx, b.cy, b.radius});
    site.buildings.push_back(b);
  }
  for (int attempt = 0; attempt < 600 && site.trees.size() < 70; ++attempt) {
    Tree t;
    t.cx = random.uniform(-95, 95), t.cy = random.uniform(-95, 95);
    t.crown_radius = random.uniform(1.5, 4.0);
    t.radius = t.crown_radius;
    if (!isFree(t.cx, t.cy, t.radius, 1.0)) continue;
    if (std::abs(t.cx * terrain.road_nx + t.cy * terrain.road_ny - terrain.road_c) <
        terrain.road_half_width + t.radius) {
      continue;  // no trees on the road
    }
    t.ground_z = terrain.height(t.cx, t.cy);
    t.trunk_radius = random.uniform(0.12, 0.35);
    t.crown_height = t.crown_radius * random.uniform(1.0, 1.6);
    double clear_trunk = random.uniform(1.5, 3.5);
    t.crown_z = t.ground_z + clear_trunk + t.crown_height;
    t.trunk_top = t.crown_z;
    std::array<std::uint8_t, 3> leaf = {52, 96, 38};
    int tint = int(random.uniform(-18, 18));
    t.leaf_color = {std::uint8_t(leaf[0] + tint / 2), std::uint8_t(leaf[1] + tint),
                    std::uint8_t(leaf[2] + tint / 3)};
    taken.push_back({t.cx, t.cy, t.radius});
    site.trees.push_back(t);
  }
  return site;
}

bool castRay(const Site& site, Vec3 o, Vec3 d, double max_t, double ground_hint,
             std::span<const std::uint16_t> objects, Random& random, Hit& hit) {
  // Nothing beyond the site's edge is kept: stop the terrain search there (most far beams end
  // with one evaluation at the edge instead of a full search).
  const double half = Site::kHalfSize;
  if (d.x != 0) max_t = std::min(max_t, ((d.x > 0 ? half : -half) - o.x) / d.x);
  if (d.y != 0) max_t = std::min(max_t, ((d.y > 0 ? half : -half) - o.y) / d.y);
  if (!(max_t > 0)) return false;
  std::array<double, 2> gradient{};
  double best = hitTerrain(site.terrain, o, d, max_t, ground_hint, gradient);
  Surface surface = Surface::Grass;
  std::uint32_t best_object = 0;
  int best_plane = -1;
  Vec3 crown_normal;
  for (std::uint16_t index : objects) {
    if (index < site.buildings.size()) {
      int plane;
      double t = hitBuilding(site.buildings[index], o, d, plane);
      if (t < best) best = t, surface = Surface::Wall, best_object = index, best_plane = plane;
      continue;
    }
    const Tree& tree = site.trees[index - site.buildings.size()];
    double t = hitTrunk(tree, o, d);
    if (t < best) best = t, surface = Surface::Bark, best_object = index;
    double t_in, t_out;
    if (hitCrown(tree, o, d, t_in, t_out) && t_in < best) {
      // Foliage is porous: a fifth of the beams find a gap, the rest stop a random
      // (exponentially distributed) depth inside, which gives crowns their volume in a scan.
      if (random.uniform() < 0.2) continue;
      double depth = -0.35 * std::log(1.0 - random.uniform());
      double t_hit = t_in + std::min(depth, 0.9 * (t_out - t_in));
      if (t_hit < best) {
        best = t_hit, surface = Surface::Foliage, best_object = index;
        Vec3 p = o + d * t_hit;
        double r2 = tree.crown_radius * tree.crown_radius;
        double h2 = tree.crown_height * tree.crown_height;
        crown_normal =
            normalized({(p.x - tree.cx) / r2, (p.y - tree.cy) / r2, (p.z - tree.crown_z) / h2});
      }
    }
  }
  if (!(best <= max_t)) return false;
  Vec3 p = o + d * best;
  if (std::abs(p.x) > Site::kHalfSize || std::abs(p.y) > Site::kHalfSize) return false;
  hit.t = best;
  hit.object = best_object;
  hit.surface = surface;
  switch (surface) {
    case Surface::Grass: {
      hit.normal = normalized({-gradient[0], -gradient[1], 1});
      const Terrain& t = site.terrain;
      if (std::abs(p.x * t.road_nx + p.y * t.road_ny - t.road_c) < t.road_half_width) {
        hit.surface = Surface::Road;
      }
      break;
    }
    case Surface::Wall: {
      const Building& b = site.buildings[best_object];
      hit.normal = buildingNormal(b, best_plane);
      if (best_plane >= 5) hit.surface = b.slope > 0 ? Surface::Roof : Surface::FlatRoof;
      break;
    }
    case Surface::Bark: {
      const Tree& tree = site.trees[best_object - site.buildings.size()];
      hit.normal = normalized({p.x - tree.cx, p.y - tree.cy, 0});
      break;
    }
    default:
      hit.normal = crown_normal;
      break;
  }
  return true;
}

}  // namespace parallax::synth
