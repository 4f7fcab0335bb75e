// Colours of the synthetic site's surfaces. The aim is a cloud that reads as a scan at a glance
// (grass patches, a road, plastered walls with windows, tiled roofs, bark, foliage) and gives a
// renderer's colour path something to show; it is not a radiometric model.
#include <algorithm>
#include <cmath>

#include "synth/scene_geometry.h"

namespace parallax::synth {
namespace {

using Rgb = std::array<double, 3>;

// Sun from the south-east, high: Lambert shading plus a generous ambient term, as a photographed
// (textured) scan on an overcast-to-sunny day looks.
const Vec3 kSun = normalized({0.4, -0.3, 0.85});

double fract(double v) {
  return v - std::floor(v);
}

Rgb toRgb(const std::array<std::uint8_t, 3>& c) {
  return {double(c[0]), double(c[1]), double(c[2])};
}

Rgb mix(const Rgb& a, const Rgb& b, double w) {
  return {a[0] + (b[0] - a[0]) * w, a[1] + (b[1] - a[1]) * w, a[2] + (b[2] - a[2]) * w};
}

// Windows on a wall: a regular grid of panes per floor (3 m), stopping below the eaves.
bool isWindow(const Building& b, Vec3 p, const Vec3& normal) {
  double px = p.x - b.cx, py = p.y - b.cy;
  double lx = px * b.cos_a + py * b.sin_a, ly = -px * b.sin_a + py * b.cos_a;
  // The coordinate along the wall: local y on the long walls (normal along x'), x' on gable ends.
  double nx_local = normal.x * b.cos_a + normal.y * b.sin_a;
  double along = std::abs(nx_local) > 0.5 ? ly : lx;
  double height = p.z - b.ground_z;
  if (height < 0.8 || p.z > b.eave_z - 0.6) return false;
  double u = fract((along + 50.0) / 3.2), v = fract(height / 3.0);
  return u > 0.32 && u < 0.68 && v > 0.3 && v < 0.75;
}

}  // namespace

Rgba8 surfaceColor(const Site& site, const Hit& hit, Vec3 p, Random& random) {
  Rgb color;
  double jitter = 8;  // per-point variation, in 8-bit steps
  switch (hit.surface) {
    case Surface::Grass: {
      // Low-frequency patches of lusher and drier grass.
      double patch = 0.5 + 0.5 * fastSin(0.21 * p.x + 1.3) * fastSin(0.17 * p.y + 0.4);
      double fine = 0.5 + 0.5 * fastSin(1.7 * p.x + 0.9 * p.y);
      color = mix(Rgb{78, 118, 48}, Rgb{132, 142, 70}, 0.8 * patch + 0.2 * fine);
      jitter = 14;
      break;
    }
    case Surface::Road: {
      const Terrain& t = site.terrain;
      double across = std::abs(p.x * t.road_nx + p.y * t.road_ny - t.road_c);
      color = across > t.road_half_width - 0.25 ? Rgb{196, 196, 190} : Rgb{98, 97, 95};
      jitter = 10;
      break;
    }
    case Surface::Wall:
    case Surface::Window: {
      const Building& b = site.buildings[hit.object];
      color = isWindow(b, p, hit.normal) ? Rgb{52, 62, 78} : toRgb(b.wall_color);
      jitter = 6;
      break;
    }
    case Surface::Roof: {
      const Building& b = site.buildings[hit.object];
      double px = p.x - b.cx, py = p.y - b.cy;
      double lx = px * b.cos_a + py * b.sin_a;
      // Courses of tiles every 0.33 m down the slope, with a shadowed lower edge.
      double course = fract(std::abs(lx) / 0.33);
      color = toRgb(b.roof_color);
      if (course < 0.18) color = mix(color, Rgb{0, 0, 0}, 0.35);
      break;
    }
    case Surface::FlatRoof:
      color = {132, 130, 124}, jitter = 12;
      break;
    case Surface::Bark:
      color = {94, 72, 52}, jitter = 10;
      break;
    case Surface::Foliage: {
      const Tree& tree = site.trees[hit.object - site.buildings.size()];
      color = toRgb(tree.leaf_color);
      jitter = 22;  // leaves at every angle: strong per-point variation
      break;
    }
  }
  double shade = 0.62 + 0.38 * std::max(0.0, dot(hit.normal, kSun));
  double noise = (random.uniform() - 0.5) * 2.0 * jitter;
  Rgba8 out;
  auto channel = [&](double value) {
    return std::uint8_t(std::clamp(std::lround(value * shade + noise), 0l, 255l));
  };
  out.r = channel(color[0]);
  out.g = channel(color[1]);
  out.b = channel(color[2]);
  out.a = 255;
  return out;
}

}  // namespace parallax::synth
