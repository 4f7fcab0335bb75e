// The grid sampler (sampler.h): one point per cell, no distance test.
//
// PotreeConverter's "random" sampler also keeps one point per cell of a 128^3 grid. Here the
// kept point is the first candidate in the builder's order (Morton order inside each child), so
// no random numbers are drawn and the result is deterministic; the price is a slight bias of each
// kept point towards its cell's low corner, invisible at the spacing it is drawn at.
#include <cstdint>

#include "lod/sampler.h"
#include "lod/sampler_grid.h"

namespace parallax {
namespace {

using sampler_detail::CellGrid;

class RandomSampler final : public Sampler {
 public:
  void sample(const SampleRequest& request, std::span<std::uint8_t> taken) const override {
    thread_local CellGrid grid;
    // Cells of exactly the spacing where the grid allows it (a coarser grid keeps fewer points).
    grid.reset(request.box, request.spacing);
    const Quantization& q = request.quantization;
    for (std::size_t i = 0; i < request.candidates.size(); ++i) {
      const Int3 p = request.positions[request.candidates[i]];
      const std::size_t cell = grid.index(grid.cellOf(q.toWorld(0, p.x) - request.box.min[0]),
                                          grid.cellOf(q.toWorld(1, p.y) - request.box.min[1]),
                                          grid.cellOf(q.toWorld(2, p.z) - request.box.min[2]));
      const bool empty = grid.head(cell) < 0;
      taken[i] = empty ? 1 : 0;
      if (empty) grid.setHead(cell, 0);
    }
  }
};

}  // namespace

std::unique_ptr<Sampler> makeRandomSampler() {
  return std::make_unique<RandomSampler>();
}

}  // namespace parallax
