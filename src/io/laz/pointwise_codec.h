// The point-wise chunk codec (compressors 1 and 2) of point formats 0-5: items POINT10,
// GPSTIME11, RGB12, WAVEPACKET13 and BYTE, versions 1 and 2. See chunk_codec.h for the chunk
// layout.
#pragma once

#include <memory>
#include <span>

#include "io/laz/chunk_codec.h"

namespace parallax::laz {

// Throw UnsupportedItems for an item list the point-wise codec cannot code.
// The decoder is specialised for POINT10 with GPSTIME11 and/or RGB12, all version 2 (formats
// 0-3), unless `path` asks for the general one (the tests compare the two).
std::unique_ptr<ChunkDecoder> makePointwiseDecoder(std::span<const LazItem> items,
                                                   DecoderPath path = DecoderPath::kSpecialised);
std::unique_ptr<ChunkEncoder> makePointwiseEncoder(std::span<const LazItem> items);

}  // namespace parallax::laz
