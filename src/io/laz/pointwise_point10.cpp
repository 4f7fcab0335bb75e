// POINT10: the 20 bytes every point format 0-5 starts with (x y z, intensity, the return/flag
// byte, classification, scan angle rank, user data, point source id).
//
// Version 2 (Isenburg 2013, "Compressing the points"): a symbol of six bits says which of the
// non-coordinate fields changed. The return number r and the number of returns n select a
// context m (a point's place in its pulse) and a level l (returns left), because points of the
// same place in their pulses are alike: x and y are predicted by the median of the last five
// differences of the same m, z by the last height of the same l, intensity by the last value of
// the same m. The flag, class and user data bytes are coded with a model per previous value.
// The number of corrector bits of x (and y) chooses the context of y (and z): a large jump in x
// makes one in y likely.
//
// Version 1: x and y predicted by the median of the last three differences, z by the last z,
// the other fields by their last value through integer coders.
#include <cassert>

#include "io/laz/integer_codec.h"
#include "io/laz/pointwise_items.h"
#include "io/laz/pointwise_point10.h"

namespace parallax::laz::pointwise {

// The coders live in the item's namespace (not a using-directive: in a unity batch one would
// reach the other items' sources too).
namespace point10 {
namespace {

class Point10EncoderV2 final : public ItemEncoder {
 public:
  void start(const std::byte* first) override {
    s_.reset(first);
    intensity_.reset();
    source_id_.reset();
    dx_.reset();
    dy_.reset();
    z_.reset();
  }

  void encode(ArithmeticEncoder& enc, const std::byte* item) override {
    Point10 p;
    std::memcpy(&p, item, sizeof p);
    Point10& last = s_.last;
    const unsigned r = p.returnNumber(), n = p.numberOfReturns();
    const unsigned m = kReturnContext[n][r], l = kReturnLevel[n][r];
    const std::uint32_t changed = (last.flags != p.flags ? 32u : 0u) |
                                  (s_.last_intensity[m] != p.intensity ? 16u : 0u) |
                                  (last.classification != p.classification ? 8u : 0u) |
                                  (last.scan_angle_rank != p.scan_angle_rank ? 4u : 0u) |
                                  (last.user_data != p.user_data ? 2u : 0u) |
                                  (last.point_source_id != p.point_source_id ? 1u : 0u);
    enc.encodeSymbol(s_.changed, changed);
    if (changed & 32) enc.encodeSymbol(s_.flags[last.flags], p.flags);
    if (changed & 16) {
      intensity_.encode(enc, s_.last_intensity[m], p.intensity, m < 3 ? m : 3);
      s_.last_intensity[m] = p.intensity;
    }
    if (changed & 8) enc.encodeSymbol(s_.classification[last.classification], p.classification);
    if (changed & 4) {
      enc.encodeSymbol(s_.scan_angle[p.scanDirection()],
                       std::uint8_t(p.scan_angle_rank - last.scan_angle_rank));
    }
    if (changed & 2) enc.encodeSymbol(s_.user_data[last.user_data], p.user_data);
    if (changed & 1) source_id_.encode(enc, last.point_source_id, p.point_source_id);

    const bool single = n == 1;
    std::int32_t diff = wrapSub(p.x, last.x);
    dx_.encode(enc, s_.x_median[m].get(), diff, single ? 1 : 0);
    s_.x_median[m].add(diff);
    diff = wrapSub(p.y, last.y);
    dy_.encode(enc, s_.y_median[m].get(), diff, yContext(dx_.lastK(), single));
    s_.y_median[m].add(diff);
    z_.encode(enc, s_.last_height[l], p.z, zContext((dx_.lastK() + dy_.lastK()) / 2, single));
    s_.last_height[l] = p.z;
    last = p;
  }

 private:
  StateV2<false> s_;
  IntegerEncoder intensity_{kIntensityV2}, source_id_{kSourceId};
  IntegerEncoder dx_{kDxV2}, dy_{kDyV2}, z_{kZV2};
};

// ---------------------------------------------------------------------------------------------
// Version 1.

template <bool kDecoding>
struct StateV1 {
  Point10 last{};
  std::array<std::int32_t, 3> x_diff{}, y_diff{};
  unsigned next_diff = 0;  // which of the three is replaced next
  SymbolModel changed{64, kDecoding};
  ModelsByByte flags{kDecoding}, classification{kDecoding}, user_data{kDecoding};

  void reset(const std::byte* first) {
    std::memcpy(&last, first, sizeof last);
    x_diff.fill(0);
    y_diff.fill(0);
    next_diff = 0;
    changed.reset();
    flags.startChunk();
    classification.startChunk();
    user_data.startChunk();
  }
  void recordDiffs(std::int32_t dx, std::int32_t dy) {
    x_diff[next_diff] = dx;
    y_diff[next_diff] = dy;
    next_diff = next_diff == 2 ? 0 : next_diff + 1;
  }
};

const IntegerCodecShape kDxV1{.bits = 32, .contexts = 1};
const IntegerCodecShape kDyV1{.bits = 32, .contexts = 20};
const IntegerCodecShape kZV1{.bits = 32, .contexts = 20};
const IntegerCodecShape kIntensityV1{.bits = 16, .contexts = 1};
const IntegerCodecShape kScanAngleV1{.bits = 8, .contexts = 2};

class Point10DecoderV1 final : public ItemDecoder {
 public:
  void start(const std::byte* first) override {
    s_.reset(first);
    for (IntegerDecoder* c : {&dx_, &dy_, &z_, &intensity_, &scan_angle_, &source_id_}) c->reset();
  }

