// A frame's draw set with a second one drawn after it: a layer (a raster shown as points,
// raster/raster_layer.h) over a cloud or an octree's selection. The chunks stay their owners';
// the combined set only lists them.
#pragma once

#include "render/draw_set.h"

namespace parallax {

// `base`'s items, then `layer`'s; the bounds of both; colours only where both have them (a
// chunk without a colour section cannot be drawn by a shader that reads one), normals,
// intensity, classes and GPS time as `base` has them where `layer` has them too; the intensity
// quantization and typical spacing are `base`'s (the filters and the sizes are the cloud's).
DrawSet withLayer(const DrawSet& base, const DrawSet& layer);

}  // namespace parallax
