// --m3c2 EPOCH2: Lague, Brodu & Leroux 2013 (M3C2) on every kept point of the processed cloud as a
// core point, written as the tiles' m3c2_* records (m3c2Scalars()). NOTES.md "M3C2" gives the
// definitions and where they leave the paper's choices open.
//
// Per core point q:
// 1. the normal n: PCA plane of epoch 1's points within D / 2 of q (the paper's normal scale D is
//    a diameter), turned up or towards a point;
// 2. for each epoch, the points p inside the cylinder of axis n through q, radius R, reaching H
//    either side of q: |(p - q) . n| <= H and |(p - q) - ((p - q) . n) n| <= R; their projections
//    (p - q) . n give the epoch's position along the normal (mean, or median) and its roughness
//    (standard deviation);
// 3. distance = position 2 - position 1, LoD95 = 1.96 (sqrt(s1^2 / n1 + s2^2 / n2) + reg) (the
//    paper's equation 1: reg inside the bracket), significant when |distance| > LoD95.
//
// Out of core: every neighbourhood has a known radius (D / 2 for the normal, sqrt(R^2 + H^2) for
// the ball holding the cylinder), so each tile is loaded once with that halo and every answer is
// exact; the epochs other than the processed cloud are spilled with the processed cloud's slab
// edges. Sums run over the points in (squared distance, id) order, so the bytes do not depend on
// the tiling.
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "core/error.h"
#include "process/local_plane.h"
#include "process/process_steps.h"
#include "process/tile_queries.h"

namespace parallax {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The 95 % confidence factor of the paper's level of detection (two-sided normal quantile).
constexpr double kConfidence95 = 1.96;

struct M3c2Result {
  double distance = kNaN, uncertainty = kNaN, std1 = kNaN, std2 = kNaN;
  std::uint32_t count1 = 0, count2 = 0;
  std::uint8_t significant = 0;
};

// One epoch inside one cylinder: its projections' count, position (mean or median) and standard
// deviation (over n, not n - 1: the roughness of the points found, as CloudCompare's M3C2 plug-in
// reports it; NOTES.md).
struct CylinderStats {
  std::uint32_t count = 0;
  double position = kNaN, std = kNaN;
};

CylinderStats cylinderStats(const NeighbourIndex& index, const GridPoint& q, const double n[3],
                            const M3c2Step& step, double ball, std::vector<Neighbour>& found,
                            std::vector<double>& along) {
  index.withinRadius(q.x, q.y, q.z, ball, found);
  along.clear();
  const double r2 = step.cylinder_radius * step.cylinder_radius;
  for (const Neighbour& f : found) {
    const GridPoint& p = index.points()[f.at];
    const double v[3] = {p.x - q.x, p.y - q.y, p.z - q.z};
    const double t = v[0] * n[0] + v[1] * n[1] + v[2] * n[2];
    if (std::abs(t) > step.half_length) continue;
    const double w[3] = {v[0] - t * n[0], v[1] - t * n[1], v[2] - t * n[2]};
    if ((w[0] * w[0] + w[1] * w[1]) + w[2] * w[2] > r2) continue;
    along.push_back(t);
  }
  CylinderStats stats;
  stats.count = std::uint32_t(along.size());
  if (along.empty()) return stats;
  double sum = 0.0;
  for (double t : along) sum += t;
  const double mean = sum / double(along.size());
  double squares = 0.0;
  for (double t : along) squares += (t - mean) * (t - mean);
  stats.std = std::sqrt(squares / double(along.size()));
  stats.position = mean;
  if (step.median) {
    std::sort(along.begin(), along.end());
    const std::size_t half = along.size() / 2;
    stats.position = along.size() % 2 ? along[half] : 0.5 * (along[half - 1] + along[half]);
  }
  return stats;
}

// The normal at q from epoch 1's points within D / 2; false when they do not fix a plane.
bool coreNormal(const NeighbourIndex& epoch1, const GridPoint& q, const M3c2Step& step,
                std::vector<Neighbour>& found, double n[3]) {
  epoch1.withinRadius(q.x, q.y, q.z, 0.5 * step.normal_scale, found);
  const LocalPlane plane = fitLocalPlane(epoch1.points(), found);
  if (!plane.valid) return false;
  double toward[3] = {0.0, 0.0, 1.0};
  if (step.orientation == NormalOrientation::kPoint) {
    toward[0] = step.toward[0] - q.x;
    toward[1] = step.toward[1] - q.y;
    toward[2] = step.toward[2] - q.z;
  }
  const double sign =
      plane.normal[0] * toward[0] + plane.normal[1] * toward[1] + plane.normal[2] * toward[2] < 0.0
          ? -1.0
          : 1.0;
  for (int a = 0; a < 3; ++a) n[a] = sign * plane.normal[a];
  return true;
}

M3c2Result m3c2At(const NeighbourIndex& epoch1, const NeighbourIndex& epoch2, const GridPoint& q,
                  const M3c2Step& step, double ball, std::vector<Neighbour>& found,
                  std::vector<double>& along) {
  M3c2Result result;
  double n[3];
  if (!coreNormal(epoch1, q, step, found, n)) return result;
  const CylinderStats a = cylinderStats(epoch1, q, n, step, ball, found, along);
  const CylinderStats b = cylinderStats(epoch2, q, n, step, ball, found, along);
  result.count1 = a.count;
  result.count2 = b.count;
  result.std1 = a.std;
  result.std2 = b.std;
  if (a.count == 0 || b.count == 0) return result;
  result.distance = b.position - a.position;
  result.uncertainty =
      kConfidence95 *
      (std::sqrt(a.std * a.std / a.count + b.std * b.std / b.count) + step.registration_error);
  result.significant = std::abs(result.distance) > result.uncertainty ? 1 : 0;
  return result;
}

TileSet spillEpoch(const std::vector<std::filesystem::path>& paths, const StepContext& context,
                   const std::string& name) {
  std::vector<ConvertInput> inputs;
  for (const std::filesystem::path& path : paths) inputs.push_back(ConvertInput{.path = path});
  const std::filesystem::path dir = context.work_dir / name;
  std::filesystem::create_directories(dir);
  TileSet set = TileSet::spill(inputs, dir, name, context.max_tile_points, &context.tiles.edges(),
                               context.progress);
  if (set.points() == 0) {
    throw InputError({.file = paths.front().string(),
                      .expected = "points to compare with for " + context.label,
                      .found = "none"});
  }
  return set;
}

}  // namespace