  void decode(ArithmeticDecoder& dec, std::byte* out) override {
    Point10& p = s_.last;
    const std::int32_t dx = dx_.decode(dec, medianOf3(s_.x_diff));
    p.x = wrapAdd(p.x, dx);
    std::uint32_t k = dx_.lastK();
    const std::int32_t dy = dy_.decode(dec, medianOf3(s_.y_diff), k < 19 ? k : 19);
    p.y = wrapAdd(p.y, dy);
    k = (k + dy_.lastK()) / 2;
    p.z = z_.decode(dec, p.z, k < 19 ? k : 19);
    const std::uint32_t changed = dec.decodeSymbol(s_.changed);
    if (changed & 32) p.intensity = std::uint16_t(intensity_.decode(dec, p.intensity));
    if (changed & 16) p.flags = std::uint8_t(dec.decodeSymbol(s_.flags[p.flags]));
    if (changed & 8) {
      p.classification = std::uint8_t(dec.decodeSymbol(s_.classification[p.classification]));
    }
    if (changed & 4) {
      p.scan_angle_rank = std::uint8_t(scan_angle_.decode(dec, p.scan_angle_rank, k < 3 ? 1 : 0));
    }
    if (changed & 2) p.user_data = std::uint8_t(dec.decodeSymbol(s_.user_data[p.user_data]));
    if (changed & 1) p.point_source_id = std::uint16_t(source_id_.decode(dec, p.point_source_id));
    s_.recordDiffs(dx, dy);
    std::memcpy(out, &p, sizeof p);
  }

 private:
  StateV1<true> s_;
  IntegerDecoder dx_{kDxV1}, dy_{kDyV1}, z_{kZV1};
  IntegerDecoder intensity_{kIntensityV1}, scan_angle_{kScanAngleV1}, source_id_{kSourceId};
};

class Point10EncoderV1 final : public ItemEncoder {
 public:
  void start(const std::byte* first) override {
    s_.reset(first);
    for (IntegerEncoder* c : {&dx_, &dy_, &z_, &intensity_, &scan_angle_, &source_id_}) c->reset();
  }

  void encode(ArithmeticEncoder& enc, const std::byte* item) override {
    Point10 p;
    std::memcpy(&p, item, sizeof p);
    Point10& last = s_.last;
    const std::int32_t dx = wrapSub(p.x, last.x), dy = wrapSub(p.y, last.y);
    dx_.encode(enc, medianOf3(s_.x_diff), dx);
    std::uint32_t k = dx_.lastK();
    dy_.encode(enc, medianOf3(s_.y_diff), dy, k < 19 ? k : 19);
    k = (k + dy_.lastK()) / 2;
    z_.encode(enc, last.z, p.z, k < 19 ? k : 19);
    const std::uint32_t changed = (last.intensity != p.intensity ? 32u : 0u) |
                                  (last.flags != p.flags ? 16u : 0u) |
                                  (last.classification != p.classification ? 8u : 0u) |
                                  (last.scan_angle_rank != p.scan_angle_rank ? 4u : 0u) |
                                  (last.user_data != p.user_data ? 2u : 0u) |
                                  (last.point_source_id != p.point_source_id ? 1u : 0u);
    enc.encodeSymbol(s_.changed, changed);
    if (changed & 32) intensity_.encode(enc, last.intensity, p.intensity);
    if (changed & 16) enc.encodeSymbol(s_.flags[last.flags], p.flags);
    if (changed & 8) enc.encodeSymbol(s_.classification[last.classification], p.classification);
    if (changed & 4) {
      scan_angle_.encode(enc, last.scan_angle_rank, p.scan_angle_rank, k < 3 ? 1 : 0);
    }
    if (changed & 2) enc.encodeSymbol(s_.user_data[last.user_data], p.user_data);
    if (changed & 1) source_id_.encode(enc, last.point_source_id, p.point_source_id);
    s_.recordDiffs(dx, dy);
    last = p;
  }

 private:
  StateV1<false> s_;
  IntegerEncoder dx_{kDxV1}, dy_{kDyV1}, z_{kZV1};
  IntegerEncoder intensity_{kIntensityV1}, scan_angle_{kScanAngleV1}, source_id_{kSourceId};
};

}  // namespace
}  // namespace point10

std::unique_ptr<ItemDecoder> makePoint10Decoder(int version) {
  assert((version == 1 || version == 2) && "POINT10 has versions 1 and 2");
  if (version == 1) return std::make_unique<point10::Point10DecoderV1>();
  return std::make_unique<point10::Point10DecoderV2>();
}

std::unique_ptr<ItemEncoder> makePoint10Encoder(int version) {
  assert((version == 1 || version == 2) && "POINT10 has versions 1 and 2");
  if (version == 1) return std::make_unique<point10::Point10EncoderV1>();
  return std::make_unique<point10::Point10EncoderV2>();
}

}  // namespace parallax::laz::pointwise
