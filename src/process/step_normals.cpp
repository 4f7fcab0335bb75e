// --normals K / --normals-radius R: a normal for every kept point from the plane of its
// neighbourhood (local_plane.h), oriented as asked; written as the tiles' "normals" records
// (and "curvature" with --curvature).
#include <algorithm>
#include <cmath>
#include <queue>
#include <stdexcept>

#include "process/local_plane.h"
#include "process/process_runner.h"
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

// Hoppe et al. 1992: a minimum spanning tree over the K-nearest graph, edges weighted
// 1 - |n_i . n_j| (nearly parallel normals first), grown by Prim from the highest point (its
// normal turned up); each point reached is flipped to agree with the one it was reached from.
// A graph of several parts starts again from the highest point not yet reached. Ties in the
// queue go to the smaller index: the tree does not depend on anything but the points.
void propagateOrientation(const TileSet& tiles, std::uint32_t k) {
  const std::vector<GridPoint> points = tiles.readPoints(0);
  const std::vector<std::uint8_t> kept = tiles.readKept(0);
  std::vector<Normal> normals = tiles.readRecords<Normal>(0, "normals");
  std::vector<GridPoint> live;
  std::vector<std::uint32_t> slot;
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (!kept[i]) continue;
    live.push_back(points[i]);
    slot.push_back(std::uint32_t(i));
  }
  const NeighbourIndex index(live);
  std::vector<std::vector<Neighbour>> graph(live.size());
  tbb::parallel_for(std::size_t(0), live.size(), [&](std::size_t i) {
    index.nearest(live[i].x, live[i].y, live[i].z, std::size_t(k) + 1, graph[i]);
  });
  // Undirected: j's list gets i where i found j.
  std::vector<std::vector<std::uint32_t>> adjacent(live.size());
  for (std::size_t i = 0; i < live.size(); ++i) {
    for (const Neighbour& n : graph[i]) {
      if (n.at == i) continue;
      adjacent[i].push_back(n.at);
      adjacent[n.at].push_back(std::uint32_t(i));
    }
  }
  graph.clear();
  auto normal = [&](std::uint32_t i) -> Normal& { return normals[slot[i]]; };
  auto weight = [&](std::uint32_t a, std::uint32_t b) {
    const Normal& na = normal(a);
    const Normal& nb = normal(b);
    return 1.0 - std::abs(double(na.x) * nb.x + double(na.y) * nb.y + double(na.z) * nb.z);
  };
  std::vector<std::uint8_t> reached(live.size(), 0);
  std::vector<std::uint32_t> by_height(live.size());
  for (std::uint32_t i = 0; i < by_height.size(); ++i) by_height[i] = i;
  std::sort(by_height.begin(), by_height.end(), [&](std::uint32_t a, std::uint32_t b) {
    return live[a].z > live[b].z || (live[a].z == live[b].z && live[a].id < live[b].id);
  });
  struct Edge {
    double weight;
    std::uint64_t to_id;
    std::uint32_t from, to;
    bool operator>(const Edge& o) const {
      return weight > o.weight || (weight == o.weight && to_id > o.to_id);
    }
  };
  std::priority_queue<Edge, std::vector<Edge>, std::greater<Edge>> queue;
  for (std::uint32_t root : by_height) {
    if (reached[root]) continue;
    reached[root] = 1;
    Normal& n = normal(root);
    if (n.z < 0.0f) n = {-n.x, -n.y, -n.z};
    auto grow = [&](std::uint32_t from) {
      for (std::uint32_t to : adjacent[from]) {
        if (!reached[to]) queue.push({weight(from, to), live[to].id, from, to});
      }
    };
    grow(root);
    while (!queue.empty()) {
      const Edge e = queue.top();
      queue.pop();
      if (reached[e.to]) continue;
      reached[e.to] = 1;
      const Normal& a = normal(e.from);
      Normal& b = normal(e.to);
      if (double(a.x) * b.x + double(a.y) * b.y + double(a.z) * b.z < 0.0) b = {-b.x, -b.y, -b.z};
      grow(e.to);
    }
  }
  tiles.writeRecords<Normal>(0, "normals", normals);
}

}  // namespace

void runNormalsStep(const NormalsStep& step, const StepContext& context) {
  // --orient sensor: turned up here, and towards each point's sensor when the output is written
  // (process_runner.cpp), where the input's columns and scans are at hand; the tiles carry
  // positions only.
  const TileSet& tiles = context.tiles;
  if (step.orientation == NormalOrientation::kPropagate && tiles.tiles() > 1) {
    // The spanning tree joins the whole cloud; out of core it would need the tiles' graphs joined
    // at their halos (NOTES.md). Refused rather than oriented per tile, which would make the
    // output depend on --memory.
    throw std::invalid_argument(
        context.label + " --orient propagate: the cloud must fit one tile; give --memory " +
        std::to_string((tiles.points() * kProcessBytesPerPoint >> 20) + 1) + " or more");
  }
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
        tiles,
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
          if (!hood.covers(q, reach)) return false;
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
  if (step.orientation == NormalOrientation::kPropagate && tiles.tiles() == 1) {
    propagateOrientation(tiles, step.k ? step.k : 8);
  }
}

}  // namespace parallax
