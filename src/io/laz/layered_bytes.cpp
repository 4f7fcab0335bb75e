// BYTE14, versions 3 and 4: the "extra bytes" of point formats 6-10, one layer per byte, each
// coded as its difference (mod 256) from the same byte of the channel's last point.
//
// Memory: one 256-symbol model per byte and channel. The decoder creates a byte's model only when
// its layer is present in a chunk, so what a hostile chunk can make it allocate grows with the
// chunk's own size (and is bounded by the item size, at most 65 535 bytes, times four channels).
#include <cassert>

#include "io/laz/layered_items.h"

namespace parallax::laz::layered {

namespace {

class BytesState {
 protected:
  BytesState(std::size_t count, unsigned version, bool for_decoding)
      : count_(count), version_(version), for_decoding_(for_decoding) {
    for (auto& last : last_) last.resize(count);
  }
  void startChunk(const std::byte* first, unsigned context) {
    used_.fill(false);
    current_ = context;
    startContext(context, reinterpret_cast<const std::uint8_t*>(first));
  }
  void startContext(unsigned context, const std::uint8_t* seed) {
    std::vector<std::uint8_t>& last = last_[context];
    if (seed != last.data()) std::copy(seed, seed + count_, last.begin());
    // Models are reset when first used in this context (see model()).
    fresh_[context].assign(count_, false);
    used_[context] = true;
  }
  unsigned enter(unsigned context) {
    const ContextSwitch s = switchContext(current_, context, used_, version_);
    if (s.start_new) startContext(s.models, last_[current_].data());
    current_ = s.models;
    return s.last;
  }
  SymbolModel& model(std::size_t i) {
    std::vector<std::unique_ptr<SymbolModel>>& models = models_[current_];
    if (models.empty()) models.resize(count_);
    if (!fresh_[current_][i]) {
      if (!models[i]) {
        models[i] = std::make_unique<SymbolModel>(256, for_decoding_);
      } else {
        models[i]->reset();
      }
      fresh_[current_][i] = true;
    }
    return *models[i];
  }

  std::size_t count_;
  unsigned version_;
  bool for_decoding_;
  std::array<std::vector<std::unique_ptr<SymbolModel>>, kChannels> models_;
  std::array<std::vector<bool>, kChannels> fresh_;
  std::array<std::vector<std::uint8_t>, kChannels> last_;
  std::array<bool, kChannels> used_{};
  unsigned current_ = 0;
};

class BytesDecoder final : public ItemDecoder, BytesState {
 public:
  BytesDecoder(std::size_t count, unsigned version)
      : BytesState(count, version, true), dec_(count), present_(count) {}
  std::size_t size() const override { return count_; }
  std::size_t layerCount() const override { return count_; }
  void start(const std::byte* first, std::span<const std::span<const std::byte>> layers,
             unsigned context) override {
    assert(layers.size() == count_ && "one layer per extra byte");
    for (std::size_t i = 0; i < count_; ++i) {
      present_[i] = !layers[i].empty();
      dec_[i].start(layers[i]);
    }
    startChunk(first, context);
  }
  LayerFailure failure() const override {
    for (std::size_t i = 0; i < count_; ++i) {
      if (LayerFailure f = checkLayer(dec_[i], present_[i], i)) return f;
    }
    return {};
  }
  std::size_t decodeRun(std::byte* item, std::size_t count, std::size_t stride,
                        const std::uint8_t* contexts) override {
    return decodeRunOf(*this, item, count, stride, contexts);
  }

  void decode(std::byte* item, unsigned context) override {
    std::uint8_t* last = last_[enter(context)].data();
    for (std::size_t i = 0; i < count_; ++i) {
      if (present_[i]) last[i] = std::uint8_t(last[i] + dec_[i].decodeSymbol(model(i)));
      item[i] = std::byte(last[i]);
    }
  }

 private:
  std::vector<ArithmeticDecoder> dec_;
  std::vector<bool> present_;
};

class BytesEncoder final : public ItemEncoder, BytesState {
 public:
  BytesEncoder(std::size_t count, unsigned version)
      : BytesState(count, version, false), layers_(count), changed_(count) {}
  std::size_t size() const override { return count_; }
  std::size_t layerCount() const override { return count_; }
  void start(const std::byte* first, unsigned context) override {
    for (LayerStream& l : layers_) l.restart();
    changed_.assign(count_, false);
    startChunk(first, context);
  }
  void finish() override {
    for (LayerStream& l : layers_) l.finish();
  }
  std::span<const std::uint8_t> layer(std::size_t i) const override {
    return changed_[i] ? std::span<const std::uint8_t>(layers_[i].bytes)
                       : std::span<const std::uint8_t>{};
  }
  void encode(const std::byte* item, unsigned context) override {
    std::uint8_t* last = last_[enter(context)].data();
    for (std::size_t i = 0; i < count_; ++i) {
      const auto value = std::uint8_t(item[i]);
      layers_[i].encoder.encodeSymbol(model(i), std::uint8_t(value - last[i]));
      if (value != last[i]) {
        changed_[i] = true;
        last[i] = value;
      }
    }
  }

 private:
  std::vector<LayerStream> layers_;
  std::vector<bool> changed_;
};

}  // namespace

std::unique_ptr<ItemDecoder> makeBytesDecoder(std::size_t count, unsigned version) {
  return std::make_unique<BytesDecoder>(count, version);
}
std::unique_ptr<ItemEncoder> makeBytesEncoder(std::size_t count, unsigned version) {
  return std::make_unique<BytesEncoder>(count, version);
}

}  // namespace parallax::laz::layered
