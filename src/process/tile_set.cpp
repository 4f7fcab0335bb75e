// TileSet and loadNeighbourhood (tile_set.h).
#include "process/tile_set.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <memory>
#include <stdexcept>
#include <system_error>

#include "core/error.h"

namespace parallax {

namespace {

constexpr std::size_t kLeastBatchPoints = 4096;
constexpr std::size_t kMostBatchPoints = std::size_t(1) << 20;
// Records of a work file read at once (no more than a batch).
constexpr std::size_t kMostBlockRecords = std::size_t(1) << 16;
constexpr std::size_t kHistogramBins = std::size_t(1) << 16;

struct FileCloser {
  void operator()(std::FILE* f) const {
    if (f) std::fclose(f);
  }
};
using File = std::unique_ptr<std::FILE, FileCloser>;

File openFile(const std::filesystem::path& path, const char* mode) {
  File f(std::fopen(path.c_str(), mode));
  if (!f) {
    throw std::system_error(errno, std::generic_category(), "cannot open " + path.string());
  }
  return f;
}

void writeAll(std::FILE* f, const void* data, std::size_t size, const std::filesystem::path& path) {
  if (size > 0 && std::fwrite(data, 1, size, f) != size) {
    throw std::system_error(errno, std::generic_category(), "cannot write " + path.string());
  }
}

void readAll(std::FILE* f, void* data, std::size_t size, const std::filesystem::path& path) {
  if (size > 0 && std::fread(data, 1, size, f) != size) {
    throw std::runtime_error("work file " + path.string() + " is shorter than written");
  }
}

struct Xyz {
  double x, y, z;
};

// VmRSS and VmHWM of /proc/self/status in kB (0 where not read).
void readResidentKb(std::uint64_t& rss, std::uint64_t& hwm) {
  rss = hwm = 0;
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind("VmRSS:", 0) == 0) rss = std::strtoull(line.c_str() + 6, nullptr, 10);
    if (line.rfind("VmHWM:", 0) == 0) hwm = std::strtoull(line.c_str() + 6, nullptr, 10);
  }
}

}  // namespace

bool memoryTraceOn() {
  static const bool on = [] {
    const char* value = std::getenv("PARALLAX_PROCESS_TRACE");
    return value && *value && std::strcmp(value, "0") != 0;
  }();
  return on;
}

void traceMemory(const std::string& what, std::uint64_t points) {
  if (!memoryTraceOn()) return;
  std::uint64_t rss = 0, hwm = 0;
  readResidentKb(rss, hwm);
  std::fprintf(stderr, "parallax process: memory %-40s rss %7.1f MB  peak %7.1f MB  points %llu\n",
               what.c_str(), double(rss) / 1024.0, double(hwm) / 1024.0,
               static_cast<unsigned long long>(points));
  // "5" resets the peak to the current resident size (proc(5), /proc/PID/clear_refs).
  if (std::FILE* refs = std::fopen("/proc/self/clear_refs", "w")) {
    std::fputs("5", refs);
    std::fclose(refs);
  }
}

std::size_t TileSet::batchPointsFor(std::uint64_t max_tile_points) {
  return std::size_t(
      std::clamp<std::uint64_t>(max_tile_points / 4, kLeastBatchPoints, kMostBatchPoints));
}

