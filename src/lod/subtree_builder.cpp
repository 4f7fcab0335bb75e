#include "lod/subtree_builder.h"

#include <tbb/parallel_for.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <cmath>
#include <memory>

#include "core/morton.h"

namespace parallax {
namespace {

// Bits of Morton code per axis: a subtree splits at most this many levels deep; below that the
// points are (nearly) coincident and stay in one leaf however many there are.
constexpr int kMortonBits = 21;
// Subtrees smaller than this are built on the calling thread (task overhead dominates).
constexpr std::size_t kParallelThreshold = 50'000;

struct KeyedPoint {
  std::uint64_t key;
  std::uint32_t index;
};

struct TreeNode {
  std::vector<std::uint32_t> points;
  std::array<std::unique_ptr<TreeNode>, 8> children;
  bool isLeaf() const {
    return std::none_of(children.begin(), children.end(), [](const auto& c) { return bool(c); });
  }
};

class Builder {
 public:
  Builder(std::span<const Int3> positions, const Quantization& quantization,
          const OctreeBuildOptions& options, const Sampler& sampler,
          std::span<const KeyedPoint> sorted)
      : positions_(positions),
        quantization_(quantization),
        options_(options),
        sampler_(sampler),
        sorted_(sorted) {}

  std::unique_ptr<TreeNode> build(std::size_t begin, std::size_t end, int depth, const Bounds3& box,
                                  double spacing) const {
    auto node = std::make_unique<TreeNode>();
    if (end - begin <= options_.max_node_points || depth >= kMortonBits) {
      node->points.reserve(end - begin);
      for (std::size_t i = begin; i < end; ++i) node->points.push_back(std::uint32_t(i));
      return node;
    }
    // The sorted order holds the octants one after the other: find their boundaries.
    const int shift = 3 * (kMortonBits - 1 - depth);
    std::array<std::size_t, 9> bounds{};
    bounds[0] = begin;
    for (int octant = 0; octant < 8; ++octant) {
      bounds[octant + 1] =
          std::size_t(std::partition_point(sorted_.begin() + std::ptrdiff_t(bounds[octant]),
                                           sorted_.begin() + std::ptrdiff_t(end),
                                           [&](const KeyedPoint& p) {
                                             return int((p.key >> shift) & 7) <= octant;
                                           }) -
                      sorted_.begin());
    }
    auto buildChild = [&](int octant) {
      if (bounds[octant + 1] > bounds[octant]) {
        node->children[octant] = build(bounds[octant], bounds[octant + 1], depth + 1,
                                       childBox(box, octant), spacing * 0.5);
      }
    };
    if (end - begin >= kParallelThreshold) {
      tbb::task_group group;
      for (int octant = 0; octant < 8; ++octant) group.run([&, octant] { buildChild(octant); });
      group.wait();
    } else {
      for (int octant = 0; octant < 8; ++octant) buildChild(octant);
    }
    std::array<std::vector<std::uint32_t>*, 8> lists{};
    int count = 0;
    for (auto& child : node->children) {
      if (child) lists[std::size_t(count++)] = &child->points;
    }
    takeSample(positions_, quantization_, box, spacing, std::span(lists.data(), std::size_t(count)),
               node->points, sampler_);
    for (auto& child : node->children) {
      if (child && child->points.empty() && child->isLeaf()) child.reset();
    }
    return node;
  }

