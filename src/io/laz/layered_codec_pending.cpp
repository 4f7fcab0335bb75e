// Placeholder until the layered codec (compressor 3) is merged: the factories exist so that
// everything links, and say what is missing. Deleted at the merge of the layered codec.
#include "io/laz/layered_codec.h"

namespace parallax::laz {

std::unique_ptr<ChunkDecoder> makeLayeredDecoder(std::span<const LazItem>) {
  throw UnsupportedItems("layered LAZ (point formats 6-10) is being written");
}

std::unique_ptr<ChunkEncoder> makeLayeredEncoder(std::span<const LazItem>) {
  throw UnsupportedItems("layered LAZ (point formats 6-10) is being written");
}

}  // namespace parallax::laz
