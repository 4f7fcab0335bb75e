// The tiles a processing run works on: the cloud cut into slabs along x, each small enough for
// memory, spilled to files in a work folder, and read back with a halo of any width.
//
// Why slabs of x and not the octree builder's chunks: a neighbourhood query needs "every point
// within r of this one", and for a slab that is one interval of x, whatever r turns out to be
// (a K-nearest query learns its radius only when it is answered, and grows its halo then:
// NOTES.md). The slabs are cut at the edges of a 65 536-bin histogram of x so each holds at most
// the points the budget allows (a single bin more crowded than that is one slab over budget).
//
// Files, for slab i: tile_i.points (its points as GridPoint records, in input order: world
// x y z double and the point's index in the whole input), tile_i.kept (one byte a point: 1 kept,
// 0 removed by an earlier step), and what the steps write beside them (tile_i.<name>: one fixed-
// size record a point, in the same order).
#pragma once

#include <cstdint>
#include <filesystem>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "core/progress.h"
#include "lod/convert_stages.h"
#include "process/neighbour_index.h"

namespace parallax {

// PARALLAX_PROCESS_TRACE set (to anything but 0): each call prints to stderr the process's
// resident memory now (VmRSS) and its peak since the call before (VmHWM, then reset through
// /proc/self/clear_refs, so each phase's own peak is read), with `what` (a phase, a slab's round)
// and `points` (what the phase loaded). Nothing without the variable. Linux only; elsewhere the
// line says "n/a".
bool memoryTraceOn();
void traceMemory(const std::string& what, std::uint64_t points = 0);

// A box [lo, hi) on every axis (an infinite bound: nothing beyond on that side).
struct PointBox {
  double lo[3], hi[3];
};

// A query's ball: the points p with squaredDistance(p, centre) <= r2 (neighbour_index.h's
// expression) are loaded for it.
struct QueryBall {
  double x, y, z, r2;
};
// A run of balls, balls[begin, end), and a box holding all of them.
struct BallGroup {
  PointBox box;
  std::uint32_t begin = 0, end = 0;
};

// What the rounds after a tile's first loaded (answerTileQueries, tile_queries.h), over a run:
// the points a round holds beyond the first load's are what pushes the peak past --memory. A
// round is loaded in batches of at most TileSet::roundPoints() points (BallBatches).
struct TileStatistics {
  std::uint64_t later_rounds = 0;         // rounds after a tile's first, all steps
  std::uint64_t later_round_points = 0;   // the points their batches loaded, summed
  std::uint64_t largest_later_round = 0;  // the most points one batch of them held at once
  std::uint64_t later_round_boxes = 0;    // the boxes they loaded (a box per cluster of queries)
  std::uint64_t later_round_batches = 0;  // their batches (one per round when it fits)
  std::uint64_t later_round_passes = 0;   // their passes over the slab files: a pass a batch,
                                          // and one more where a round was counted first
};

class TileSet {
 public:
  static constexpr double kInfinity = std::numeric_limits<double>::infinity();

  // Reads `inputs` (in order; ids count on across them), spills their points into slabs of at
  // most `max_tile_points` (at most kMaxTiles slabs: larger slabs when more would be needed).
  // `edges`: cut at these x values instead (the reference cloud of --distance-to, cut as the
  // processed cloud is). Throws InputError from the readers.
  static constexpr std::size_t kMaxTiles = 512;
  static TileSet spill(const std::vector<ConvertInput>& inputs, const std::filesystem::path& dir,
                       const std::string& name, std::uint64_t max_tile_points,
                       const std::vector<double>* edges, const ProgressFactory& progress);

  // Points a pass reads, spills or copies at once: a quarter of a slab, between 4 096 and 1 M,
  // so that a small --memory reads in small batches too (the default's batches are 1 M points).
  static std::size_t batchPointsFor(std::uint64_t max_tile_points);
  std::size_t batchPoints() const { return batch_points_; }
  // The most points a later round of a tile's queries loads at once (BallBatches): what a slab
  // may hold (`max_tile_points` as spill used it), the share of --memory a step's load has.
  std::uint64_t roundPoints() const { return round_points_; }

  std::size_t tiles() const { return counts_.size(); }
  std::uint64_t points() const { return points_; }
  std::uint64_t count(std::size_t tile) const { return counts_[tile]; }
  // The tile's x interval [lo, hi): -inf and +inf at the ends.
  double lo(std::size_t tile) const { return tile == 0 ? -kInfinity : edges_[tile - 1]; }
  double hi(std::size_t tile) const { return tile + 1 == tiles() ? kInfinity : edges_[tile]; }
  const std::vector<double>& edges() const { return edges_; }
  std::size_t tileOf(double x) const;
  // The points' bounds (world units).
  const double* min() const { return min_; }
  const double* max() const { return max_; }