TileSet TileSet::spill(const std::vector<ConvertInput>& inputs, const std::filesystem::path& dir,
                       const std::string& name, std::uint64_t max_tile_points,
                       const std::vector<double>* edges, const ProgressFactory& progress) {
  TileSet set;
  set.dir_ = dir;
  set.name_ = name;
  set.batch_points_ = batchPointsFor(max_tile_points);
  set.round_points_ = std::max<std::uint64_t>(max_tile_points, 1);
  std::uint64_t total = 0;
  for (const ConvertInput& input : inputs) {
    PointStream probe(input.path, input.text_columns, nullptr, &input.filter);
    total += probe.pointCount();
  }
  // Pass 1: the world positions in input order, and their bounds.
  const std::filesystem::path all_path = dir / (name + ".xyz");
  {
    File all = openFile(all_path, "wb");
    auto bar = progress ? progress("reading", total) : nullptr;
    for (int a = 0; a < 3; ++a) {
      set.min_[a] = kInfinity;
      set.max_[a] = -kInfinity;
    }
    std::vector<Xyz> block;
    for (const ConvertInput& input : inputs) {
      PointStream stream(input.path, input.text_columns, nullptr, &input.filter);
      PointCloud batch;
      while (stream.next(batch, set.batch_points_)) {
        block.resize(batch.count);
        for (std::size_t i = 0; i < batch.count; ++i) {
          block[i] = {batch.worldX(i), batch.worldY(i), batch.worldZ(i)};
          const double* v = &block[i].x;
          for (int a = 0; a < 3; ++a) {
            set.min_[a] = std::min(set.min_[a], v[a]);
            set.max_[a] = std::max(set.max_[a], v[a]);
          }
        }
        writeAll(all.get(), block.data(), block.size() * sizeof(Xyz), all_path);
        set.points_ += batch.count;
        if (bar) bar->advance(batch.count);
      }
    }
    if (std::fflush(all.get()) != 0) {
      throw std::system_error(errno, std::generic_category(), "cannot write " + all_path.string());
    }
  }
  if (set.points_ == 0) {
    for (int a = 0; a < 3; ++a) set.min_[a] = set.max_[a] = 0.0;
  }
  auto forEachBlock = [&](auto&& visit) {
    File all = openFile(all_path, "rb");
    const std::size_t records = std::min(set.batch_points_, kMostBlockRecords);
    std::vector<Xyz> block(records);
    for (std::uint64_t done = 0; done < set.points_;) {
      const std::size_t n = std::size_t(std::min<std::uint64_t>(records, set.points_ - done));
      readAll(all.get(), block.data(), n * sizeof(Xyz), all_path);
      visit(std::span<const Xyz>(block.data(), n), done);
      done += n;
    }
  };
  // The slabs' edges: bins of a histogram of x gathered until the next would overflow a slab.
  if (edges) {
    set.edges_ = *edges;
  } else if (set.points_ > 0 && set.max_[0] > set.min_[0]) {
    max_tile_points = std::max<std::uint64_t>({max_tile_points, 1, set.points_ / kMaxTiles + 1});
    set.round_points_ = max_tile_points;
    std::vector<std::uint64_t> histogram(kHistogramBins, 0);
    const double width = (set.max_[0] - set.min_[0]) / double(kHistogramBins);
    auto binOf = [&](double x) {
      return std::min<std::size_t>(kHistogramBins - 1, std::size_t((x - set.min_[0]) / width));
    };
    forEachBlock([&](std::span<const Xyz> block, std::uint64_t) {
      for (const Xyz& p : block) ++histogram[binOf(p.x)];
    });
    std::uint64_t in_tile = 0;
    for (std::size_t bin = 0; bin < kHistogramBins; ++bin) {
      if (in_tile > 0 && in_tile + histogram[bin] > max_tile_points) {
        set.edges_.push_back(set.min_[0] + double(bin) * width);
        in_tile = 0;
      }
      in_tile += histogram[bin];
    }
    // The edges are compared with x as computed, so a point lands in one slab whatever the bins.
    set.edges_.erase(std::unique(set.edges_.begin(), set.edges_.end()), set.edges_.end());
  }
  set.counts_.assign(set.edges_.size() + 1, 0);
  // Pass 2: every point appended to its slab's file.
  {
    auto bar = progress ? progress("tiling", set.points_) : nullptr;
    std::vector<File> files;
    std::vector<std::vector<GridPoint>> buffers(set.tiles());
    for (std::size_t t = 0; t < set.tiles(); ++t)
      files.push_back(openFile(set.file(t, "points"), "wb"));
    auto flush = [&](std::size_t t) {
      writeAll(files[t].get(), buffers[t].data(), buffers[t].size() * sizeof(GridPoint),
               set.file(t, "points"));
      buffers[t].clear();
    };
    forEachBlock([&](std::span<const Xyz> block, std::uint64_t first) {
      for (std::size_t i = 0; i < block.size(); ++i) {
        const std::size_t t = set.tileOf(block[i].x);
        buffers[t].push_back({block[i].x, block[i].y, block[i].z, first + i});
        ++set.counts_[t];
        if (buffers[t].size() >= 4096) flush(t);
      }
      if (bar) bar->advance(block.size());
    });
    for (std::size_t t = 0; t < set.tiles(); ++t) {
      flush(t);
      if (std::fflush(files[t].get()) != 0) {
        throw std::system_error(errno, std::generic_category(),
                                "cannot write " + set.file(t, "points").string());
      }
      const std::vector<std::uint8_t> kept(set.counts_[t], 1);
      set.writeRecords<std::uint8_t>(t, "kept", kept);
    }
  }
  std::filesystem::remove(all_path);
  return set;
}

