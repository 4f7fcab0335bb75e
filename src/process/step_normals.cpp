// --normals K / --normals-radius R: a normal for every kept point from the plane of its
// neighbourhood (local_plane.h), oriented as asked; written as the tiles' "normals" records
// (and "curvature" with --curvature).
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>
#include <stdexcept>
#include <tuple>

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

// Hoppe et al. 1992: a minimum spanning tree over the K-nearest graph of `live`, edges weighted
// 1 - |n_i . n_j| (nearly parallel normals first), grown by Prim from the highest point (its
// normal turned up); each point reached is flipped to agree with the one it was reached from.
// A graph of several parts starts again from the highest point not yet reached. Ties in the
// queue go to the smaller id: the tree depends on nothing but the points. `part[i]`: the part
// (0, 1, ... in the order they were grown) point i was reached in; returns the parts' roots.
std::vector<std::uint32_t> propagateOrientation(const std::vector<GridPoint>& live,
                                                std::vector<Normal*>& normal_of, std::uint32_t k,
                                                std::vector<std::uint32_t>& part) {
  // The K-nearest graph, undirected, in compressed rows: j's row gets i where i found j. The
  // rows hold what one list a point with push_back held before, in the same order (each row in
  // the order of the i that added to it, i's own neighbours at i's turn), so Prim's queue sees
  // the same edges in the same order. A point's own list holds k + 1 ids at most (itself not
  // among them when k + 1 duplicates of smaller id came first): 4 (k + 1) bytes a point, the
  // rows twice that, instead of lists of 24-byte Neighbour records.
  const std::size_t stride = std::size_t(k) + 1;
  constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
  std::vector<std::uint32_t> found(live.size() * stride, kNone);
  {
    const NeighbourIndex index(live);
    tbb::enumerable_thread_specific<std::vector<Neighbour>> scratch;
    tbb::parallel_for(std::size_t(0), live.size(), [&](std::size_t i) {
      std::vector<Neighbour>& neighbours = scratch.local();
      index.nearest(live[i].x, live[i].y, live[i].z, stride, neighbours);
      std::uint32_t* row = found.data() + i * stride;
      for (const Neighbour& n : neighbours) {
        if (n.at != i) *row++ = n.at;
      }
    });
  }
  std::vector<std::uint64_t> first(live.size() + 1, 0);
  for (std::size_t i = 0; i < live.size(); ++i) {
    for (std::size_t e = i * stride; e < (i + 1) * stride && found[e] != kNone; ++e) {
      ++first[i + 1];
      ++first[found[e] + 1];
    }
  }
  for (std::size_t i = 0; i < live.size(); ++i) first[i + 1] += first[i];
  std::vector<std::uint32_t> adjacent(first.back());
  {
    std::vector<std::uint64_t> end(first.begin(), first.end() - 1);
    for (std::size_t i = 0; i < live.size(); ++i) {
      for (std::size_t e = i * stride; e < (i + 1) * stride && found[e] != kNone; ++e) {
        adjacent[end[i]++] = found[e];
        adjacent[end[found[e]]++] = std::uint32_t(i);
      }
    }
  }
  found = std::vector<std::uint32_t>();  // `= {}` would keep the capacity (assign)
  auto normal = [&](std::uint32_t i) -> Normal& { return *normal_of[i]; };
  auto weight = [&](std::uint32_t a, std::uint32_t b) {
    const Normal& na = normal(a);
    const Normal& nb = normal(b);
    return 1.0 - std::abs(double(na.x) * nb.x + double(na.y) * nb.y + double(na.z) * nb.z);
  };
  constexpr std::uint32_t kUnreached = std::numeric_limits<std::uint32_t>::max();
  part.assign(live.size(), kUnreached);
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
  std::vector<std::uint32_t> roots;
  for (std::uint32_t root : by_height) {
    if (part[root] != kUnreached) continue;
    const std::uint32_t current = std::uint32_t(roots.size());
    roots.push_back(root);
    part[root] = current;
    Normal& n = normal(root);
    if (n.z < 0.0f) n = {-n.x, -n.y, -n.z};
    auto grow = [&](std::uint32_t from) {
      for (std::uint64_t e = first[from]; e < first[from + 1]; ++e) {
        const std::uint32_t to = adjacent[e];
        if (part[to] == kUnreached) queue.push({weight(from, to), live[to].id, from, to});
      }
    };
    grow(root);
    while (!queue.empty()) {
      const Edge e = queue.top();
      queue.pop();
      if (part[e.to] != kUnreached) continue;
      part[e.to] = current;
      const Normal& a = normal(e.from);
      Normal& b = normal(e.to);
      if (double(a.x) * b.x + double(a.y) * b.y + double(a.z) * b.z < 0.0) b = {-b.x, -b.y, -b.z};
      grow(e.to);
    }
  }
  return roots;
}

