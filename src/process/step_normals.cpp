// --normals K / --normals-radius R: a normal for every kept point from the plane of its
// neighbourhood (local_plane.h), oriented as asked; written as the tiles' "normals" records
// (and "curvature" with --curvature).
#include <cmath>
#include <stdexcept>

#include "process/local_plane.h"
#include "process/process_steps.h"
#include "process/tile_queries.h"

namespace parallax {

namespace {

struct Normal {
  float x, y, z;
};

void orient(const NormalsStep& step, const GridPoint& p, double n[3]) {
  double toward[3] = {0.0, 0.0, 1.0};
  if (step.orientation == NormalOrientation::kPoint) {
    toward[0] = step.toward[0] - p.x;
    toward[1] = step.toward[1] - p.y;
    toward[2] = step.toward[2] - p.z;
  }
  if (n[0] * toward[0] + n[1] * toward[1] + n[2] * toward[2] < 0.0) {
    for (int a = 0; a < 3; ++a) n[a] = -n[a];
  }
}

}  // namespace

void runNormalsStep(const NormalsStep& step, const StepContext& context) {
  if (step.orientation == NormalOrientation::kSensor ||
      step.orientation == NormalOrientation::kPropagate) {
    // Caught before any work by the runner (process_runner.cpp); kept here as the contract.
    throw std::logic_error("runNormalsStep: orientation not supported by the tiled path");
  }
  const TileSet& tiles = context.tiles;
  auto bar = context.progress ? context.progress(context.label, tiles.points()) : nullptr;
  for (std::size_t t = 0; t < tiles.tiles(); ++t) {
    const std::vector<GridPoint> points = tiles.readPoints(t);
    const std::vector<std::uint8_t> kept = tiles.readKept(t);
    std::vector<Normal> normals(points.size(), Normal{0, 0, 0});
    std::vector<float> curvature(points.size(), 0.0f);
    TileNeighbourhood first = loadNeighbourhood(tiles, t, 0.0, points, kept);
    const std::vector<GridPoint> queries(first.points.begin(), first.points.begin() + first.core);
    const std::vector<std::uint32_t> slot = first.slot;
    first = {};
    const double halo = step.k ? 1.5 * NeighbourIndex::radiusForCount(queries, double(step.k))
                               : step.radius * (1.0 + 1e-9);
    answerTileQueries(
        queries, halo, [&](double h) { return loadNeighbourhood(tiles, t, h, points, kept); },
        [&](const TileNeighbourhood& hood, const NeighbourIndex& grid, std::uint32_t i,
            const GridPoint& q, std::vector<Neighbour>& neighbours) -> bool {
          double reach = step.radius;
          if (step.k) {
            grid.nearest(q.x, q.y, q.z, step.k, neighbours);
            reach =
                neighbours.size() < step.k ? TileSet::kInfinity : std::sqrt(neighbours.back().d2);
          } else {
            grid.withinRadius(q.x, q.y, q.z, step.radius, neighbours);
          }
          if (!hood.covers(q.x, reach)) return false;
          const LocalPlane plane = fitLocalPlane(grid.points(), neighbours);
          if (plane.valid) {
            double n[3] = {plane.normal[0], plane.normal[1], plane.normal[2]};
            orient(step, q, n);
            normals[slot[i]] = {float(n[0]), float(n[1]), float(n[2])};
            curvature[slot[i]] = float(plane.curvature);
          }
          return true;
        });
    tiles.writeRecords<Normal>(t, "normals", normals);
    if (step.curvature) tiles.writeRecords<float>(t, "curvature", curvature);
    if (bar) bar->advance(points.size());
  }
}

}  // namespace parallax