std::size_t TileSet::tileOf(double x) const {
  return std::size_t(std::upper_bound(edges_.begin(), edges_.end(), x) - edges_.begin());
}

std::filesystem::path TileSet::file(std::size_t tile, const std::string& what) const {
  return dir_ / (name_ + "_" + std::to_string(tile) + "." + what);
}

bool TileSet::has(std::size_t tile, const std::string& what) const {
  return std::filesystem::exists(file(tile, what));
}

void TileSet::writeBytes(std::size_t tile, const std::string& what, const void* data,
                         std::size_t size) const {
  const std::filesystem::path path = file(tile, what);
  File f = openFile(path, "wb");
  writeAll(f.get(), data, size, path);
  if (std::fflush(f.get()) != 0) {
    throw std::system_error(errno, std::generic_category(), "cannot write " + path.string());
  }
}

void TileSet::readBytes(std::size_t tile, const std::string& what, void* data,
                        std::size_t size) const {
  const std::filesystem::path path = file(tile, what);
  File f = openFile(path, "rb");
  readAll(f.get(), data, size, path);
}

std::vector<GridPoint> TileSet::readPoints(std::size_t tile) const {
  return readRecords<GridPoint>(tile, "points");
}

std::vector<std::uint8_t> TileSet::readKept(std::size_t tile) const {
  return readRecords<std::uint8_t>(tile, "kept");
}

void TileSet::appendKeptInRange(double lo, double hi, std::size_t except,
                                std::vector<GridPoint>& out) const {
  const double box_lo[3] = {lo, -kInfinity, -kInfinity}, box_hi[3] = {hi, kInfinity, kInfinity};
  appendKeptInBox(box_lo, box_hi, except, out);
}

void TileSet::appendKeptInBox(const double lo[3], const double hi[3], std::size_t except,
                              std::vector<GridPoint>& out) const {
  // Reserved up front for every point of the overlapping tiles: a bound on what is appended, so
  // the vector is never grown by doubling (a copy of everything loaded so far, old and new held
  // at once). The reserved pages that are never written are never made resident.
  std::vector<std::size_t> overlapping;
  std::uint64_t bound = 0;
  for (std::size_t t = 0; t < tiles(); ++t) {
    if (t == except || this->hi(t) <= lo[0] || this->lo(t) >= hi[0] || counts_[t] == 0) continue;
    overlapping.push_back(t);
    bound += counts_[t];
  }
  out.reserve(out.size() + std::size_t(bound));
  for (const std::size_t t : overlapping) {
    File points = openFile(file(t, "points"), "rb");
    File kept = openFile(file(t, "kept"), "rb");
    const std::size_t records = std::min(batch_points_, kMostBlockRecords);
    std::vector<GridPoint> block(records);
    std::vector<std::uint8_t> flags(records);
    for (std::uint64_t done = 0; done < counts_[t];) {
      const std::size_t n = std::size_t(std::min<std::uint64_t>(records, counts_[t] - done));
      readAll(points.get(), block.data(), n * sizeof(GridPoint), file(t, "points"));
      readAll(kept.get(), flags.data(), n, file(t, "kept"));
      for (std::size_t i = 0; i < n; ++i) {
        const GridPoint& p = block[i];
        if (flags[i] && p.x >= lo[0] && p.x < hi[0] && p.y >= lo[1] && p.y < hi[1] &&
            p.z >= lo[2] && p.z < hi[2]) {
          out.push_back(p);
        }
      }
      done += n;
    }
  }
}