  std::filesystem::path file(std::size_t tile, const std::string& what) const;
  std::vector<GridPoint> readPoints(std::size_t tile) const;
  std::vector<std::uint8_t> readKept(std::size_t tile) const;
  // Appends the kept points of every tile but `except` whose x is in [lo, hi).
  void appendKeptInRange(double lo, double hi, std::size_t except,
                         std::vector<GridPoint>& out) const;
  // The same within the box [lo, hi) on every axis (`except` SIZE_MAX: every tile).
  void appendKeptInBox(const double lo[3], const double hi[3], std::size_t except,
                       std::vector<GridPoint>& out) const;

  // One pass over the files of the tiles that the boxes of the groups holding balls[from, end)
  // overlap in x (BallBatches). Appends to `out` every kept point within a ball of
  // balls[from, to), once however many hold it, unless that would make more than `limit`: then
  // `out` is emptied and the pass goes on counting only, and it returns false. For each kept
  // point within a ball of balls[from, end), adds one to `from_counts` at the first such ball,
  // and, for a point within a ball of balls[to, end), to `to_counts` at the first of those
  // (both balls.size() long): how many points balls[from, b) or balls[to, b) hold in all,
  // summed, for any b.
  bool appendKeptInBalls(std::span<const BallGroup> groups, std::span<const QueryBall> balls,
                         std::uint32_t from, std::uint32_t to, std::uint64_t limit,
                         std::vector<GridPoint>& out, std::vector<std::uint64_t>& from_counts,
                         std::vector<std::uint64_t>& to_counts) const;

  // A round after a tile's first: `batches` batches (`passes` passes over the files, `boxes`
  // boxes) that loaded `points` in all, `largest` at once (TileStatistics).
  void noteLaterRound(std::uint64_t points, std::uint64_t largest, std::size_t boxes,
                      std::size_t batches, std::size_t passes) const;
  const TileStatistics& statistics() const { return statistics_; }

  // Per-point records of `what` ("kept", "normals", ...), `record_size` bytes each.
  template <class T>
  void writeRecords(std::size_t tile, const std::string& what, std::span<const T> records) const {
    writeBytes(tile, what, records.data(), records.size_bytes());
  }
  template <class T>
  std::vector<T> readRecords(std::size_t tile, const std::string& what) const {
    std::vector<T> out(count(tile));
    readBytes(tile, what, out.data(), out.size() * sizeof(T));
    return out;
  }
  bool has(std::size_t tile, const std::string& what) const;
  // Renames tile_i.<from> to tile_i.<to> for every tile (a step's kept flags become current).
  void renameAll(const std::string& from, const std::string& to) const;
  // Points kept, over all tiles.
  std::uint64_t keptPoints() const;

 private:
  void writeBytes(std::size_t tile, const std::string& what, const void* data,
                  std::size_t size) const;
  void readBytes(std::size_t tile, const std::string& what, void* data, std::size_t size) const;

  std::filesystem::path dir_;
  std::string name_;
  std::vector<double> edges_;  // tiles() - 1 inner edges, ascending
  std::vector<std::uint64_t> counts_;
  std::uint64_t points_ = 0;
  std::size_t batch_points_ = 1;
  std::uint64_t round_points_ = 1;
  double min_[3] = {0, 0, 0}, max_[3] = {0, 0, 0};
  mutable TileStatistics statistics_;  // counted by the steps, which see the tiles as const
};

// A tile's kept points and the kept points within a halo around it: the input of a step's
// queries on that tile.
struct TileNeighbourhood {
  std::vector<GridPoint> points;    // the tile's kept points first, then the halo's
  std::size_t core = 0;             // how many of `points` are the tile's
  std::vector<std::uint32_t> slot;  // for each of the tile's kept points, its record in the tile
  // Every kept point in the box [lo, hi) is in `points` (infinite bounds: nothing beyond).
  double lo[3] = {-TileSet::kInfinity, -TileSet::kInfinity, -TileSet::kInfinity};
  double hi[3] = {TileSet::kInfinity, TileSet::kInfinity, TileSet::kInfinity};

