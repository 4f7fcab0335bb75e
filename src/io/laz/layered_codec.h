// The layered chunk codec (compressor 3) of point formats 6-10: items POINT14, RGB14, RGBNIR14,
// WAVEPACKET14 and BYTE14, versions 3 and 4. See chunk_codec.h for the chunk layout.
#pragma once

#include <memory>
#include <span>

#include "io/laz/chunk_codec.h"

namespace parallax::laz {

// Throw UnsupportedItems for an item list the layered codec cannot code.
std::unique_ptr<ChunkDecoder> makeLayeredDecoder(std::span<const LazItem> items);
std::unique_ptr<ChunkEncoder> makeLayeredEncoder(std::span<const LazItem> items);

}  // namespace parallax::laz