namespace {

// The boxes of a round bucketed by a grid over their x-y extent, so that a point is tested
// against the few boxes of its cell, not all of them.
class BoxBuckets {
 public:
  explicit BoxBuckets(std::span<const BallGroup> groups) : groups_(groups) {
    std::vector<PointBox> boxes(groups.size());
    for (std::size_t i = 0; i < groups.size(); ++i) boxes[i] = groups[i].box;
    for (int a = 0; a < 2; ++a) {
      lo_[a] = TileSet::kInfinity;
      hi_[a] = -TileSet::kInfinity;
      for (const PointBox& b : boxes) {
        lo_[a] = std::min(lo_[a], b.lo[a]);
        hi_[a] = std::max(hi_[a], b.hi[a]);
      }
      // An infinite side: the cells span the finite bounds, the end cells take the rest.
      if (!std::isfinite(lo_[a]) || !std::isfinite(hi_[a])) {
        double finite_lo = TileSet::kInfinity, finite_hi = -TileSet::kInfinity;
        for (const PointBox& b : boxes) {
          for (const double v : {b.lo[a], b.hi[a]}) {
            if (std::isfinite(v)) {
              finite_lo = std::min(finite_lo, v);
              finite_hi = std::max(finite_hi, v);
            }
          }
        }
        lo_[a] = std::isfinite(finite_lo) ? finite_lo : 0.0;
        hi_[a] = std::isfinite(finite_hi) ? finite_hi : 0.0;
      }
    }
    // About two boxes a cell across, at most 256 x 256 cells, and coarser while the boxes would
    // be listed in more than 4 M cells in all (many boxes as wide as the cloud).
    std::size_t side = std::clamp<std::size_t>(
        std::size_t(std::ceil(std::sqrt(double(boxes.size())) * 2.0)), 1, 256);
    for (;; side /= 2) {
      for (int a = 0; a < 2; ++a) {
        cells_[a] = hi_[a] > lo_[a] ? side : 1;
        scale_[a] = hi_[a] > lo_[a] ? double(cells_[a]) / (hi_[a] - lo_[a]) : 0.0;
      }
      std::uint64_t listed = 0;
      for (const PointBox& b : boxes) {
        listed += std::uint64_t(cell(0, b.hi[0]) - cell(0, b.lo[0]) + 1) *
                  std::uint64_t(cell(1, b.hi[1]) - cell(1, b.lo[1]) + 1);
      }
      if (side <= 1 || listed <= (std::uint64_t(4) << 20)) break;
    }
    start_.assign(cells_[0] * cells_[1] + 1, 0);
    auto forCells = [&](const PointBox& b, auto&& visit) {
      const std::size_t x0 = cell(0, b.lo[0]), x1 = cell(0, b.hi[0]);
      const std::size_t y0 = cell(1, b.lo[1]), y1 = cell(1, b.hi[1]);
      for (std::size_t y = y0; y <= y1; ++y) {
        for (std::size_t x = x0; x <= x1; ++x) visit(y * cells_[0] + x);
      }
    };
    for (const PointBox& b : boxes) forCells(b, [&](std::size_t c) { ++start_[c + 1]; });
    for (std::size_t c = 1; c < start_.size(); ++c) start_[c] += start_[c - 1];
    in_cell_.resize(start_.back());
    std::vector<std::size_t> next(start_.begin(), start_.end() - 1);
    for (std::uint32_t i = 0; i < boxes.size(); ++i) {
      forCells(boxes[i], [&](std::size_t c) { in_cell_[next[c]++] = i; });
    }
  }