  // For a later round's query (answerTileQueries): every kept point within this distance of it
  // is loaded, and the box is not what says so (the box is then infinite).
  double within = TileSet::kInfinity;

  // Whether a ball of radius `r` around `q` lies within what was loaded, so that a query
  // answered with that radius is exact.
  bool covers(const GridPoint& q, double r) const {
    if (!(r <= within)) return false;
    const double v[3] = {q.x, q.y, q.z};
    for (int a = 0; a < 3; ++a) {
      if (lo[a] != -TileSet::kInfinity && !(v[a] - r >= lo[a])) return false;
      if (hi[a] != TileSet::kInfinity && !(v[a] + r < hi[a])) return false;
    }
    return true;
  }
  bool everything() const {
    if (within != TileSet::kInfinity) return false;
    for (int a = 0; a < 3; ++a) {
      if (lo[a] != -TileSet::kInfinity || hi[a] != TileSet::kInfinity) return false;
    }
    return true;
  }
};

// Loads tile `tile` of `tiles` with a halo of `halo` either side (an infinite halo past the
// cloud's ends). `core` and `slot` from readPoints/readKept (read once, reused as halos grow).
TileNeighbourhood loadNeighbourhood(const TileSet& tiles, std::size_t tile, double halo,
                                    const std::vector<GridPoint>& core_points,
                                    const std::vector<std::uint8_t>& core_kept);

// The balls of a later round: each pending query (`pending` indexes `queries`, `halos` their
// halos, in the same order) with a ball of its halo (a hair over it: the answer checks its reach
// against the halo itself, so rounding never makes a loaded point look missing), the balls
// grouped by a grid whose cells are as wide as their halo rounded up to a power of two, each
// group with the bounding box of its balls. `balls[j]` is pending[j]'s, in group order through
// `ball_of[j]`. A query far from the rest (a bogus return high above the ground) loads the
// points within its own reach, not a box around all pending queries that spans the slab, and
// not even its own box (whose corners would reach the ground below it).
void groupQueryBalls(std::span<const GridPoint> queries, std::span<const std::uint32_t> pending,
                     std::span<const double> halos, std::vector<BallGroup>& groups,
                     std::vector<QueryBall>& balls, std::vector<std::uint32_t>& ball_of);

// The batches a later round's balls are loaded in (answerTileQueries): runs balls[from, to) of
// the balls in group order, each holding at most TileSet::roundPoints() points (a point once
// however many of its balls hold it), each loaded in one pass over the slab files. A sparse
// region as wide as a slab, or a K larger than most neighbourhoods, can leave pending queries
// whose balls together hold more than a slab: loaded at once they would take more than --memory.
// How the points of a run are known before it is loaded: a pass counts, for each point, the
// first ball at or after `from` that holds it, so that balls[from, to) hold exactly the sum of
// the counts over [from, to) (a point in any of them has its first one there); the pass that
// loads a batch counts from its end for the next. The first pass tries the whole round at once
// (nothing known yet) and counts too; only when that would go over does it load nothing and
// the batches follow. A single ball holding more than the limit is a batch of its own: its query
// needs every one of them.
class BallBatches {
 public:
  BallBatches(const TileSet& tiles, std::span<const BallGroup> groups,
              std::span<const QueryBall> balls, std::uint64_t limit);
  // The next batch's points into `points` (emptied first): false when every ball was loaded.
  bool next(std::vector<GridPoint>& points);
  // The balls of the batch `next` loaded last.
  std::uint32_t from() const { return from_; }
  std::uint32_t to() const { return to_; }
  std::size_t batches() const { return batches_; }
  std::size_t passes() const { return passes_; }
  std::uint64_t points() const { return points_; }
  std::uint64_t largest() const { return largest_; }

 private:
  const TileSet& tiles_;
  std::span<const BallGroup> groups_;
  std::span<const QueryBall> balls_;
  std::uint64_t limit_;
  std::uint32_t from_ = 0, to_ = 0;
  bool counted_ = false;  // counts_ holds the first-ball counts from to_ on
  std::vector<std::uint64_t> counts_, spare_;
  std::size_t batches_ = 0, passes_ = 0;
  std::uint64_t points_ = 0, largest_ = 0;
};

// Every kept point of `set` within `halo` of tile t's x interval (an infinite halo past the
// cloud's ends), none of them "core": another cloud's points around a tile of the processed one
// (`set` tiled with its edges: the reference of --distance-to, an epoch of --m3c2).
TileNeighbourhood loadAround(const TileSet& set, std::size_t t, double halo);

}  // namespace parallax