std::vector<StepScalar> m3c2Scalars() {
  return {{"m3c2_distance", ScalarType::Float64},  {"m3c2_uncertainty", ScalarType::Float64},
          {"m3c2_significant", ScalarType::UInt8}, {"m3c2_count1", ScalarType::UInt32},
          {"m3c2_count2", ScalarType::UInt32},     {"m3c2_std1", ScalarType::Float64},
          {"m3c2_std2", ScalarType::Float64}};
}

void runM3c2Step(const M3c2Step& step, const StepContext& context) {
  checkM3c2(step);
  const TileSet& tiles = context.tiles;
  const TileSet epoch2 = spillEpoch({step.epoch2}, context, "m3c2_epoch2");
  const bool own_epoch1 = step.epoch1.empty();
  const TileSet epoch1_file =
      own_epoch1 ? TileSet{} : spillEpoch(step.epoch1, context, "m3c2_epoch1");
  // A hair over the cylinder's corner distance: every point inside the cylinder is inside the
  // ball whatever the rounding of its squared distance, and the cylinder's own tests decide.
  const double ball =
      std::sqrt(step.cylinder_radius * step.cylinder_radius + step.half_length * step.half_length) *
      (1.0 + 1e-9);
  const double reach = std::max(0.5 * step.normal_scale, ball);
  // The halo a hair wider still, so `covers` holds at the slab's edge.
  const double halo = reach * (1.0 + 1e-9);
  auto bar = context.progress ? context.progress(context.label, tiles.points()) : nullptr;
  tbb::enumerable_thread_specific<std::pair<std::vector<Neighbour>, std::vector<double>>> scratch;
  for (std::size_t t = 0; t < tiles.tiles(); ++t) {
    const std::vector<GridPoint> points = tiles.readPoints(t);
    const std::vector<std::uint8_t> kept = tiles.readKept(t);
    TileNeighbourhood own = loadNeighbourhood(tiles, t, own_epoch1 ? halo : 0.0, points, kept);
    const std::vector<GridPoint> queries(own.points.begin(), own.points.begin() + own.core);
    const std::vector<std::uint32_t> slot = own.slot;
    TileNeighbourhood hood1 = own_epoch1 ? std::move(own) : loadAround(epoch1_file, t, halo);
    own = {};
    TileNeighbourhood hood2 = loadAround(epoch2, t, halo);
    for (const GridPoint& q : queries) {
      if (!hood1.covers(q, reach) || !hood2.covers(q, reach)) {
        throw std::logic_error(context.label + ": a cylinder reaches past its tile's halo");
      }
    }
    const NeighbourIndex index1(std::move(hood1.points));
    const NeighbourIndex index2(std::move(hood2.points));
    std::vector<M3c2Result> results(points.size());
    const std::vector<std::uint32_t> order = spatialOrder(queries);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, order.size(), 512),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                        auto& [found, along] = scratch.local();
                        for (std::size_t j = range.begin(); j != range.end(); ++j) {
                          const std::uint32_t i = order[j];
                          results[slot[i]] =
                              m3c2At(index1, index2, queries[i], step, ball, found, along);
                        }
                      });
    auto column = [&](const std::string& name, auto member) {
      using T = std::remove_cvref_t<decltype(results[0].*member)>;
      std::vector<T> values(results.size());
      for (std::size_t i = 0; i < results.size(); ++i) values[i] = results[i].*member;
      tiles.writeRecords<T>(t, name, values);
    };
    column("m3c2_distance", &M3c2Result::distance);
    column("m3c2_uncertainty", &M3c2Result::uncertainty);
    column("m3c2_significant", &M3c2Result::significant);
    column("m3c2_count1", &M3c2Result::count1);
    column("m3c2_count2", &M3c2Result::count2);
    column("m3c2_std1", &M3c2Result::std1);
    column("m3c2_std2", &M3c2Result::std2);
    if (bar) bar->advance(points.size());
  }
}

}  // namespace parallax