  // The first of balls[at_least, end) that holds p (balls.size() when none): the groups of p's
  // cell are listed in ascending order, and their balls are runs in the same order, so the first
  // group that holds p has the first ball.
  std::uint32_t firstHolder(const GridPoint& p, std::span<const QueryBall> balls,
                            std::uint32_t at_least) const {
    const std::size_t c = cell(1, p.y) * cells_[0] + cell(0, p.x);
    for (std::size_t j = start_[c]; j < start_[c + 1]; ++j) {
      const BallGroup& g = groups_[in_cell_[j]];
      if (g.end <= at_least) continue;
      const PointBox& b = g.box;
      if (!(p.x >= b.lo[0] && p.x < b.hi[0] && p.y >= b.lo[1] && p.y < b.hi[1] && p.z >= b.lo[2] &&
            p.z < b.hi[2])) {
        continue;
      }
      for (std::uint32_t k = std::max(g.begin, at_least); k < g.end; ++k) {
        const QueryBall& ball = balls[k];
        if (squaredDistance(p.x, p.y, p.z, ball.x, ball.y, ball.z) <= ball.r2) return k;
      }
    }
    return std::uint32_t(balls.size());
  }

 private:
  std::size_t cell(int a, double v) const {
    const double c = (v - lo_[a]) * scale_[a];
    if (!(c > 0.0)) return 0;  // below, NaN-free: -inf and the lower bound
    return std::min(cells_[a] - 1, std::size_t(std::min(c, 1e18)));
  }

  std::span<const BallGroup> groups_;
  double lo_[2], hi_[2], scale_[2];
  std::size_t cells_[2];
  std::vector<std::size_t> start_;
  std::vector<std::uint32_t> in_cell_;
};

}  // namespace

bool TileSet::appendKeptInBalls(std::span<const BallGroup> groups, std::span<const QueryBall> balls,
                                std::uint32_t from, std::uint32_t to, std::uint64_t limit,
                                std::vector<GridPoint>& out,
                                std::vector<std::uint64_t>& from_counts,
                                std::vector<std::uint64_t>& to_counts) const {
  const std::uint32_t none = std::uint32_t(balls.size());
  from_counts.assign(balls.size(), 0);
  to_counts.assign(balls.size(), 0);
  if (groups.empty() || from >= none) return true;
  const BoxBuckets buckets(groups);
  std::vector<std::size_t> overlapping;
  std::uint64_t bound = 0;
  for (std::size_t t = 0; t < tiles(); ++t) {
    if (counts_[t] == 0) continue;
    const bool overlaps = std::any_of(groups.begin(), groups.end(), [&](const BallGroup& g) {
      return g.end > from && this->hi(t) > g.box.lo[0] && this->lo(t) < g.box.hi[0];
    });
    if (!overlaps) continue;
    overlapping.push_back(t);
    bound += counts_[t];
  }
  // As appendKeptInBox: a bound reserved once (no more than the limit), its untouched pages never
  // made resident.
  out.reserve(out.size() + std::size_t(std::min(bound, limit)));
  const std::size_t records = std::min(batch_points_, kMostBlockRecords);
  std::vector<GridPoint> block(records);
  std::vector<std::uint8_t> flags(records);
  bool complete = true;
  for (const std::size_t t : overlapping) {
    File points = openFile(file(t, "points"), "rb");
    File kept = openFile(file(t, "kept"), "rb");
    for (std::uint64_t done = 0; done < counts_[t];) {
      const std::size_t n = std::size_t(std::min<std::uint64_t>(records, counts_[t] - done));
      readAll(points.get(), block.data(), n * sizeof(GridPoint), file(t, "points"));
      readAll(kept.get(), flags.data(), n, file(t, "kept"));
      for (std::size_t i = 0; i < n; ++i) {
        if (!flags[i]) continue;
        const std::uint32_t first = buckets.firstHolder(block[i], balls, from);
        if (first == none) continue;
        ++from_counts[first];
        if (first >= to) {
          ++to_counts[first];
          continue;
        }
        if (complete && out.size() >= limit) {
          complete = false;                // over the limit: counted only, from here on
          out = std::vector<GridPoint>();  // freed (`= {}` would keep the capacity)
        }
        if (complete) out.push_back(block[i]);
        const std::uint32_t after = to < none ? buckets.firstHolder(block[i], balls, to) : none;
        if (after != none) ++to_counts[after];
      }
      done += n;
    }
  }
  return complete;
}

