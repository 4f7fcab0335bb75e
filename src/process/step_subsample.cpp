// --subsample voxel:SIZE | spacing:D | random:N: the tiles' "kept" flags lowered for the points
// not taken.
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <unordered_map>

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
    // The voxel's integer coordinates held as doubles: floor() is exact, and a quotient past
    // 2^63 (a tiny SIZE) stays a distinct, ordered key instead of an out-of-range integer
    // conversion (undefined; on x86 every such point fell in one voxel).
    struct Keyed {
      std::array<double, 3> voxel;
      std::uint64_t id;
      std::uint32_t at;
      bool operator<(const Keyed& o) const {
        return voxel < o.voxel || (voxel == o.voxel && id < o.id);
      }
    };
    std::vector<Keyed> keyed(hood.points.size());
    for (std::size_t i = 0; i < hood.points.size(); ++i) {
      const GridPoint& p = hood.points[i];
      keyed[i] = {
          {std::floor((p.x - corner[0]) / step.size), std::floor((p.y - corner[1]) / step.size),
           std::floor((p.z - corner[2]) / step.size)},
          p.id,
          std::uint32_t(i)};
    }
    tbb::parallel_sort(keyed.begin(), keyed.end());
    traceMemory("voxel slab " + std::to_string(t) + " sorted", hood.points.size());
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

// No two kept points closer than D, greedily (CloudCompare's "space" subsampling): the points are
// visited in one order, and each is kept when no point kept before it lies closer than D. The
// order is columns of width D in x (from the kept points' minimum), and the input order (id)
// within a column: a point's earlier neighbours within D are then in its own column or the one
// before, so the columns can be decided left to right, slab after slab, and the answer does not
// depend on where the slabs are cut. A column belongs to the slab holding its left edge; a halo
// of D around the slab holds the whole of its columns and the column before them, decided by
// this slab or an earlier one. Decisions are one bit a point (the input's index), so that the
// column before may be decided in an earlier slab: N / 8 bytes beside the slab's own memory.
void spacingSubsample(const SubsampleStep& step, const StepContext& context) {
  const TileSet& tiles = context.tiles;
  const double d = step.size;
  const double x0 = keptMinimum(tiles)[0];
  const auto columnOf = [&](double x) { return std::int64_t(std::floor((x - x0) / d)); };
  const auto ownerOf = [&](std::int64_t column) { return tiles.tileOf(x0 + double(column) * d); };
  std::vector<std::uint64_t> taken((tiles.points() + 63) / 64, 0);
  const auto isTaken = [&](std::uint64_t id) { return (taken[id >> 6] >> (id & 63)) & 1u; };
  auto bar = context.progress ? context.progress(context.label, tiles.points()) : nullptr;
  for (std::size_t t = 0; t < tiles.tiles(); ++t) {
    const std::vector<GridPoint> points = tiles.readPoints(t);
    const std::vector<std::uint8_t> kept = tiles.readKept(t);
    const TileNeighbourhood hood = loadNeighbourhood(tiles, t, d * 1.001, points, kept);
    // Kept points in cells of D (column, y, z), for the "any kept point closer than D" test;
    // a hash collision only adds points to compare.
    const auto cellCoords = [&](std::int64_t c, const GridPoint& p) {
      return std::array<std::int64_t, 3>{c, std::int64_t(std::floor(p.y / d)),
                                         std::int64_t(std::floor(p.z / d))};
    };
    std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> grid;
    const auto keyOf = [](const std::array<std::int64_t, 3>& c) {
      return (std::uint64_t(c[0]) * 0x9E3779B97F4A7C15ull) ^
             (std::uint64_t(c[1]) * 0xC2B2AE3D27D4EB4Full) ^
             (std::uint64_t(c[2]) * 0x165667B19E3779F9ull);
    };
    struct Candidate {
      std::int64_t column;
      std::uint64_t id;
      std::uint32_t at;
      bool operator<(const Candidate& o) const {
        return column < o.column || (column == o.column && id < o.id);
      }
    };
    std::vector<Candidate> candidates;
    for (std::size_t i = 0; i < hood.points.size(); ++i) {
      const GridPoint& p = hood.points[i];
      const std::int64_t column = columnOf(p.x);
      const std::size_t owner = ownerOf(column);
      if (owner == t) {
        candidates.push_back({column, p.id, std::uint32_t(i)});
      } else if (owner < t && isTaken(p.id)) {
        grid[keyOf(cellCoords(column, p))].push_back(std::uint32_t(i));
      }
    }
    std::sort(candidates.begin(), candidates.end());
    const double d2_min = d * d;
    for (const Candidate& c : candidates) {
      const GridPoint& p = hood.points[c.at];
      const std::array<std::int64_t, 3> cell = cellCoords(c.column, p);
      bool near = false;
      for (std::int64_t a = -1; a <= 0 && !near; ++a) {  // later columns hold nothing kept yet
        for (std::int64_t b = -1; b <= 1 && !near; ++b) {
          for (std::int64_t e = -1; e <= 1 && !near; ++e) {
            const auto found = grid.find(keyOf({cell[0] + a, cell[1] + b, cell[2] + e}));
            if (found == grid.end()) continue;
            for (std::uint32_t j : found->second) {
              const GridPoint& q = hood.points[j];
              if (squaredDistance(p.x, p.y, p.z, q.x, q.y, q.z) < d2_min) {
                near = true;
                break;
              }
            }
          }
        }
      }
      if (near) continue;
      taken[p.id >> 6] |= std::uint64_t(1) << (p.id & 63);
      grid[keyOf(cell)].push_back(c.at);
    }
    if (bar) bar->advance(points.size());
  }
  for (std::size_t t = 0; t < tiles.tiles(); ++t) {
    const std::vector<GridPoint> points = tiles.readPoints(t);
    std::vector<std::uint8_t> kept = tiles.readKept(t);
    for (std::size_t i = 0; i < points.size(); ++i) kept[i] = kept[i] && isTaken(points[i].id);
    tiles.writeRecords<std::uint8_t>(t, "kept", kept);
  }
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
      spacingSubsample(step, context);
      return;
  }
}

}  // namespace parallax
