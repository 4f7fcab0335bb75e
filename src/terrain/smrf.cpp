// SMRF (smrf.h): the progressive opening of the minimum surface and the final test.
#include "terrain/smrf.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "terrain/morphology.h"

namespace parallax {

SmrfSurface smrfSurface(ElevationGrid minimum, const SmrfParameters& parameters) {
  SmrfSurface out;
  const std::vector<double> measured = minimum.values();  // before filling: NaN where empty
  minimum.fillEmpty();
  if (minimum.cells() == 0 || ElevationGrid::empty(minimum.values()[0])) return out;

  // Pingel et al. 2013, section 2.2: open with a window of radius 1, 2, ... cells; a cell the
  // opening of radius r lowers (against radius r - 1) by more than slope * r * cell is an object.
  std::vector<std::uint8_t> object(minimum.cells(), 0);
  const std::size_t radius =
      std::size_t(std::max(1.0, std::ceil(parameters.window / parameters.cell)));
  ElevationGrid last = minimum;
  for (std::size_t r = 1; r <= radius; ++r) {
    ElevationGrid opened = open(last, r);
    const double height = parameters.slope * double(r) * parameters.cell;
    for (std::size_t c = 0; c < object.size(); ++c) {
      if (last.values()[c] - opened.values()[c] > height) object[c] = 1;
    }
    last = std::move(opened);
  }

  // The provisional ground: the measured minimum where it is not an object, filled elsewhere.
  out.ground =
      ElevationGrid(minimum.x0(), minimum.y0(), minimum.cell(), minimum.nx(), minimum.ny());
  for (std::size_t c = 0; c < object.size(); ++c) {
    out.object_cells += object[c];
    out.ground.values()[c] = object[c] ? ElevationGrid::kEmpty : measured[c];
  }
  out.ground.fillEmpty();
  if (ElevationGrid::empty(out.ground.values()[0])) {
    // Every measured cell an object: nothing to stand on; keep the minimum surface.
    out.ground = minimum;
  }
  out.slope = out.ground.slope();
  return out;
}

bool smrfIsGround(const SmrfSurface& surface, const SmrfParameters& parameters, double x, double y,
                  double z) {
  if (surface.ground.cells() == 0) return false;
  const double allowed = parameters.threshold + parameters.scalar * surface.slope.sample(x, y);
  return std::abs(z - surface.ground.sample(x, y)) <= allowed;
}

}  // namespace parallax
