// The item codecs of LASzip's layered chunks (compressor 3), as the chunk layout
// (layered_chunk.cpp) drives them. Internal to the LAZ codec; see layered_codec.h for the public
// entry points and chunk_codec.h for the chunk layout.
//
// Every item codes its part of each record in one or more layers, each an arithmetic stream of its
// own. A chunk starts every item from the chunk's first record (stored raw); the items then code
// points 1..n-1. An item whose layer did not change over the whole chunk leaves that layer empty,
// and its decoder repeats the last value.
//
// Scanner channels. POINT14 keeps one set of models and one "last point" per scanner channel
// (0-3), and tells the items after it which channel context to use for each point. How it tells
// them is the one difference between versions 3 and 4 of the layered items (LASzip 3.x,
// lasreaditemcompressed_v3.cpp and _v4.cpp, whose change history dates the fix to December 2017):
//   - version 4: the context is the point's scanner channel;
//   - version 3: the context is the new channel on a point where the channel changes, and 0 on
//     every other point (LASzip's point reader starts each point with context 0 and the v3
//     POINT14 codec only overwrites it on a change). Files with one scanner channel other than 0
//     see their item contexts move to 0 after the first point.
// And in each item after POINT14: on a switch to a context already used in this chunk, version 4
// predicts from that context's last value; version 3 keeps predicting (for that one point) from
// the previous context's last value and stores the point's value there. Both are reproduced
// exactly, because a stream decodes only with the writer's contexts.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <memory>
#include <span>
#include <utility>
#include <vector>

#include "io/laz/arithmetic_decoder.h"
#include "io/laz/arithmetic_encoder.h"
#include "io/laz/arithmetic_models.h"
#include "io/laz/chunk_codec.h"

namespace parallax::laz::layered {

inline constexpr unsigned kChannels = 4;  // scanner channels: 2 bits in the record

// Little-endian loads and stores of record fields (LAS is little endian; the project assumes a
// little-endian host, see las_header.h).
template <class T>
inline T loadLE(const std::byte* p) {
  T v;
  std::memcpy(&v, p, sizeof(T));
  return v;
}
template <class T>
inline void storeLE(std::byte* p, T v) {
  std::memcpy(p, &v, sizeof(T));
}

// A model (or integer codec) reset when first used after its context (re)started rather than
// when the context starts: the state it codes with is the same, and a chunk pays only for the
// models it uses. (COPC files can hold chunks of a few points, where resetting every model of
// every item would cost more than decoding.)
template <class T>
class Lazy {
 public:
  template <class... Args>
  explicit Lazy(Args&&... args) : value_(std::forward<Args>(args)...) {}
  void reset() { fresh_ = false; }
  T& operator*() {
    if (!fresh_) {
      value_.reset();
      fresh_ = true;
    }
    return value_;
  }
  T* operator->() { return &**this; }

 private:
  T value_;
  bool fresh_ = false;
};

// Symbol models created on first use in a context, as LASzip creates them lazily: a model is
// fresh (just reset) when first used after its context was (re)started, whatever it learned in an
// earlier chunk. Allocations persist across chunks; reset() only marks them stale.
template <unsigned N>
class LazySymbolModels {
  static_assert(N <= 64, "one bit per model in a 64-bit mask");

 public:
  LazySymbolModels(std::uint32_t symbols, bool for_decoding)
      : symbols_(symbols), for_decoding_(for_decoding) {}
  void reset() { fresh_ = 0; }
  SymbolModel& operator[](unsigned i) {
    const std::uint64_t bit = std::uint64_t(1) << i;
    if ((fresh_ & bit) == 0) {
      if (!models_[i]) {
        models_[i] = std::make_unique<SymbolModel>(symbols_, for_decoding_);
      } else {
        models_[i]->reset();
      }
      fresh_ |= bit;
    }
    return *models_[i];
  }