void TileSet::noteLaterRound(std::uint64_t points, std::uint64_t largest, std::size_t boxes,
                             std::size_t batches, std::size_t passes) const {
  ++statistics_.later_rounds;
  statistics_.later_round_points += points;
  statistics_.largest_later_round = std::max(statistics_.largest_later_round, largest);
  statistics_.later_round_boxes += boxes;
  statistics_.later_round_batches += batches;
  statistics_.later_round_passes += passes;
}

void TileSet::renameAll(const std::string& from, const std::string& to) const {
  for (std::size_t t = 0; t < tiles(); ++t) std::filesystem::rename(file(t, from), file(t, to));
}

std::uint64_t TileSet::keptPoints() const {
  std::uint64_t kept = 0;
  for (std::size_t t = 0; t < tiles(); ++t) {
    for (std::uint8_t k : readKept(t)) kept += k;
  }
  return kept;
}

TileNeighbourhood loadNeighbourhood(const TileSet& tiles, std::size_t tile, double halo,
                                    const std::vector<GridPoint>& core_points,
                                    const std::vector<std::uint8_t>& core_kept) {
  TileNeighbourhood hood;
  hood.lo[0] = tiles.lo(tile) - halo;
  hood.hi[0] = tiles.hi(tile) + halo;
  // Past the cloud's ends there is nothing more to load: the halo is infinite there.
  if (hood.lo[0] < tiles.min()[0]) hood.lo[0] = -TileSet::kInfinity;
  if (hood.hi[0] > tiles.max()[0]) hood.hi[0] = TileSet::kInfinity;
  // Reserved once for the tile and every point of the tiles its halo overlaps (appendKeptInBox
  // then finds the room): reserved for the tile alone, the halo's reserve moved the tile's copy
  // into a larger block, the old and new held at once beside the tile's records, round 1's
  // peak (20 M-point trace, NOTES.md). Untouched reserved pages are never made resident.
  std::uint64_t halo_bound = 0;
  for (std::size_t t = 0; halo > 0.0 && t < tiles.tiles(); ++t) {
    if (t != tile && tiles.hi(t) > hood.lo[0] && tiles.lo(t) < hood.hi[0]) {
      halo_bound += tiles.count(t);
    }
  }
  hood.points.reserve(core_points.size() + std::size_t(halo_bound));
  hood.slot.reserve(core_points.size());
  for (std::size_t i = 0; i < core_points.size(); ++i) {
    if (!core_kept[i]) continue;
    hood.points.push_back(core_points[i]);
    hood.slot.push_back(std::uint32_t(i));
  }
  hood.core = hood.points.size();
  if (halo > 0.0) tiles.appendKeptInRange(hood.lo[0], hood.hi[0], tile, hood.points);
  return hood;
}

