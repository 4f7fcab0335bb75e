// --outliers statistical:K,S and radius:R,N: the tiles' "kept" flags lowered for outliers, or
// their "mark" raised (--mark-outliers: class 7, low noise).
#include <cmath>

#include "process/process_steps.h"
#include "process/tile_queries.h"

namespace parallax {

namespace {

// Sums of the mean distances in fixed point (2^-32 units): integer sums do not depend on the
// order they are added in, so the cloud's mean and deviation, and so which points are outliers,
// do not depend on how the cloud was tiled.
__extension__ typedef __int128 Fixed;
constexpr double kFixedScale = 4294967296.0;

// Lowers `kept` or raises `mark` of the points `outlier` says, in every tile.
template <class IsOutlier>
void applyOutliers(const StepContext& context, bool mark, IsOutlier&& outlier) {
  const TileSet& tiles = context.tiles;
  for (std::size_t t = 0; t < tiles.tiles(); ++t) {
    std::vector<std::uint8_t> kept = tiles.readKept(t);
    std::vector<std::uint8_t> marks = tiles.has(t, "mark")
                                          ? tiles.readRecords<std::uint8_t>(t, "mark")
                                          : std::vector<std::uint8_t>(kept.size(), 0);
    for (std::size_t i = 0; i < kept.size(); ++i) {
      if (!kept[i] || !outlier(t, i)) continue;
      if (mark) {
        marks[i] = 1;
      } else {
        kept[i] = 0;
      }
    }
    if (mark) {
      tiles.writeRecords<std::uint8_t>(t, "mark", marks);
    } else {
      tiles.writeRecords<std::uint8_t>(t, "kept", kept);
    }
  }
}

// Each kept point's mean distance to its k nearest others (PCL's StatisticalOutlierRemoval:
// k + 1 nearest, the first, the point itself, skipped), as a float as PCL keeps it; the tiles'
// "meandist" records (NaN for removed points).
void meanDistances(const OutliersStep& step, const StepContext& context, Fixed& sum,
                   Fixed& sum_squares, std::uint64_t& valid) {
  const TileSet& tiles = context.tiles;
  auto bar = context.progress ? context.progress(context.label, tiles.points()) : nullptr;
  sum = sum_squares = 0;
  valid = 0;
  for (std::size_t t = 0; t < tiles.tiles(); ++t) {
    // The slab's records (32 bytes a point) are read by the first round only: freed once it has
    // loaded, before its index is built (the step's peak), not held through the later rounds.
    std::vector<GridPoint> points = tiles.readPoints(t);
    const std::vector<std::uint8_t> kept = tiles.readKept(t);
    const std::size_t count = points.size();
    std::vector<float> mean(count, std::nanf(""));
    TileNeighbourhood first = loadNeighbourhood(tiles, t, 0.0, points, kept);
    // With no halo the neighbourhood is the tile's kept points alone: they are the queries.
    const std::vector<GridPoint> queries = std::move(first.points);
    const std::vector<std::uint32_t> slot = std::move(first.slot);
    first = {};
    const std::size_t k = std::size_t(step.k) + 1;
    answerTileQueries(
        queries, 1.5 * NeighbourIndex::radiusForCount(queries, double(k)),
        [&](double h) {
          TileNeighbourhood hood = loadNeighbourhood(tiles, t, h, points, kept);
          points = std::vector<GridPoint>();  // not `= {}`: that keeps the capacity
          return hood;
        },
        tiles,
        [&](const TileNeighbourhood& hood, const NeighbourIndex& grid, std::uint32_t i,
            const GridPoint& q, std::vector<Neighbour>& neighbours, double& needed) -> bool {
          grid.nearest(q.x, q.y, q.z, k, neighbours);
          const double reach =
              neighbours.size() < k ? TileSet::kInfinity : std::sqrt(neighbours.back().d2);
          if (!hood.covers(q, reach)) {
            needed = reach;
            return false;
          }
          double total = 0.0;
          for (std::size_t n = 1; n < neighbours.size(); ++n) total += std::sqrt(neighbours[n].d2);
          mean[slot[i]] = float(total / double(step.k));
          return true;
        });
    for (std::size_t i = 0; i < count; ++i) {
      if (!kept[i]) continue;
      const double d = mean[i];
      sum += Fixed(d * kFixedScale);
      sum_squares += Fixed(d * d * kFixedScale);
      ++valid;
    }
    tiles.writeRecords<float>(t, "meandist", mean);
    traceMemory("mean distances slab " + std::to_string(t) + " written", count);
    if (bar) bar->advance(count);
  }
}

}  // namespace

void runOutliersStep(const OutliersStep& step, const StepContext& context) {
  const TileSet& tiles = context.tiles;
  if (step.method == OutliersStep::Method::kStatistical) {
    Fixed sum_fixed = 0, squares_fixed = 0;
    std::uint64_t valid = 0;
    meanDistances(step, context, sum_fixed, squares_fixed, valid);
    if (valid < 2) return;
    // PCL's threshold: mean + S * standard deviation (n - 1 in the variance).
    const double sum = double(sum_fixed) / kFixedScale;
    const double squares = double(squares_fixed) / kFixedScale;
    const double n = double(valid);
    const double variance = std::max(0.0, (squares - sum * sum / n) / (n - 1.0));
    const double threshold = sum / n + step.std_ratio * std::sqrt(variance);
    std::vector<float> mean;
    std::size_t mean_tile = SIZE_MAX;
    applyOutliers(context, step.mark, [&](std::size_t t, std::size_t i) {
      if (t != mean_tile) {
        mean = tiles.readRecords<float>(t, "meandist");
        mean_tile = t;
      }
      return double(mean[i]) > threshold;
    });
    for (std::size_t t = 0; t < tiles.tiles(); ++t)
      std::filesystem::remove(tiles.file(t, "meandist"));
    return;
  }
  // radius:R,N: fewer than N other points within R (distance <= R).
  auto bar = context.progress ? context.progress(context.label, tiles.points()) : nullptr;
  for (std::size_t t = 0; t < tiles.tiles(); ++t) {
    const std::vector<GridPoint> points = tiles.readPoints(t);
    const std::vector<std::uint8_t> kept = tiles.readKept(t);
    std::vector<std::uint8_t> isolated(points.size(), 0);
    const TileNeighbourhood hood =
        loadNeighbourhood(tiles, t, step.radius * (1.0 + 1e-9), points, kept);
    const NeighbourIndex grid(hood.points);
    tbb::enumerable_thread_specific<std::vector<Neighbour>> scratch;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, hood.core, 1024),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                        std::vector<Neighbour>& neighbours = scratch.local();
                        for (std::size_t i = range.begin(); i != range.end(); ++i) {
                          const GridPoint& q = hood.points[i];
                          grid.withinRadius(q.x, q.y, q.z, step.radius, neighbours);
                          isolated[hood.slot[i]] =
                              neighbours.size() < std::size_t(step.min_neighbours) + 1;
                        }
                      });
    tiles.writeRecords<std::uint8_t>(t, "isolated", isolated);
    if (bar) bar->advance(points.size());
  }
  std::vector<std::uint8_t> isolated;
  std::size_t isolated_tile = SIZE_MAX;
  applyOutliers(context, step.mark, [&](std::size_t t, std::size_t i) {
    if (t != isolated_tile) {
      isolated = tiles.readRecords<std::uint8_t>(t, "isolated");
      isolated_tile = t;
    }
    return isolated[i] != 0;
  });
  for (std::size_t t = 0; t < tiles.tiles(); ++t)
    std::filesystem::remove(tiles.file(t, "isolated"));
}

}  // namespace parallax