 private:
  std::array<std::unique_ptr<SymbolModel>, N> models_;
  std::uint64_t fresh_ = 0;
  std::uint32_t symbols_;
  bool for_decoding_;
};

// Which context an item after POINT14 codes a point with, after the POINT14 codec handed it
// `context` for this point (see the version note at the top). `current` is the item's context
// before this point; `used` says which contexts the chunk has started so far.
struct ContextSwitch {
  unsigned models;  // the context whose models code this point (the item's new current context)
  unsigned last;    // the context whose last value predicts the point and takes its value
  bool start_new;   // `models` starts now: seed its last value from context `current`'s first
};
inline ContextSwitch switchContext(unsigned current, unsigned context,
                                   const std::array<bool, kChannels>& used, unsigned version) {
  if (context == current) return {current, current, false};
  if (!used[context]) return {context, context, true};
  return {context, version >= 4 ? context : current, false};
}

// A layer whose stream ran past its bytes (`overran`) or held an impossible value.
struct LayerFailure {
  int layer = -1;  // -1: none
  bool overran = false;
  explicit operator bool() const { return layer >= 0; }
};
inline LayerFailure checkLayer(const ArithmeticDecoder& dec, bool present, std::size_t layer) {
  if (!present || dec.ok()) return {};
  return {int(layer), dec.overran()};
}

// Decodes one item (not POINT14) of each record.
class ItemDecoder {
 public:
  virtual ~ItemDecoder() = default;
  virtual std::size_t size() const = 0;        // bytes of the item in a record
  virtual std::size_t layerCount() const = 0;  // layers of the item in a chunk
  // Starts a chunk: `first` is the item in the chunk's first record, `layers` the item's layers
  // (layerCount() of them, each possibly empty), `context` the first record's channel.
  virtual void start(const std::byte* first, std::span<const std::span<const std::byte>> layers,
                     unsigned context) = 0;
  virtual void decode(std::byte* item, unsigned context) = 0;
  // The chunk's fast path: decodes the item of `count` records `stride` bytes apart, starting at
  // `item`, record i with context contexts[i]. An item's layers are streams of their own, so the
  // chunk decodes one item at a time over all its points, each item's models staying in cache,
  // with no virtual call per point. Returns `count`, or fewer when a layer was found broken (it
  // is checked every kCheckInterval records, so that a broken chunk claiming many points stops
  // early; the caller then decodes again point by point to name the first point affected).
  virtual std::size_t decodeRun(std::byte* item, std::size_t count, std::size_t stride,
                                const std::uint8_t* contexts) = 0;
  // The first layer whose stream ran past its bytes or held an impossible value, if any.
  virtual LayerFailure failure() const = 0;
};

inline constexpr std::size_t kCheckInterval = 1024;

// decodeRun for a final decoder class: its decode() is called directly (and inlined).
template <class Decoder>
std::size_t decodeRunOf(Decoder& decoder, std::byte* item, std::size_t count, std::size_t stride,
                        const std::uint8_t* contexts) {
  for (std::size_t i = 0; i < count; ++i, item += stride) {
    decoder.Decoder::decode(item, contexts[i]);
    if ((i + 1) % kCheckInterval == 0 && decoder.failure()) return i + 1;
  }
  return count;
}

// Encodes one item (not POINT14) of each record.
class ItemEncoder {
 public:
  virtual ~ItemEncoder() = default;
  virtual std::size_t size() const = 0;
  virtual std::size_t layerCount() const = 0;
  virtual void start(const std::byte* first, unsigned context) = 0;
  virtual void encode(const std::byte* item, unsigned context) = 0;
  // Ends the chunk's streams; layer(i) is then the bytes of layer i as the chunk stores them
  // (empty for a layer whose values never changed).
  virtual void finish() = 0;
  virtual std::span<const std::uint8_t> layer(std::size_t i) const = 0;
};

std::unique_ptr<ItemDecoder> makeRgbDecoder(bool nir, unsigned version);
std::unique_ptr<ItemEncoder> makeRgbEncoder(bool nir, unsigned version);
std::unique_ptr<ItemDecoder> makeWavepacketDecoder(unsigned version);
std::unique_ptr<ItemEncoder> makeWavepacketEncoder(unsigned version);
std::unique_ptr<ItemDecoder> makeBytesDecoder(std::size_t count, unsigned version);
std::unique_ptr<ItemEncoder> makeBytesEncoder(std::size_t count, unsigned version);

// One layer's encoder: its bytes and the arithmetic encoder writing them, restarted per chunk.
struct LayerStream {
  std::vector<std::uint8_t> bytes;
  ArithmeticEncoder encoder{bytes};
  bool finished = false;

  LayerStream() = default;
  LayerStream(const LayerStream&) = delete;
  LayerStream& operator=(const LayerStream&) = delete;
  void restart() {
    bytes.clear();
    encoder = ArithmeticEncoder(bytes);
    finished = false;
  }
  void finish() {
    if (!finished) encoder.finish();
    finished = true;
  }
};

}  // namespace parallax::laz::layered
