// --ground smrf|pmf|csf: a whole-cloud grid step. Two passes over the tiles with a grid of the whole
// cloud's extent between them: the first lowers the minimum surface with every candidate point
// (memory: the grid's cells, not the points), the filter runs on the grid, the second writes
// each candidate's class ("class" records: 2 ground, 1 the rest, 0 left as the input has it).
// The minimum of a cell does not depend on the order points arrive in, so neither does the
// result on the tiling.
#include <cstdio>
#include <memory>
#include <stdexcept>

#include "core/error.h"
#include "process/process_steps.h"
#include "process/tile_queries.h"
#include "terrain/csf.h"
#include "terrain/pmf.h"
#include "terrain/smrf.h"

namespace parallax {

namespace {

constexpr std::uint8_t kGround = 2, kUnclassified = 1;
// A grid cell's bytes at the filter's peak: the minimum, its measured copy, the last and the
// current opening with the row pass between them, the ground and its slope (double each), the
// object and fill flags.
constexpr std::uint64_t kGridBytesPerCell = 64;

struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};

}  // namespace

void writeInputClasses(const StepContext& context) {
  const TileSet& tiles = context.tiles;
  std::vector<std::unique_ptr<std::FILE, FileCloser>> files(tiles.tiles());
  for (std::size_t t = 0; t < tiles.tiles(); ++t) {
    files[t].reset(std::fopen(tiles.file(t, "class_in").c_str(), "wb"));
    if (!files[t]) throw std::runtime_error("cannot write " + tiles.file(t, "class_in").string());
  }
  for (const ConvertInput& input : *context.inputs) {
    PointStream stream(input.path, input.text_columns, nullptr, &input.filter);
    PointCloud batch;
    while (stream.next(batch, tiles.batchPoints())) {
      for (std::size_t i = 0; i < batch.count; ++i) {
        const std::uint8_t c = batch.hasClassification() ? batch.classification[i] : 0;
        if (std::fputc(c, files[tiles.tileOf(batch.worldX(i))].get()) == EOF) {
          throw std::runtime_error("cannot write the input classes to the work folder");
        }
      }
    }
  }
  for (auto& f : files) {
    if (std::fflush(f.get()) != 0) throw std::runtime_error("cannot write the input classes");
  }
}

std::vector<std::uint8_t> currentClasses(const TileSet& tiles, std::size_t t) {
  std::vector<std::uint8_t> classes = tiles.readRecords<std::uint8_t>(t, "class_in");
  if (tiles.has(t, "class")) {
    const std::vector<std::uint8_t> set = tiles.readRecords<std::uint8_t>(t, "class");
    for (std::size_t i = 0; i < classes.size(); ++i) {
      if (set[i]) classes[i] = set[i];
    }
  }
  return classes;
}

namespace {

// Which points of tile `t` the filter classifies: kept, not marked as noise by an earlier step,
// and with --keep-classes only those whose class so far is 0 (never classified) or 1.
std::vector<std::uint8_t> candidates(const GroundStep& step, const TileSet& tiles, std::size_t t) {
  std::vector<std::uint8_t> take = tiles.readKept(t);
  if (tiles.has(t, "mark")) {
    const std::vector<std::uint8_t> mark = tiles.readRecords<std::uint8_t>(t, "mark");
    for (std::size_t i = 0; i < take.size(); ++i) take[i] = take[i] && !mark[i];
  }
  if (step.keep_classes) {
    const std::vector<std::uint8_t> now = currentClasses(tiles, t);
    for (std::size_t i = 0; i < take.size(); ++i) take[i] = take[i] && now[i] <= kUnclassified;
  }
  return take;
}

// The minimum surface of the points `take` says, over every tile (`take(t)`: a flag a point).
template <class Take>
ElevationGrid minimumSurface(const TileSet& tiles, double cell, Take&& take) {
  ElevationGrid minimum =
      ElevationGrid::covering(tiles.min()[0], tiles.min()[1], tiles.max()[0], tiles.max()[1], cell);
  for (std::size_t t = 0; t < tiles.tiles(); ++t) {
    const std::vector<GridPoint> points = tiles.readPoints(t);
    const std::vector<std::uint8_t> flags = take(t);
    for (std::size_t i = 0; i < points.size(); ++i) {
      if (flags[i]) minimum.addMinimum(points[i].x, points[i].y, points[i].z);
    }
  }
  return minimum;
}

// PMF's iterations (terrain/pmf.h), each a pass over the tiles that lowers the "pmf" flags of
// the points above the opening of the last surface and builds the next surface from the others.
void runPmf(const GroundStep& step, const StepContext& context) {
  const TileSet& tiles = context.tiles;
  const PmfParameters& p = step.pmf;
  ElevationGrid minimum =
      minimumSurface(tiles, p.cell_size, [&](std::size_t t) { return candidates(step, tiles, t); });
  for (const PmfIteration& iteration : pmfIterations(p)) {
    const ElevationGrid opened = pmfOpen(minimum, iteration.radius);
    ElevationGrid next(minimum.x0(), minimum.y0(), minimum.cell(), minimum.nx(), minimum.ny());
    for (std::size_t t = 0; t < tiles.tiles(); ++t) {
      const std::vector<GridPoint> points = tiles.readPoints(t);
      std::vector<std::uint8_t> ground = tiles.has(t, "pmf")
                                             ? tiles.readRecords<std::uint8_t>(t, "pmf")
                                             : candidates(step, tiles, t);
      for (std::size_t i = 0; i < points.size(); ++i) {
        if (!ground[i]) continue;
        const GridPoint& q = points[i];
        if (q.z - opened.at(opened.column(q.x), opened.row(q.y)) >= iteration.threshold) {
          ground[i] = 0;
        } else {
          next.addMinimum(q.x, q.y, q.z);
        }
      }
      tiles.writeRecords<std::uint8_t>(t, "pmf", ground);
    }
    minimum = std::move(next);
  }
}

}  // namespace

