// The items of the point-wise codec (compressors 1 and 2), one coder per item and direction.
// Internal to io/laz: the chunk codec (pointwise_codec.cpp) strings them together in record
// order. Each coder owns its models and its "last item" state; `start` resets both from the
// chunk's first (raw) record, so every chunk decodes on its own.
//
// What each item codes is the format's (Isenburg, "LASzip: lossless compression of LiDAR data",
// PE&RS 79(2), 2013, and the LAZ specification's item list): the contexts, the predictions and the
// moments at which models are created and updated must match LASzip's exactly, or the stream does
// not decode. The comments in the item files say which field predicts which.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <memory>

#include "core/byte_order.h"
#include "io/laz/arithmetic_decoder.h"
#include "io/laz/arithmetic_encoder.h"
#include "io/laz/arithmetic_models.h"
#include "io/laz/wrapping_int32.h"

namespace parallax::laz::pointwise {

class ItemDecoder {
 public:
  virtual ~ItemDecoder() = default;
  // The chunk's first record's bytes of this item (read raw) start the context.
  virtual void start(const std::byte* first) = 0;
  // Decodes the next item into `out` (the item's size in bytes).
  virtual void decode(ArithmeticDecoder& dec, std::byte* out) = 0;
};

class ItemEncoder {
 public:
  virtual ~ItemEncoder() = default;
  virtual void start(const std::byte* first) = 0;
  virtual void encode(ArithmeticEncoder& enc, const std::byte* item) = 0;
};

// Versions: 1 or 2 (WAVEPACKET13: 1). The factories assert on others (the codec checks first).
std::unique_ptr<ItemDecoder> makePoint10Decoder(int version);
std::unique_ptr<ItemEncoder> makePoint10Encoder(int version);
std::unique_ptr<ItemDecoder> makeGpsTimeDecoder(int version);
std::unique_ptr<ItemEncoder> makeGpsTimeEncoder(int version);
std::unique_ptr<ItemDecoder> makeRgbDecoder(int version);
std::unique_ptr<ItemEncoder> makeRgbEncoder(int version);
std::unique_ptr<ItemDecoder> makeBytesDecoder(int version, std::size_t count);
std::unique_ptr<ItemEncoder> makeBytesEncoder(int version, std::size_t count);
std::unique_ptr<ItemDecoder> makeWavepacketDecoder();
std::unique_ptr<ItemEncoder> makeWavepacketEncoder();

// ---------------------------------------------------------------------------------------------
// Helpers shared by the items (and wrapping_int32.h).

// A 256-symbol model per value of a context byte (the last class, user data or flag byte),
// created the first time its context occurs: most files use a handful of them. A model's reset
// for a new chunk happens at its first use in that chunk, which leaves it in the state LASzip's
// reset of every existing model at the chunk start gives.
class ModelsByByte {
 public:
  explicit ModelsByByte(bool for_decoding) : for_decoding_(for_decoding) {}
  void startChunk() { ++chunk_; }
  SymbolModel& operator[](std::uint8_t context) {
    std::unique_ptr<SymbolModel>& model = models_[context];
    if (!model) {
      model = std::make_unique<SymbolModel>(256, for_decoding_);
    } else if (chunk_of_[context] != chunk_) {
      model->reset();
    }
    chunk_of_[context] = chunk_;
    return *model;
  }

 private:
  bool for_decoding_;
  std::uint32_t chunk_ = 0;
  std::array<std::unique_ptr<SymbolModel>, 256> models_{};
  std::array<std::uint32_t, 256> chunk_of_{};
};

}  // namespace parallax::laz::pointwise