 private:
  std::span<const Int3> positions_;
  const Quantization& quantization_;
  const OctreeBuildOptions& options_;
  const Sampler& sampler_;
  std::span<const KeyedPoint> sorted_;
};

constexpr int kRadixBits = 9;

bool keyedLess(const KeyedPoint& x, const KeyedPoint& y) {
  return x.key < y.key || (x.key == y.key && x.index < y.index);
}

// Sorts `points` (which share the key bits above `shift + kRadixBits`) by key then index: a
// stable counting sort on the bits [shift, shift + kRadixBits) through `scratch`, then each
// piece the same way on the next bits while it is large, by comparisons once it is small.
void sortBucket(std::span<KeyedPoint> points, std::span<KeyedPoint> scratch, int shift) {
  constexpr std::size_t kSmall = 64;
  if (points.size() <= kSmall) {
    std::sort(points.begin(), points.end(), keyedLess);
    return;
  }
  constexpr std::size_t kPieces = std::size_t(1) << kRadixBits;
  std::array<std::uint32_t, kPieces + 1> start{};
  for (const KeyedPoint& p : points) ++start[((p.key >> shift) & (kPieces - 1)) + 1];
  for (std::size_t b = 0; b < kPieces; ++b) start[b + 1] += start[b];
  std::array<std::uint32_t, kPieces> at{};
  std::copy(start.begin(), start.end() - 1, at.begin());
  for (const KeyedPoint& p : points) scratch[at[(p.key >> shift) & (kPieces - 1)]++] = p;
  std::copy(scratch.begin(), scratch.end(), points.begin());
  for (std::size_t b = 0; b < kPieces; ++b) {
    const std::size_t size = start[b + 1] - start[b];
    if (size > kSmall && shift >= kRadixBits) {
      sortBucket(points.subspan(start[b], size), scratch.subspan(start[b], size),
                 shift - kRadixBits);
    } else if (size > 1) {
      std::sort(points.begin() + start[b], points.begin() + start[b + 1], keyedLess);
    }
  }
}

std::vector<KeyedPoint> mortonOrder(std::span<const Int3> positions, const Quantization& q,
                                    const Bounds3& box) {
  std::vector<KeyedPoint> keyed(positions.size());
  const double cells = double(1u << kMortonBits);
  std::array<double, 3> factor{};
  for (int axis = 0; axis < 3; ++axis) factor[axis] = cells / (box.max[axis] - box.min[axis]);
  auto cell = [&](int axis, std::int32_t value) {
    const double c = std::floor((q.toWorld(axis, value) - box.min[axis]) * factor[axis]);
    return std::uint64_t(std::clamp(c, 0.0, cells - 1.0));
  };
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, positions.size(), 1 << 16),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      for (std::size_t i = range.begin(); i != range.end(); ++i) {
                        const Int3 p = positions[i];
                        keyed[i] = {spreadBits21(cell(0, p.x)) << 2 |
                                        spreadBits21(cell(1, p.y)) << 1 |
                                        spreadBits21(cell(2, p.z)),
                                    std::uint32_t(i)};
                      }
                    });
  // A counting-sort pass on the top 9 bits (the first 3 levels: 512 buckets, stable, so ties
  // keep index order), then in parallel per bucket more such passes on the next bits (most
  // significant first) while a piece is large, and a comparison sort of the small pieces: less
  // than half the CPU of sorting each bucket by comparisons (13 % of a conversion's CPU).
  constexpr std::size_t kBuckets = std::size_t(1) << kRadixBits;
  constexpr int kTopShift = 3 * kMortonBits - kRadixBits;
  // The first pass in parallel too: a histogram per block of the input, then each block
  // scatters from its own offsets (blocks in input order: still stable).
  const std::size_t blocks = std::clamp<std::size_t>(keyed.size() >> 16, 1, 64);
  const std::size_t block_size = (keyed.size() + blocks - 1) / blocks;
  std::vector<std::array<std::size_t, kBuckets>> at(blocks);
  tbb::parallel_for(std::size_t(0), blocks, [&](std::size_t block) {
    at[block].fill(0);
    const std::size_t end = std::min(keyed.size(), (block + 1) * block_size);
    for (std::size_t i = block * block_size; i < end; ++i)
      ++at[block][std::size_t(keyed[i].key >> kTopShift)];
  });
  std::vector<std::size_t> start(kBuckets + 1, 0);
  for (std::size_t b = 0; b < kBuckets; ++b) {
    std::size_t offset = start[b];
    for (std::size_t block = 0; block < blocks; ++block) {
      const std::size_t count = at[block][b];
      at[block][b] = offset;
      offset += count;
    }
    start[b + 1] = offset;
  }
  std::vector<KeyedPoint> sorted(keyed.size());
  tbb::parallel_for(std::size_t(0), blocks, [&](std::size_t block) {
    const std::size_t end = std::min(keyed.size(), (block + 1) * block_size);
    for (std::size_t i = block * block_size; i < end; ++i)
      sorted[at[block][std::size_t(keyed[i].key >> kTopShift)]++] = keyed[i];
  });
  // `keyed` is the scratch of the second pass: bucket b's range of it is free.
  tbb::parallel_for(std::size_t(0), kBuckets, [&](std::size_t b) {
    sortBucket(std::span(sorted).subspan(start[b], start[b + 1] - start[b]),
               std::span(keyed).subspan(start[b], start[b + 1] - start[b]), kTopShift - kRadixBits);
  });
  return sorted;
}

}  // namespace

