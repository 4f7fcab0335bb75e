// What every neighbourhood step does on a tile: load it with a halo, build a grid, answer each
// kept point's query, and load again, around each query whose answer reached past what was
// loaded, the points within its own larger halo, until none is left. Internal to the process
// module.
#pragma once

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "core/progress.h"
#include "core/scalar_type.h"
#include "lod/convert_stages.h"
#include "process/neighbour_index.h"
#include "process/tile_set.h"

namespace parallax {

// What a step needs of the run: the tiles of the cloud and where to report progress.
struct StepContext {
  const TileSet& tiles;
  std::filesystem::path work_dir;
  std::uint64_t max_tile_points = 0;
  ProgressFactory progress;
  std::string label;            // the step as given ("--normals 16"), for progress and messages
  std::uint64_t memory_mb = 0;  // what a whole-cloud grid may take
  const std::vector<ConvertInput>* inputs = nullptr;  // the run's inputs, read again by steps
                                                      // that need their other columns
};

// For each of `queries` (the tile's kept points), calls `answer(hood, grid, i, query, scratch,
// needed)` (`hood`'s points moved into `grid`: grid.points()), which returns whether its answer
// is exact (TileNeighbourhood::covers) and, when it is not, sets `needed` to the radius its
// answer over the points loaded reached (infinite: too few points); those that are not are asked
// again with a larger halo. `load(halo)` loads the points searched for the first round. In each
// later round every pending query has a halo of its own: the radius its answer needed, or, where
// it found too few points, its last halo doubled. That radius bounds what it needs over the whole
// cloud (its K-th distance over a subset of it is at least its K-th distance over all of it), so
// one more round answers it however far it is from the rest; its last halo doubled as well (the
// rule before) only made its ball larger (4 times the points on a surface) for nothing. The
// round loads every point within some pending query's halo (groupQueryBalls, a point once
// however many balls hold it), in batches of at most TileSet::roundPoints() points, a slab's
// worth (BallBatches: one pass over the slab files of `searched` a batch, one batch unless the
// round's balls hold more), and a query's answer is exact when its reach is within its own halo.
// One box around all pending queries, as before, spanned the slab and its neighbours from the
// ground up as soon as one of them was a bogus return hundreds of metres up, and each later
// round reloaded all of that (the 100 M-point run's peak, NOTES.md). A query with too few points
// doubles its halo, so it reaches the whole cloud (everything loaded) before it could fail again.
//
// Queries are asked in Morton order, so that consecutive ones walk the same nodes and leaves:
// when the first load holds the queries themselves first (`hood.core == queries.size()`, as
// loadNeighbourhood does), in the tree's own order, read from the tree's copy of the points (one
// sort, and the positions read in order instead of gathered); otherwise in spatialOrder.
template <class Load, class Answer>
void answerTileQueries(std::span<const GridPoint> queries, double halo, Load&& load,
                       const TileSet& searched, Answer&& answer) {
  if (queries.empty()) return;
  std::vector<std::uint32_t> pending;
  std::vector<double> halos;  // each pending query's halo for its next round (later rounds)
  tbb::enumerable_thread_specific<std::vector<Neighbour>> scratch;
  // What a later round's query checks its answer against: its own halo (the points loaded for
  // the other queries are real points of the cloud too, so they never make an answer wrong;
  // only its own ball says what is complete).
  tbb::enumerable_thread_specific<TileNeighbourhood> views;
  // Per pending query: whether its answer was exact, and the radius it needed when not.
  std::vector<std::uint8_t> exact;
  std::vector<double> needed;
  bool first = true;
  int round = 0;
  while (first || !pending.empty()) {
    ++round;
    const std::string round_name = "round " + std::to_string(round);
    TileNeighbourhood hood;
    if (first) {
      hood = load(halo);
      traceMemory(round_name + " load (0 groups)", hood.points.size());
      // The loaded points move into the index (the answers read them as grid.points()).
      const NeighbourIndex grid(std::move(hood.points));
      traceMemory(round_name + " index", 0);
      hood.points = {};
      const std::span<const GridPoint> tree = grid.treePoints();
      // Where each query's position is read: its place in the tree (the queries are the first
      // load's core), or a copy gathered in the order they are asked, so that reading them does
      // not wait on memory in the middle of each search.
      std::vector<std::uint32_t> in_tree;
      std::vector<GridPoint> asked;
      const bool from_tree = hood.core == queries.size();
      if (from_tree) {
        const std::span<const std::uint32_t> order = grid.treeOrder();
        pending.reserve(queries.size());
        in_tree.reserve(queries.size());
        for (std::uint32_t j = 0; j < order.size(); ++j) {
          if (order[j] >= hood.core) continue;
          pending.push_back(order[j]);
          in_tree.push_back(j);
        }
      } else {
        pending = spatialOrder(queries);
        asked.resize(pending.size());
        for (std::size_t j = 0; j < pending.size(); ++j) asked[j] = queries[pending[j]];
      }
      exact.assign(pending.size(), 0);
      needed.assign(pending.size(), 0.0);
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, pending.size(), 1024),
                        [&](const tbb::blocked_range<std::size_t>& range) {
                          std::vector<Neighbour>& local = scratch.local();
                          for (std::size_t j = range.begin(); j != range.end(); ++j) {
                            const GridPoint& q = from_tree ? tree[in_tree[j]] : asked[j];
                            exact[j] = answer(hood, grid, pending[j], q, local, needed[j]);
                          }
                        });
      traceMemory(round_name + " answers", pending.size());
    } else {
      // Each pending query's ball, loaded in batches of at most a slab's points (BallBatches):
      // one batch, one pass over the slab files, unless the round's balls hold more.
      std::vector<BallGroup> groups;
      std::vector<QueryBall> balls;
      std::vector<std::uint32_t> ball_of;
      groupQueryBalls(queries, pending, halos, groups, balls, ball_of);
      std::vector<std::uint32_t> of_ball(balls.size());
      for (std::uint32_t j = 0; j < ball_of.size(); ++j) of_ball[ball_of[j]] = j;
      exact.assign(pending.size(), 0);
      needed.assign(pending.size(), 0.0);
      BallBatches batches(searched, groups, balls, searched.roundPoints());
      std::vector<GridPoint> loaded;
      std::vector<std::uint32_t> batch;  // into pending: the queries of the batch's balls
      std::vector<GridPoint> asked;
      while (batches.next(loaded)) {
        traceMemory(round_name + " load (" + std::to_string(groups.size()) + " groups, balls " +
                        std::to_string(batches.from()) + "-" + std::to_string(batches.to()) + ")",
                    loaded.size());
        const NeighbourIndex grid(std::move(loaded));
        loaded = {};
        // Asked in the order they were pending (spatial, from the first round).
        batch.assign(of_ball.begin() + batches.from(), of_ball.begin() + batches.to());
        std::sort(batch.begin(), batch.end());
        traceMemory(round_name + " index", batch.size());
        asked.resize(batch.size());
        for (std::size_t b = 0; b < batch.size(); ++b) asked[b] = queries[pending[batch[b]]];
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, batch.size(), 1024),
                          [&](const tbb::blocked_range<std::size_t>& range) {
                            std::vector<Neighbour>& local = scratch.local();
                            TileNeighbourhood& view = views.local();
                            for (std::size_t b = range.begin(); b != range.end(); ++b) {
                              const std::uint32_t j = batch[b];
                              view.within = halos[j];
                              exact[j] = answer(view, grid, pending[j], asked[b], local, needed[j]);
                            }
                          });
        traceMemory(round_name + " answers", batch.size());
      }
      searched.noteLaterRound(batches.points(), batches.largest(), groups.size(), batches.batches(),
                              batches.passes());
    }
    // The next halo of a query still pending: the radius its answer over the points loaded
    // reached (a hair over it: covers() wants the ball strictly inside the box's upper side),
    // or doubled where it found too few points.
    std::vector<std::uint32_t> again;
    std::vector<double> again_halos;
    for (std::size_t j = 0; j < pending.size(); ++j) {
      if (exact[j]) continue;
      // A ball holds every point when it reaches the cloud's farthest corner.
      const bool everything = first ? hood.everything() : [&] {
        const GridPoint& q = queries[pending[j]];
        const double* lo = searched.min();
        const double* hi = searched.max();
        const double far =
            squaredDistance(std::max(q.x - lo[0], hi[0] - q.x), std::max(q.y - lo[1], hi[1] - q.y),
                            std::max(q.z - lo[2], hi[2] - q.z), 0, 0, 0);
        return far * (1.0 + 1e-6) < halos[j] * halos[j];
      }();
      if (everything) {
        // With every point loaded each answer is exact: a query that says otherwise is a bug.
        throw std::logic_error(
            "process: a query over the whole cloud reported an incomplete answer");
      }
      again.push_back(pending[j]);
      const double was = first ? halo : halos[j];
      const double reach = std::isfinite(needed[j]) ? needed[j] * (1.0 + 1e-9) : 0.0;
      again_halos.push_back(reach > 0.0 ? reach : was > 0.0 ? 2.0 * was : 1.0);
    }
    first = false;
    pending = std::move(again);
    halos = std::move(again_halos);
  }
}

