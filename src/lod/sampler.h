// Sampling strategies: which points an inner node keeps from the points of its children.
//
// The octree is built bottom-up (subtree_builder.h): once a node's children hold their points,
// the node takes a subsample of them spaced by its own spacing, and the children keep the rest.
// A sampler only decides which candidates are taken; moving them is the builder's job.
#pragma once

#include <cstdint>
#include <memory>
#include <span>

#include "core/bounds.h"
#include "core/point_cloud.h"
#include "core/quantization.h"
#include "lod/octree_build_options.h"

namespace parallax {

struct SampleRequest {
  std::span<const Int3> positions;            // quantized positions that `candidates` index
  Quantization quantization;                  // of `positions`
  Bounds3 box;                                // the node's cube, world units
  double spacing = 0.0;                       // the node's spacing, world units (> 0)
  std::span<const std::uint32_t> candidates;  // the children's points, in the order to consider
};

class Sampler {
 public:
  virtual ~Sampler() = default;
  // Sets taken[i] to 1 when the node keeps candidates[i], to 0 otherwise (taken.size() equals
  // candidates.size()). Thread-safe: one sampler serves all worker threads.
  virtual void sample(const SampleRequest& request, std::span<std::uint8_t> taken) const = 0;
};

// The Poisson-disk sampler: candidates in the given order, each kept when no kept point lies
// closer than the spacing (Euclidean, world units), checked in a grid of cells no smaller than
// the spacing, so only the 27 cells around a candidate need looking at.
std::unique_ptr<Sampler> makePoissonSampler();

// The grid sampler: the first candidate to fall in each cell of edge `spacing` is kept.
std::unique_ptr<Sampler> makeRandomSampler();

std::unique_ptr<Sampler> makeSampler(SamplingMethod method);

}  // namespace parallax