// --orient propagate over several tiles, so the orientation crosses their borders:
// 1. each tile's parts are oriented by propagateOrientation, every part from its own root;
// 2. at each border, the K-nearest graph of the points within a band either side joins parts of
//    the two tiles; of the edges joining two parts the lightest (1 - |n_a . n_b|, ties by ids)
//    says whether one must be flipped to agree with the other;
// 3. a spanning tree over the parts (Prim over those joins, lightest first, from the part of
//    the highest root, then the highest root not yet reached) decides each part's flip;
// 4. the flips are applied. With one tile, 2-4 do nothing: the whole cloud's tree.
void propagateOverTiles(const TileSet& tiles, std::uint32_t k) {
  struct Part {
    GridPoint root;
    std::uint8_t flip = 0;
  };
  std::vector<Part> parts;
  std::vector<std::size_t> first_part(tiles.tiles() + 1, 0);
  std::vector<double> band(tiles.tiles(), 0.0);
  for (std::size_t t = 0; t < tiles.tiles(); ++t) {
    const std::vector<GridPoint> points = tiles.readPoints(t);
    const std::vector<std::uint8_t> kept = tiles.readKept(t);
    std::vector<Normal> normals = tiles.readRecords<Normal>(t, "normals");
    std::vector<GridPoint> live;
    std::vector<Normal*> normal_of;
    for (std::size_t i = 0; i < points.size(); ++i) {
      if (!kept[i]) continue;
      live.push_back(points[i]);
      normal_of.push_back(&normals[i]);
    }
    std::vector<std::uint32_t> part;
    const std::vector<std::uint32_t> roots = propagateOrientation(live, normal_of, k, part);
    first_part[t] = parts.size();
    for (std::uint32_t r : roots) parts.push_back({live[r], 0});
    std::vector<std::uint32_t> part_of(points.size(), 0);
    for (std::size_t i = 0, j = 0; i < points.size(); ++i) {
      if (kept[i]) part_of[i] = std::uint32_t(first_part[t]) + part[j++];
    }
    // A band of about 4 K neighbours' reach on this tile's density.
    band[t] = 4.0 * NeighbourIndex::radiusForCount(live, double(k));
    tiles.writeRecords<Normal>(t, "normals", normals);
    tiles.writeRecords<std::uint32_t>(t, "part", part_of);
  }
  first_part[tiles.tiles()] = parts.size();
  if (tiles.tiles() == 1) return;

  struct Join {
    double weight;
    std::uint64_t id_a, id_b;
    std::uint32_t a, b;
    std::uint8_t opposite;  // the normals point apart: one part flips against the other
  };
  std::vector<Join> joins;
  auto lighter = [](const Join& a, const Join& b) {
    return std::tie(a.weight, a.id_a, a.id_b) < std::tie(b.weight, b.id_a, b.id_b);
  };
  for (std::size_t t = 0; t + 1 < tiles.tiles(); ++t) {
    const std::size_t border_start = joins.size();
    const double width = std::max(band[t], band[t + 1]);
    std::vector<GridPoint> near;
    std::vector<Normal> near_normals;
    std::vector<std::uint32_t> near_part;
    std::size_t left = 0;
    for (std::size_t side = t; side <= t + 1; ++side) {
      const std::vector<GridPoint> points = tiles.readPoints(side);
      const std::vector<std::uint8_t> kept = tiles.readKept(side);
      const std::vector<Normal> normals = tiles.readRecords<Normal>(side, "normals");
      const std::vector<std::uint32_t> part = tiles.readRecords<std::uint32_t>(side, "part");
      for (std::size_t i = 0; i < points.size(); ++i) {
        const bool in_band =
            side == t ? points[i].x >= tiles.hi(t) - width : points[i].x < tiles.hi(t) + width;
        if (!kept[i] || !in_band) continue;
        near.push_back(points[i]);
        near_normals.push_back(normals[i]);
        near_part.push_back(part[i]);
      }
      if (side == t) left = near.size();
    }
    const NeighbourIndex index(near);
    std::vector<Neighbour> found;
    for (std::size_t i = 0; i < left; ++i) {
      index.nearest(near[i].x, near[i].y, near[i].z, std::size_t(k) + 1, found);
      for (const Neighbour& n : found) {
        if (n.at < left) continue;  // the same tile: already in its part's tree
        const Normal& a = near_normals[i];
        const Normal& b = near_normals[n.at];
        const double dot = double(a.x) * b.x + double(a.y) * b.y + double(a.z) * b.z;
        joins.push_back({1.0 - std::abs(dot), near[i].id, near[n.at].id, near_part[i],
                         near_part[n.at], std::uint8_t(dot < 0.0)});
      }
    }
    // Only the lightest join of two parts can be taken by the tree over the parts: the border's
    // others are dropped, so the joins kept grow with the parts, not with the band's points.
    std::sort(joins.begin() + std::ptrdiff_t(border_start), joins.end(),
              [&](const Join& a, const Join& b) {
                return std::tie(a.a, a.b) < std::tie(b.a, b.b) ||
                       (std::tie(a.a, a.b) == std::tie(b.a, b.b) && lighter(a, b));
              });
    joins.erase(std::unique(joins.begin() + std::ptrdiff_t(border_start), joins.end(),
                            [](const Join& a, const Join& b) { return a.a == b.a && a.b == b.b; }),
                joins.end());
  }
  // Prim over the parts: joins lightest first (ties by the points' ids).
  std::vector<std::vector<std::size_t>> joins_of(parts.size());
  for (std::size_t j = 0; j < joins.size(); ++j) {
    joins_of[joins[j].a].push_back(j);
    joins_of[joins[j].b].push_back(j);
  }
  auto heavier = [&](std::size_t x, std::size_t y) { return lighter(joins[y], joins[x]); };
  std::vector<std::uint32_t> order(parts.size());
  for (std::uint32_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
    const GridPoint& p = parts[a].root;
    const GridPoint& q = parts[b].root;
    return p.z > q.z || (p.z == q.z && p.id < q.id);
  });
  std::vector<std::uint8_t> reached(parts.size(), 0);
  std::priority_queue<std::size_t, std::vector<std::size_t>, decltype(heavier)> queue(heavier);
  for (std::uint32_t root : order) {
    if (reached[root]) continue;
    reached[root] = 1;
    for (std::size_t j : joins_of[root]) queue.push(j);
    while (!queue.empty()) {
      const Join& e = joins[queue.top()];
      queue.pop();
      if (reached[e.a] && reached[e.b]) continue;
      const std::uint32_t from = reached[e.a] ? e.a : e.b;
      const std::uint32_t to = reached[e.a] ? e.b : e.a;
      reached[to] = 1;
      parts[to].flip = parts[from].flip ^ e.opposite;
      for (std::size_t j : joins_of[to]) queue.push(j);
    }
  }
  for (std::size_t t = 0; t < tiles.tiles(); ++t) {
    std::vector<Normal> normals = tiles.readRecords<Normal>(t, "normals");
    const std::vector<std::uint8_t> kept = tiles.readKept(t);
    const std::vector<std::uint32_t> part = tiles.readRecords<std::uint32_t>(t, "part");
    for (std::size_t i = 0; i < normals.size(); ++i) {
      if (kept[i] && parts[part[i]].flip)
        normals[i] = {-normals[i].x, -normals[i].y, -normals[i].z};
    }
    tiles.writeRecords<Normal>(t, "normals", normals);
  }
}

}  // namespace