void takeSample(std::span<const Int3> positions, const Quantization& quantization,
                const Bounds3& box, double spacing, std::span<std::vector<std::uint32_t>*> children,
                std::vector<std::uint32_t>& node_points, const Sampler& sampler) {
  std::vector<std::uint32_t> candidates;
  std::size_t total = 0;
  for (const auto* child : children) total += child->size();
  candidates.reserve(total);
  for (const auto* child : children)
    candidates.insert(candidates.end(), child->begin(), child->end());
  std::vector<std::uint8_t> taken(candidates.size());
  sampler.sample({.positions = positions,
                  .quantization = quantization,
                  .box = box,
                  .spacing = spacing,
                  .candidates = candidates},
                 taken);
  std::size_t at = 0;
  for (auto* child : children) {
    std::size_t kept = 0;
    for (std::size_t i = 0; i < child->size(); ++i, ++at) {
      if (taken[at]) {
        node_points.push_back(candidates[at]);
      } else {
        (*child)[kept++] = candidates[at];
      }
    }
    child->resize(kept);
  }
}

BuiltSubtree buildSubtree(std::span<const Int3> positions, const Quantization& quantization,
                          const SubtreeFrame& frame, const OctreeBuildOptions& options,
                          const Sampler& sampler) {
  const std::vector<KeyedPoint> sorted = mortonOrder(positions, quantization, frame.box);
  // The build works on the positions in Morton order, and on indices into that order: the
  // samplers then read the positions nearly sequentially (in file order every candidate was a
  // cache miss, 40% of the build's time). `order` maps back to the caller's indices at the end.
  std::vector<Int3> morton_positions(sorted.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, sorted.size(), 1 << 16),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      for (std::size_t i = range.begin(); i != range.end(); ++i)
                        morton_positions[i] = positions[sorted[i].index];
                    });
  const Builder builder(morton_positions, quantization, options, sampler, sorted);
  std::unique_ptr<TreeNode> root = builder.build(0, sorted.size(), 0, frame.box, frame.spacing);

  // Flatten breadth-first: names, levels, and each node's offset in `order`; then every node's
  // points are copied to their place in parallel (it was a serial pass over all the points).
  BuiltSubtree result;
  std::vector<TreeNode*> tree_nodes{root.get()};
  result.nodes.push_back({.name = frame.name, .level = frame.level});
  std::uint64_t placed = 0;
  for (std::size_t index = 0; index < tree_nodes.size(); ++index) {
    TreeNode* tree_node = tree_nodes[index];
    result.nodes[index].first = placed;
    result.nodes[index].count = std::uint32_t(tree_node->points.size());
    placed += tree_node->points.size();
    for (int octant = 0; octant < 8; ++octant) {
      TreeNode* child = tree_node->children[std::size_t(octant)].get();
      if (!child) continue;
      const std::int32_t child_index = std::int32_t(result.nodes.size());
      BuiltNode built{.name = result.nodes[index].name + char('0' + octant),
                      .level = result.nodes[index].level + 1,
                      .parent = std::int32_t(index)};
      result.nodes.push_back(std::move(built));
      BuiltNode& parent = result.nodes[index];  // push_back may have moved it
      parent.child_mask |= std::uint8_t(1u << octant);
      parent.children[std::size_t(octant)] = child_index;
      tree_nodes.push_back(child);
    }
  }
  result.order.resize(placed);
  tbb::parallel_for(std::size_t(0), tree_nodes.size(), [&](std::size_t index) {
    std::vector<std::uint32_t>& points = tree_nodes[index]->points;
    std::uint32_t* out = result.order.data() + result.nodes[index].first;
    for (const std::uint32_t point : points) *out++ = sorted[point].index;
    std::vector<std::uint32_t>().swap(points);
  });
  return result;
}

}  // namespace parallax
