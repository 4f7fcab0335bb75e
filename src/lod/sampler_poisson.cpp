// Poisson-disk sampling in a cell grid (sampler.h).
//
// PotreeConverter sorts candidates by distance to the node's centre and tests each against the
// kept points within a sliding window of that order; a grid whose cells are no smaller than the
// spacing bounds the test to the 27 cells around the candidate instead, and the candidate's own
// cell is looked at first because in dense regions it rejects most candidates at once.
#include <array>
#include <cstdint>
#include <vector>

#include "lod/sampler.h"
#include "lod/sampler_grid.h"

namespace parallax {
namespace {

using sampler_detail::CellGrid;

// A kept point and the next kept point of its cell (-1 at the end): one cache line per look.
struct KeptPoint {
  double x, y, z;
  std::int32_t next;
};

struct PoissonScratch {
  CellGrid grid;
  std::vector<KeptPoint> kept;  // local coordinates (world minus the box minimum)
};

struct Offset {
  int x, y, z;
};

// The 26 neighbouring cells, faces first, then edges, then corners: the nearer cells are the
// likelier to reject a candidate, so they are looked at first.
constexpr std::array<Offset, 26> neighbourOffsets() {
  std::array<Offset, 26> offsets{};
  std::size_t n = 0;
  for (int manhattan = 1; manhattan <= 3; ++manhattan) {
    for (int x = -1; x <= 1; ++x)
      for (int y = -1; y <= 1; ++y)
        for (int z = -1; z <= 1; ++z)
          if ((x != 0) + (y != 0) + (z != 0) == manhattan) offsets[n++] = {x, y, z};
  }
  return offsets;
}
constexpr std::array<Offset, 26> kNeighbours = neighbourOffsets();

class PoissonSampler final : public Sampler {
 public:
  void sample(const SampleRequest& request, std::span<std::uint8_t> taken) const override {
    thread_local PoissonScratch scratch;
    CellGrid& grid = scratch.grid;
    grid.reset(request.box, request.spacing);
    scratch.kept.clear();
    const double min_distance2 = request.spacing * request.spacing;
    const Quantization& q = request.quantization;
    const int cells = grid.cells();
    const double cell_size = grid.cellSize();

    for (std::size_t i = 0; i < request.candidates.size(); ++i) {
      const Int3 p = request.positions[request.candidates[i]];
      const double local[3] = {q.toWorld(0, p.x) - request.box.min[0],
                               q.toWorld(1, p.y) - request.box.min[1],
                               q.toWorld(2, p.z) - request.box.min[2]};
      const int c[3] = {grid.cellOf(local[0]), grid.cellOf(local[1]), grid.cellOf(local[2])};
      auto conflictsIn = [&](std::size_t cell) {
        for (std::int32_t k = grid.head(cell); k >= 0; k = scratch.kept[std::size_t(k)].next) {
          const KeptPoint& other = scratch.kept[std::size_t(k)];
          const double dx = other.x - local[0], dy = other.y - local[1], dz = other.z - local[2];
          if (dx * dx + dy * dy + dz * dz < min_distance2) return true;
        }
        return false;
      };
      const std::size_t own = grid.index(c[0], c[1], c[2]);
      bool reject = conflictsIn(own);
      if (!reject) {
        // The squared gap between the candidate and the neighbouring cells along each axis: a
        // neighbour whose nearest point is a spacing or more away is skipped (about a quarter
        // of the 26: edge and corner cells, mostly).
        double gap2[3][3];
        for (int axis = 0; axis < 3; ++axis) {
          const double below = local[axis] - c[axis] * cell_size;
          const double above = cell_size - below;
          gap2[axis][0] = below * below;
          gap2[axis][1] = 0.0;
          gap2[axis][2] = above * above;
        }
        for (const Offset& o : kNeighbours) {
          const int x = c[0] + o.x, y = c[1] + o.y, z = c[2] + o.z;
          if (x < 0 || y < 0 || z < 0 || x >= cells || y >= cells || z >= cells) continue;
          if (gap2[0][o.x + 1] + gap2[1][o.y + 1] + gap2[2][o.z + 1] >= min_distance2) continue;
          if (conflictsIn(grid.index(x, y, z))) {
            reject = true;
            break;
          }
        }
      }
      taken[i] = reject ? 0 : 1;
      if (reject) continue;
      scratch.kept.push_back({local[0], local[1], local[2], grid.head(own)});
      grid.setHead(own, std::int32_t(scratch.kept.size() - 1));
    }
  }
};

}  // namespace

std::unique_ptr<Sampler> makePoissonSampler() {
  return std::make_unique<PoissonSampler>();
}

std::unique_ptr<Sampler> makeSampler(SamplingMethod method) {
  return method == SamplingMethod::Poisson ? makePoissonSampler() : makeRandomSampler();
}

}  // namespace parallax
