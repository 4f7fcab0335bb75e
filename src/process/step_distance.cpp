// --distance-to REF [--local-model plane]: each kept point's distance to the reference cloud,
// the tiles' "distance" records (float). The reference is tiled with the same edges, so the
// reference points near a tile are those of the same slab and its neighbours.
#include <cmath>

#include "core/error.h"
#include "process/local_plane.h"
#include "process/process_steps.h"
#include "process/tile_queries.h"

namespace parallax {

void runDistanceStep(const DistanceStep& step, const StepContext& context) {
  const TileSet& tiles = context.tiles;
  const std::filesystem::path ref_dir = context.work_dir / "reference";
  std::filesystem::create_directories(ref_dir);
  const TileSet reference =
      TileSet::spill({ConvertInput{.path = step.reference}}, ref_dir, "ref",
                     context.max_tile_points, &tiles.edges(), context.progress);
  const std::size_t k = step.plane ? step.k : 1;
  if (reference.points() < k) {
    throw InputError(
        {.file = step.reference.string(),
         .expected = "at least " + std::to_string(k) + " reference points for " + context.label,
         .found = std::to_string(reference.points()) + " points"});
  }
  auto bar = context.progress ? context.progress(context.label, tiles.points()) : nullptr;
  for (std::size_t t = 0; t < tiles.tiles(); ++t) {
    std::vector<float> distance(tiles.count(t), 0.0f);
    // The tile's kept points are the queries (with no halo, the whole of the load): the slab's
    // records, a copy of them, are not held through the rounds.
    TileNeighbourhood own =
        loadNeighbourhood(tiles, t, 0.0, tiles.readPoints(t), tiles.readKept(t));
    const std::vector<GridPoint> queries = std::move(own.points);
    own.points = {};
    // The reference points in the tile and its halo: the reference's own tile t is no "core".
    auto load = [&](double halo) { return loadAround(reference, t, halo); };
    const double halo =
        2.0 * NeighbourIndex::radiusForCount(queries, std::max<double>(4.0, double(k)));
    answerTileQueries(
        queries, halo, load, reference,
        [&](const TileNeighbourhood& hood, const NeighbourIndex& grid, std::uint32_t i,
            const GridPoint& q, std::vector<Neighbour>& neighbours, double& needed) -> bool {
          grid.nearest(q.x, q.y, q.z, k, neighbours);
          const double reach =
              neighbours.size() < k ? TileSet::kInfinity : std::sqrt(neighbours.back().d2);
          if (!hood.covers(q, reach)) {
            needed = reach;
            return false;
          }
          double d = reach;
          if (step.plane) {
            const LocalPlane plane = fitLocalPlane(grid.points(), neighbours);
            if (plane.valid) {
              d = std::abs(plane.normal[0] * (q.x - plane.centroid[0]) +
                           plane.normal[1] * (q.y - plane.centroid[1]) +
                           plane.normal[2] * (q.z - plane.centroid[2]));
            } else {
              d = std::sqrt(neighbours.front().d2);  // no plane: to the nearest point
            }
          }
          distance[own.slot[i]] = float(d);
          return true;
        });
    tiles.writeRecords<float>(t, "distance", distance);
    if (bar) bar->advance(tiles.count(t));
  }
}

}  // namespace parallax