// The steps (step_*.cpp). Each reads and writes the tiles' records (tile_set.h): "kept",
// "normals" (3 floats), "curvature" (float), "distance" (float), "mark" (1: class 7), "class"
// (the class to write, 0: the input's), and those of the columns below (StepScalar).
struct NormalsStep;
struct OutliersStep;
struct SubsampleStep;
struct DistanceStep;
struct GroundStep;
struct HeightAboveGroundStep;
struct M3c2Step;
void runNormalsStep(const NormalsStep& step, const StepContext& context);
void runOutliersStep(const OutliersStep& step, const StepContext& context);
void runSubsampleStep(const SubsampleStep& step, const StepContext& context);
void runDistanceStep(const DistanceStep& step, const StepContext& context);
void runGroundStep(const GroundStep& step, const StepContext& context);
void runHeightAboveGroundStep(const HeightAboveGroundStep& step, const StepContext& context);
void runM3c2Step(const M3c2Step& step, const StepContext& context);

// Classes, for the steps that read them (step_ground.cpp): the inputs read once more, each point
// routed to its tile by its x as the spill did, into "class_in" records (0 where an input has no
// classification); and a tile's classes as the run has them so far (a ground step's "class"
// record where nonzero, else the input's).
void writeInputClasses(const StepContext& context);
std::vector<std::uint8_t> currentClasses(const TileSet& tiles, std::size_t tile);

// A column a step adds to the output: its records are the tiles' "<name>" files, one value of
// `type` a point (every tile written, in the tile's order), copied into a scalar column of that
// name and type.
struct StepScalar {
  std::string name;
  ScalarType type;
};
// The columns of --m3c2 (step_m3c2.cpp) and of --height-above-ground (step_height.cpp).
std::vector<StepScalar> m3c2Scalars();
StepScalar heightAboveGroundScalar();

}  // namespace parallax