void groupQueryBalls(std::span<const GridPoint> queries, std::span<const std::uint32_t> pending,
                     std::span<const double> halos, std::vector<BallGroup>& groups,
                     std::vector<QueryBall>& balls, std::vector<std::uint32_t>& ball_of) {
  // A query's cell: the grid of width 2^e >= its halo (frexp: halo = m 2^e, m in [0.5, 1)).
  struct Cell {
    int exponent;
    std::int64_t at[3];
    std::uint32_t j;  // into pending
    bool operator<(const Cell& o) const {
      if (exponent != o.exponent) return exponent < o.exponent;
      for (int a = 0; a < 3; ++a) {
        if (at[a] != o.at[a]) return at[a] < o.at[a];
      }
      return j < o.j;
    }
    bool sameCell(const Cell& o) const {
      return exponent == o.exponent && at[0] == o.at[0] && at[1] == o.at[1] && at[2] == o.at[2];
    }
  };
  std::vector<Cell> cells(pending.size());
  for (std::uint32_t j = 0; j < pending.size(); ++j) {
    int exponent = 0;
    std::frexp(halos[j], &exponent);
    const double width = std::ldexp(1.0, exponent);
    const GridPoint& q = queries[pending[j]];
    const double v[3] = {q.x, q.y, q.z};
    cells[j].exponent = exponent;
    cells[j].j = j;
    for (int a = 0; a < 3; ++a) {
      cells[j].at[a] = std::int64_t(std::clamp(std::floor(v[a] / width), -4e18, 4e18));
    }
  }
  std::sort(cells.begin(), cells.end());
  groups.clear();
  balls.resize(pending.size());
  ball_of.assign(pending.size(), 0);
  for (std::size_t begin = 0; begin < cells.size();) {
    std::size_t end = begin + 1;
    while (end < cells.size() && cells[end].sameCell(cells[begin])) ++end;
    BallGroup group;
    group.begin = std::uint32_t(begin);
    group.end = std::uint32_t(end);
    for (int a = 0; a < 3; ++a) {
      group.box.lo[a] = TileSet::kInfinity;
      group.box.hi[a] = -TileSet::kInfinity;
    }
    for (std::size_t c = begin; c < end; ++c) {
      const std::uint32_t j = cells[c].j;
      const GridPoint& q = queries[pending[j]];
      const double r = halos[j] * (1.0 + 1e-6);
      balls[c] = {q.x, q.y, q.z, r * r};
      ball_of[j] = std::uint32_t(c);
      const double v[3] = {q.x, q.y, q.z};
      // The box a hair wider than the ball: a bucket, not a bound that decides.
      for (int a = 0; a < 3; ++a) {
        group.box.lo[a] = std::min(group.box.lo[a], v[a] - 1.001 * r);
        group.box.hi[a] = std::max(group.box.hi[a], v[a] + 1.001 * r);
      }
    }
    groups.push_back(group);
    begin = end;
  }
}

BallBatches::BallBatches(const TileSet& tiles, std::span<const BallGroup> groups,
                         std::span<const QueryBall> balls, std::uint64_t limit)
    : tiles_(tiles), groups_(groups), balls_(balls), limit_(std::max<std::uint64_t>(limit, 1)) {}

bool BallBatches::next(std::vector<GridPoint>& points) {
  points.clear();
  const std::uint32_t end = std::uint32_t(balls_.size());
  const std::uint32_t from = to_;
  if (from >= end) return false;
  for (;;) {
    // Known counts: the longest run from `from` within the limit (a ball at least); unknown
    // (the round's first pass): the whole round, counted as it goes.
    std::uint32_t to = end;
    std::uint64_t limit = limit_;
    if (counted_) {
      std::uint64_t sum = counts_[from];
      to = from + 1;
      while (to < end && sum + counts_[to] <= limit_) sum += counts_[to++];
      limit = std::max(sum, limit_);
    }
    ++passes_;
    const bool loaded =
        tiles_.appendKeptInBalls(groups_, balls_, from, to, limit, points, spare_, counts_);
    counted_ = true;
    if (!loaded) {
      // Over the limit: the counts from `from` on are known now (spare_), the batches follow.
      std::swap(counts_, spare_);
      points.clear();
      continue;
    }
    from_ = from;
    to_ = to;
    ++batches_;
    points_ += points.size();
    largest_ = std::max<std::uint64_t>(largest_, points.size());
    return true;
  }
}

TileNeighbourhood loadAround(const TileSet& set, std::size_t t, double halo) {
  TileNeighbourhood hood;
  hood.lo[0] = set.lo(t) - halo;
  hood.hi[0] = set.hi(t) + halo;
  if (hood.lo[0] < set.min()[0]) hood.lo[0] = -TileSet::kInfinity;
  if (hood.hi[0] > set.max()[0]) hood.hi[0] = TileSet::kInfinity;
  set.appendKeptInRange(hood.lo[0], hood.hi[0], SIZE_MAX, hood.points);
  return hood;
}

}  // namespace parallax
