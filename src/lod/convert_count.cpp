// Stages 1 and 2 of the conversion (convert_stages.h): scan and count.
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstring>
#include <limits>

#include "core/error.h"
#include "io/point_file.h"
#include "lod/convert_stages.h"
#include "lod/potree_reader.h"

namespace parallax {
namespace {

// The inputs' quantization when they agree and it covers the cube; otherwise per axis the finest
// input scale (coarsened by powers of two until the cube fits in int32) about the cube's centre.
Quantization chooseOutputQuantization(const std::vector<Quantization>& inputs,
                                      const Bounds3& cube) {
  auto covers = [&](const Quantization& q) {
    for (int axis = 0; axis < 3; ++axis) {
      if (!q.fits(axis, cube.min[axis]) || !q.fits(axis, cube.max[axis])) return false;
    }
    return true;
  };
  const bool agree = std::all_of(inputs.begin(), inputs.end(),
                                 [&](const Quantization& q) { return q == inputs.front(); });
  if (agree && covers(inputs.front())) return inputs.front();
  Quantization q;
  const auto center = cube.center();
  for (int axis = 0; axis < 3; ++axis) {
    double scale = inputs.front().scale[std::size_t(axis)];
    for (const Quantization& input : inputs)
      scale = std::min(scale, input.scale[std::size_t(axis)]);
    const double edge = cube.max[axis] - cube.min[axis];
    while (edge / scale > 4.0e9) scale *= 2.0;
    q.scale[std::size_t(axis)] = scale;
    q.offset[std::size_t(axis)] = std::round(center[axis] / scale) * scale;
  }
  return q;
}

}  // namespace

ConvertPlan scanInputs(const std::vector<ConvertInput>& inputs, const OctreeBuildOptions& options,
                       const ProgressFactory& progress, const std::filesystem::path& scratch_dir) {
  ConvertPlan plan;
  std::uint64_t total = 0;
  bool have_layout = false;
  // Opened once each: a text stream parses its positions first to choose its quantization, which
  // the later passes are given (input_quantizations) instead of parsing them again.
  std::vector<std::unique_ptr<PointStream>> streams;
  std::filesystem::path crs_source;
  for (const ConvertInput& input : inputs) {
    streams.push_back(std::make_unique<PointStream>(input.path, input.text_columns, nullptr,
                                                    &input.filter, input.attributes));
    total += streams.back()->pointCount();
    plan.input_quantizations.push_back(streams.back()->quantization());
    // The CRS travels into the octree; merged inputs must not disagree on it (a file that
    // states none is taken to share the others').
    const CoordinateSystem& crs = streams.back()->crs();
    if (crs.empty()) continue;
    if (plan.crs.empty()) {
      plan.crs = crs;
      crs_source = input.path;
    } else if (!plan.crs.sameAs(crs)) {
      throw InputError({.file = input.path.string(),
                        .expected = "the coordinate reference system of " + crs_source.string() +
                                    " (" + plan.crs.summary() + ")",
                        .found = crs.summary(),
                        .hint = "inputs in different coordinate systems cannot be merged into "
                                "one octree: reproject them first (e.g. pdal translate with "
                                "filters.reprojection)"});
    }
  }
  // A first guess of the record size for the batch size (the layout is known after the scan).
  plan.batch_points = std::clamp<std::uint64_t>(options.memory_bytes / 8 / 128, 4096, 4u << 20);
  plan.cancel = options.cancel;
  std::unique_ptr<Progress> bar = progress ? progress("scanning", total) : nullptr;
  // Half the budget for the decoded points kept in memory, all inputs together: the scan, count
  // and distribute passes use the batch's quarter and the count grid besides, and the chunks'
  // share is free until the build, by when the spills are gone.
  std::uint64_t spill_memory = options.memory_bytes / 2;
  plan.spills.resize(inputs.size());
  for (std::size_t index = 0; index < streams.size(); ++index) {
    // Released after its pass: one input's mapping at a time.
    const std::unique_ptr<PointStream> stream = std::move(streams[index]);
    std::shared_ptr<PointSpill>& spill = plan.spills[index];
    if (!scratch_dir.empty() && !isPotreeDirectory(inputs[index].path) &&
        (options.keep_all_decoded || !rereadsCheaply(inputs[index].path))) {
      std::filesystem::create_directories(scratch_dir);
      spill = std::make_shared<PointSpill>(
          scratch_dir / ("decoded-" + std::to_string(index) + ".columns"), spill_memory,
          stream->quantization(), stream->crs());
    }
    PointCloud batch;
    bool first = true;
    while (stream->next(batch, plan.batch_points)) {
      throwIfBuildCancelled(plan.cancel);
      if (first) {
        PotreeLayout layout = PotreeLayout::fromCloud(batch);
        if (!have_layout) {
          plan.layout = std::move(layout);
          have_layout = true;
        } else {
          plan.layout.merge(layout);
        }
        first = false;
      }
      batch.computeBounds();
      plan.bounds.extend(batch.bounds);
      plan.points += batch.count;
      if (bar) bar->advance(batch.count);
      if (spill) spill->add(std::move(batch));
    }
    if (spill) spill_memory -= spill->memoryBytes();
  }
  const bool filtered = std::any_of(inputs.begin(), inputs.end(), [](const ConvertInput& input) {
    return !input.filter.keepsAll();
  });
  if (filtered && plan.points == 0) {
    throw InputError(
        {.file = inputs.front().path.string(),
         .expected =
             "at least one point that the filters (classes, returns, ranges, clip region) keep",
         .found = "none of " + std::to_string(total) + " points",
         .hint = "check the class list and the clip box against the input's "
                 "classes and bounds (parallax info)"});
  }
  if (!have_layout) plan.layout = PotreeLayout::fromCloud(PointCloud{});
  finishScan(plan, options);
  return plan;
}

void finishScan(ConvertPlan& plan, const OctreeBuildOptions& options) {
  plan.cube = octreeCube(plan.bounds);
  plan.spacing = rootSpacing(plan.cube, options);
  plan.quantization = chooseOutputQuantization(plan.input_quantizations, plan.cube);
  plan.stats = plan.layout.emptyStats();

  const std::size_t record = plan.layout.recordSize();
  // A quarter of the budget for a batch in flight (the decoded batch, its records, and two
  // copies grouped by chunk: one being written while the next batch is grouped), the rest for
  // the chunks being built; the count grid's 16 MB aside.
  plan.batch_points =
      std::clamp<std::uint64_t>(options.memory_bytes / 4 / (4 * record + 64), 1024, 4u << 20);
  // Chunks of at most 3/8 of the budget: the build runs chunks side by side within 3/4 of it
  // (convert_build_chunks.cpp), so the two largest fit together. (Half the budget, as before,
  // left a large chunk building alone with a core idle: 8 % more wall time on 100 M points.)
  plan.max_chunk_points =
      options.max_chunk_points > 0
          ? options.max_chunk_points
          : std::max<std::uint64_t>(options.memory_bytes / 8 * 3 / chunkBuildBytesPerPoint(record),
                                    options.max_node_points);
}

// Its record, its position copy, the Morton-sorted (key, index) pairs, the node lists and the
// sampling flags (subtree_builder.cpp).
std::uint64_t chunkBuildBytesPerPoint(std::size_t record_size) {
  return record_size + 12 + 16 + 8 + 8;
}

void countStream(const ConvertPlan& plan, PointStream& stream, std::vector<std::uint64_t>& counts,
                 Progress* bar) {
  const std::size_t cells = ConvertPlan::kGridCells;
  assert(counts.size() == cells && "countStream: counts has one entry per count grid cell");
  // Per-thread counts kept over the batches and summed into `counts` only before they could
  // wrap (summed per batch, the 8 MB per thread were allocated, zeroed and added up 30 times
  // for 100 M points).
  tbb::combinable<std::vector<std::uint32_t>> local(
      [&] { return std::vector<std::uint32_t>(cells, 0); });
  std::uint64_t unsummed = 0;
  auto sumLocal = [&] {
    local.combine_each([&](std::vector<std::uint32_t>& mine) {
      for (std::size_t c = 0; c < cells; ++c) counts[c] += mine[c];
      std::fill(mine.begin(), mine.end(), 0u);
    });
    unsummed = 0;
  };
  PointCloud batch;
  while (stream.next(batch, plan.batch_points)) {
    throwIfBuildCancelled(plan.cancel);
    if (unsummed + batch.count > std::numeric_limits<std::uint32_t>::max()) sumLocal();
    unsummed += batch.count;
    // Positions in the output quantization, as the chunks will see them.
    const bool same = batch.quantization == plan.quantization;
    tbb::parallel_for(tbb::blocked_range<std::uint64_t>(0, batch.count, 1 << 16),
                      [&](const auto& range) {
                        auto& mine = local.local();
                        for (std::uint64_t i = range.begin(); i != range.end(); ++i) {
                          Int3 p = batch.positions[i];
                          if (!same) {
                            p = {plan.quantization.toQuantized(0, batch.worldX(i)),
                                 plan.quantization.toQuantized(1, batch.worldY(i)),
                                 plan.quantization.toQuantized(2, batch.worldZ(i))};
                          }
                          ++mine[plan.cellOf(p)];
                        }
                      });
    if (bar) bar->advance(batch.count);
  }
  sumLocal();
}

void countChunks(ConvertPlan& plan, const std::vector<ConvertInput>& inputs,
                 const ProgressFactory& progress) {
  std::vector<std::uint64_t> counts(ConvertPlan::kGridCells, 0);
  std::unique_ptr<Progress> bar = progress ? progress("counting", plan.points) : nullptr;
  for (std::size_t input = 0; input < inputs.size(); ++input) {
    PointStream stream = openPassStream(plan, inputs, input, false, true);  // (positions only)
    countStream(plan, stream, counts, bar.get());
  }
  planChunks(plan, std::move(counts));
}

void planChunks(ConvertPlan& plan, std::vector<std::uint64_t> counts) {
  const std::size_t cells = ConvertPlan::kGridCells;
  assert(counts.size() == cells && "planChunks: counts has one entry per count grid cell");
  // Count pyramid: level l has 2^l cells a side; level kGridLevel is `counts`.
  std::vector<std::vector<std::uint64_t>> pyramid(ConvertPlan::kGridLevel + 1);
  pyramid[ConvertPlan::kGridLevel] = std::move(counts);
  for (int level = ConvertPlan::kGridLevel - 1; level >= 0; --level) {
    const std::size_t n = std::size_t(1) << level;
    auto& up = pyramid[std::size_t(level)];
    const auto& down = pyramid[std::size_t(level + 1)];
    up.assign(n * n * n, 0);
    for (std::size_t x = 0; x < 2 * n; ++x)
      for (std::size_t y = 0; y < 2 * n; ++y)
        for (std::size_t z = 0; z < 2 * n; ++z)
          up[((x / 2) * n + y / 2) * n + z / 2] += down[(x * 2 * n + y) * 2 * n + z];
  }

  // Chunks: the largest nodes holding at most max_chunk_points (or finest grid cells).
  plan.cell_chunk.assign(cells, -1);
  plan.chunks.clear();
  auto visit = [&](auto&& self, int level, std::size_t x, std::size_t y, std::size_t z,
                   const std::string& name) -> void {
    const std::size_t n = std::size_t(1) << level;
    const std::uint64_t count = pyramid[std::size_t(level)][(x * n + y) * n + z];
    if (count == 0) return;
    if (count <= plan.max_chunk_points || level == ConvertPlan::kGridLevel) {
      const std::int32_t id = std::int32_t(plan.chunks.size());
      plan.chunks.push_back({name, count});
      const std::size_t span = std::size_t(1) << (ConvertPlan::kGridLevel - level);
      for (std::size_t cx = x * span; cx < (x + 1) * span; ++cx)
        for (std::size_t cy = y * span; cy < (y + 1) * span; ++cy)
          for (std::size_t cz = z * span; cz < (z + 1) * span; ++cz)
            plan.cell_chunk[ConvertPlan::cellIndex(cx, cy, cz)] = id;
      return;
    }
    for (int octant = 0; octant < 8; ++octant) {
      self(self, level + 1, 2 * x + ((octant >> 2) & 1), 2 * y + ((octant >> 1) & 1),
           2 * z + (octant & 1), name + char('0' + octant));
    }
  };
  visit(visit, 0, 0, 0, 0, "r");
}

Column<Int3> positionsOfRecords(const std::byte* records, std::uint64_t count,
                                std::size_t record_size) {
  Column<Int3> positions(count);
  tbb::parallel_for(tbb::blocked_range<std::uint64_t>(0, count, 1 << 16), [&](const auto& range) {
    for (std::uint64_t i = range.begin(); i != range.end(); ++i)
      std::memcpy(&positions[i], records + i * record_size, sizeof(Int3));
  });
  return positions;
}

}  // namespace parallax