void runNormalsStep(const NormalsStep& step, const StepContext& context) {
  // --orient sensor: turned up here, and towards each point's sensor when the output is written
  // (process_runner.cpp), where the input's columns and scans are at hand; the tiles carry
  // positions only.
  const TileSet& tiles = context.tiles;
  auto bar = context.progress ? context.progress(context.label, tiles.points()) : nullptr;
  for (std::size_t t = 0; t < tiles.tiles(); ++t) {
    // The slab's records (32 bytes a point) are read by the first round only: freed once it has
    // loaded, before its index is built (the step's peak), not held through the later rounds.
    std::vector<GridPoint> points = tiles.readPoints(t);
    std::vector<std::uint8_t> kept = tiles.readKept(t);
    const std::size_t count = points.size();
    std::vector<Normal> normals(count, Normal{0, 0, 0});
    std::vector<float> curvature(count, 0.0f);
    TileNeighbourhood first = loadNeighbourhood(tiles, t, 0.0, points, kept);
    // With no halo the neighbourhood is the tile's kept points alone: they are the queries.
    const std::vector<GridPoint> queries = std::move(first.points);
    const std::vector<std::uint32_t> slot = std::move(first.slot);
    first = {};
    const double halo = step.k ? 1.5 * NeighbourIndex::radiusForCount(queries, double(step.k))
                               : step.radius * (1.0 + 1e-9);
    answerTileQueries(
        queries, halo,
        [&](double h) {
          TileNeighbourhood hood = loadNeighbourhood(tiles, t, h, points, kept);
          // Not `= {}`: that is assign(initializer_list), which keeps the capacity.
          points = std::vector<GridPoint>();
          kept = std::vector<std::uint8_t>();
          return hood;
        },
        tiles,
        [&](const TileNeighbourhood& hood, const NeighbourIndex& grid, std::uint32_t i,
            const GridPoint& q, std::vector<Neighbour>& neighbours, double& needed) -> bool {
          double reach = step.radius;
          if (step.k) {
            grid.nearest(q.x, q.y, q.z, step.k, neighbours);
            reach =
                neighbours.size() < step.k ? TileSet::kInfinity : std::sqrt(neighbours.back().d2);
          } else {
            grid.withinRadius(q.x, q.y, q.z, step.radius, neighbours);
          }
          if (!hood.covers(q, reach)) {
            needed = reach;
            return false;
          }
          const LocalPlane plane = fitLocalPlane(grid, neighbours);
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
    traceMemory("normals slab " + std::to_string(t) + " written", count);
    if (bar) bar->advance(count);
  }
  if (step.orientation == NormalOrientation::kPropagate) {
    propagateOverTiles(tiles, step.k ? step.k : 8);
  }
}

}  // namespace parallax