void runGroundStep(const GroundStep& step, const StepContext& context) {
  const TileSet& tiles = context.tiles;
  const bool pmf = step.method == GroundStep::Method::kPmf;
  const bool csf = step.method == GroundStep::Method::kCsf;
  const double cell = pmf ? step.pmf.cell_size : csf ? step.csf.resolution : step.smrf.cell;
  const double cells = ElevationGrid::cellsCovering(tiles.min()[0], tiles.min()[1], tiles.max()[0],
                                                    tiles.max()[1], cell);
  const double budget = double(context.memory_mb) * double(std::uint64_t(1) << 20);
  if (tiles.points() > 0 && (cells > budget / kGridBytesPerCell || cells > 0x1p32)) {
    char text[200];
    std::snprintf(text, sizeof text,
                  ": the cloud's extent at cell %g is %.6g cells, %.6g MB at %llu bytes a cell, "
                  "over --memory %llu: raise --memory or the cell",
                  cell, cells, cells * double(kGridBytesPerCell) / 1048576.0,
                  static_cast<unsigned long long>(kGridBytesPerCell),
                  static_cast<unsigned long long>(context.memory_mb));
    throw std::invalid_argument(context.label + text);
  }
  if (tiles.points() == 0) return;
  auto bar = context.progress ? context.progress(context.label, tiles.tiles()) : nullptr;
  if (step.keep_classes && !tiles.has(0, "class_in")) writeInputClasses(context);

  SmrfSurface surface;
  CsfCloth cloth;
  auto candidatesOf = [&](std::size_t t) { return candidates(step, tiles, t); };
  if (pmf) {
    runPmf(step, context);
  } else if (csf) {
    cloth = csfCloth(minimumSurface(tiles, cell, candidatesOf), step.csf);
  } else {
    surface = smrfSurface(minimumSurface(tiles, cell, candidatesOf), step.smrf);
  }

  for (std::size_t t = 0; t < tiles.tiles(); ++t) {
    const std::vector<GridPoint> points = tiles.readPoints(t);
    const std::vector<std::uint8_t> take = candidates(step, tiles, t);
    const std::vector<std::uint8_t> pmf_ground =
        pmf ? tiles.readRecords<std::uint8_t>(t, "pmf") : std::vector<std::uint8_t>();
    std::vector<std::uint8_t> classes = tiles.has(t, "class")
                                            ? tiles.readRecords<std::uint8_t>(t, "class")
                                            : std::vector<std::uint8_t>(points.size(), 0);
    for (std::size_t i = 0; i < points.size(); ++i) {
      if (!take[i]) continue;
      const GridPoint& q = points[i];
      const bool ground = pmf   ? pmf_ground[i] != 0
                          : csf ? csfIsGround(cloth, step.csf, q.x, q.y, q.z)
                                : smrfIsGround(surface, step.smrf, q.x, q.y, q.z);
      classes[i] = ground ? kGround : kUnclassified;
    }
    tiles.writeRecords<std::uint8_t>(t, "class", classes);
    if (bar) bar->advance(1);
  }
  if (pmf) {
    for (std::size_t t = 0; t < tiles.tiles(); ++t) std::filesystem::remove(tiles.file(t, "pmf"));
  }
}

}  // namespace parallax
