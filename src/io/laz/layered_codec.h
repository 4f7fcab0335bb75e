// The layered chunk codec (compressor 3) of point formats 6-10: items POINT14, RGB14, RGBNIR14,
// WAVEPACKET14 and BYTE14, versions 3 and 4. See chunk_codec.h for the chunk layout.
#pragma once

#include <memory>
#include <span>

#include "io/laz/chunk_codec.h"

namespace parallax::laz {

// Throw UnsupportedItems for an item list the layered codec cannot code.
//
// The decoder's ChunkCorrupt names the first point affected: 0 when the chunk cannot hold its
// first (raw) record; its own point count when it holds fewer points than expected; 1 (the first
// point the chunk's header governs) when it holds more or its layer sizes are wrong; else the point
// at which a layer stream ran past its bytes or held an impossible value; the records before that
// point are decoded and valid. Item versions: see layered_items.h.
// The specialised path decodes POINT14 over the whole chunk, then each other item over the whole
// chunk through its concrete type; the general one point by point, item by item.
std::unique_ptr<ChunkDecoder> makeLayeredDecoder(std::span<const LazItem> items,
                                                 DecoderPath path = DecoderPath::kSpecialised);
std::unique_ptr<ChunkEncoder> makeLayeredEncoder(std::span<const LazItem> items);

}  // namespace parallax::laz
