// --subsample voxel:SIZE | spacing:D | random:N: the tiles' "kept" flags lowered for the points
// not taken.
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

#include "process/process_steps.h"
#include "process/tile_queries.h"

namespace parallax {

namespace {

// The corner the voxels are aligned to: the minimum of the kept points.
std::array<double, 3> keptMinimum(const TileSet& tiles) {
  std::array<double, 3> corner = {TileSet::kInfinity, TileSet::kInfinity, TileSet::kInfinity};
  for (std::size_t t = 0; t < tiles.tiles(); ++t) {
    const std::vector<GridPoint> points = tiles.readPoints(t);
    const std::vector<std::uint8_t> kept = tiles.readKept(t);
    for (std::size_t i = 0; i < points.size(); ++i) {
      if (!kept[i]) continue;
      corner[0] = std::min(corner[0], points[i].x);
      corner[1] = std::min(corner[1], points[i].y);
      corner[2] = std::min(corner[2], points[i].z);
    }
  }
  return corner;
}

// One point per occupied voxel: the one nearest the centroid of the voxel's points (ties: the
// smaller id). A voxel reaches at most SIZE from any of its points, so a halo of SIZE gives each
// tile every point of the voxels its points are in; each tile decides for its own points only,
// and all tiles compute a voxel's centroid from the same points in the same (id) order.
void voxelSubsample(const SubsampleStep& step, const StepContext& context) {
  const TileSet& tiles = context.tiles;
  const std::array<double, 3> corner = keptMinimum(tiles);
  auto bar = context.progress ? context.progress(context.label, tiles.points()) : nullptr;
  for (std::size_t t = 0; t < tiles.tiles(); ++t) {
    const std::vector<GridPoint> points = tiles.readPoints(t);
    std::vector<std::uint8_t> kept = tiles.readKept(t);
    const TileNeighbourhood hood = loadNeighbourhood(tiles, t, step.size * 1.0001, points, kept);
    struct Keyed {
      std::array<std::int64_t, 3> voxel;
      std::uint64_t id;
      std::uint32_t at;
      bool operator<(const Keyed& o) const {
        return voxel < o.voxel || (voxel == o.voxel && id < o.id);
      }
    };
    std::vector<Keyed> keyed(hood.points.size());
    for (std::size_t i = 0; i < hood.points.size(); ++i) {
      const GridPoint& p = hood.points[i];
      keyed[i] = {{std::int64_t(std::floor((p.x - corner[0]) / step.size)),
                   std::int64_t(std::floor((p.y - corner[1]) / step.size)),
                   std::int64_t(std::floor((p.z - corner[2]) / step.size))},
                  p.id,
                  std::uint32_t(i)};
    }
    tbb::parallel_sort(keyed.begin(), keyed.end());
    for (std::size_t i = 0; i < hood.core; ++i) kept[hood.slot[i]] = 0;
    for (std::size_t begin = 0; begin < keyed.size();) {
      std::size_t end = begin + 1;
      while (end < keyed.size() && keyed[end].voxel == keyed[begin].voxel) ++end;
      const GridPoint& base = hood.points[keyed[begin].at];
      double c[3] = {0, 0, 0};
      for (std::size_t j = begin; j < end; ++j) {
        const GridPoint& p = hood.points[keyed[j].at];
        c[0] += p.x - base.x;
        c[1] += p.y - base.y;
        c[2] += p.z - base.z;
      }
      const double n = double(end - begin);
      for (double& v : c) v /= n;
      std::size_t best = begin;
      double best_d2 = TileSet::kInfinity;
      for (std::size_t j = begin; j < end; ++j) {
        const GridPoint& p = hood.points[keyed[j].at];
        const double d2 =
            squaredDistance(p.x - base.x, p.y - base.y, p.z - base.z, c[0], c[1], c[2]);
        if (d2 < best_d2) {  // ids ascend within the voxel: the first of equals wins
          best_d2 = d2;
          best = j;
        }
      }
      if (keyed[best].at < hood.core) kept[hood.slot[keyed[best].at]] = 1;
      begin = end;
    }
    tiles.writeRecords<std::uint8_t>(t, "kept.next", kept);
    if (bar) bar->advance(points.size());
  }
  tiles.renameAll("kept.next", "kept");
}

// A fixed permutation of the ids (SplitMix64's finaliser is a bijection): the N kept points of
// smallest hash are a uniform sample, the same whatever the tiling.
std::uint64_t shuffledId(std::uint64_t id) {
  std::uint64_t z = id + 0x9E3779B97F4A7C15ull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

void randomSubsample(const SubsampleStep& step, const StepContext& context) {
  const TileSet& tiles = context.tiles;
  constexpr int kBits = 16;
  std::vector<std::uint64_t> histogram(std::size_t(1) << kBits, 0);
  std::uint64_t kept_points = 0;
  for (std::size_t t = 0; t < tiles.tiles(); ++t) {
    const std::vector<GridPoint> points = tiles.readPoints(t);
    const std::vector<std::uint8_t> kept = tiles.readKept(t);
    for (std::size_t i = 0; i < points.size(); ++i) {
      if (!kept[i]) continue;
      ++histogram[shuffledId(points[i].id) >> (64 - kBits)];
      ++kept_points;
    }
  }
  if (step.count >= kept_points) return;
  std::size_t bin = 0;
  std::uint64_t below = 0;
  while (below + histogram[bin] < step.count) below += histogram[bin++];
  std::vector<std::uint64_t> in_bin;
  for (std::size_t t = 0; t < tiles.tiles(); ++t) {
    const std::vector<GridPoint> points = tiles.readPoints(t);
    const std::vector<std::uint8_t> kept = tiles.readKept(t);
    for (std::size_t i = 0; i < points.size(); ++i) {
      const std::uint64_t h = shuffledId(points[i].id);
      if (kept[i] && (h >> (64 - kBits)) == bin) in_bin.push_back(h);
    }
  }
  std::sort(in_bin.begin(), in_bin.end());
  // Kept: hashes up to the (count - below)-th of the bin; none of the bin when that is zero.
  const std::uint64_t take = step.count - below;
  const std::uint64_t bin_start = std::uint64_t(bin) << (64 - kBits);
  for (std::size_t t = 0; t < tiles.tiles(); ++t) {
    const std::vector<GridPoint> points = tiles.readPoints(t);
    std::vector<std::uint8_t> kept = tiles.readKept(t);
    for (std::size_t i = 0; i < points.size(); ++i) {
      if (!kept[i]) continue;
      const std::uint64_t h = shuffledId(points[i].id);
      const bool taken =
          h < bin_start || (take > 0 && (h >> (64 - kBits)) == bin && h <= in_bin[take - 1]);
      kept[i] = taken;
    }
    tiles.writeRecords<std::uint8_t>(t, "kept", kept);
  }
}

}  // namespace

void runSubsampleStep(const SubsampleStep& step, const StepContext& context) {
  switch (step.method) {
    case SubsampleStep::Method::kVoxel:
      voxelSubsample(step, context);
      return;
    case SubsampleStep::Method::kRandom:
      randomSubsample(step, context);
      return;
    case SubsampleStep::Method::kSpacing:
      throw std::logic_error("runSubsampleStep: spacing is rejected by the runner");
  }
}

}  // namespace parallax
