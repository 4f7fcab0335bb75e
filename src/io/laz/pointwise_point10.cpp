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

namespace parallax::laz::pointwise {
namespace {

struct Point10 {
  std::int32_t x, y, z;
  std::uint16_t intensity;
  std::uint8_t flags;  // return number (3 bits), number of returns (3), scan direction, edge
  std::uint8_t classification;
  std::uint8_t scan_angle_rank;
  std::uint8_t user_data;
  std::uint16_t point_source_id;

  unsigned returnNumber() const { return flags & 7u; }
  unsigned numberOfReturns() const { return (flags >> 3) & 7u; }
  unsigned scanDirection() const { return (flags >> 6) & 1u; }
};
static_assert(sizeof(Point10) == 20, "Point10 mirrors the 20-byte record prefix");

// The context m of a point by (number of returns n, return number r). Valid pairs (1 <= r <= n
// <= 5) map to 0-14 in order of n then r; the other cells spread malformed combinations (r or n
// zero, r > n) over distinct contexts instead of mixing them with valid ones. These tables are
// part of the format: the contexts decide which model codes which point.
constexpr std::uint8_t kReturnContext[8][8] = {
    {15, 14, 13, 12, 11, 10, 9, 8},  {14, 0, 1, 3, 6, 10, 10, 9},
    {13, 1, 2, 4, 7, 11, 11, 10},    {12, 3, 4, 5, 8, 12, 12, 11},
    {11, 6, 7, 8, 9, 13, 13, 12},    {10, 10, 11, 12, 13, 14, 14, 13},
    {9, 10, 11, 12, 13, 14, 15, 14}, {8, 9, 10, 11, 12, 13, 14, 15},
};
// The level l: |n - r|, the returns still to come.
constexpr std::uint8_t kReturnLevel[8][8] = {
    {0, 1, 2, 3, 4, 5, 6, 7}, {1, 0, 1, 2, 3, 4, 5, 6}, {2, 1, 0, 1, 2, 3, 4, 5},
    {3, 2, 1, 0, 1, 2, 3, 4}, {4, 3, 2, 1, 0, 1, 2, 3}, {5, 4, 3, 2, 1, 0, 1, 2},
    {6, 5, 4, 3, 2, 1, 0, 1}, {7, 6, 5, 4, 3, 2, 1, 0},
};

// The median of the last five values, kept sorted; each new value replaces the oldest end
// alternately from above and below (LASzip's "streaming median": the exact replacement order is
// part of the format, since the median is the prediction).
class StreamingMedian5 {
 public:
  void reset() {
    v_ = {0, 0, 0, 0, 0};
    from_above_ = true;
  }
  std::int32_t get() const { return v_[2]; }
  void add(std::int32_t x) {
    if (from_above_) {  // drop v_[4]
      if (x < v_[2]) {
        v_[4] = v_[3];
        v_[3] = v_[2];
        if (x < v_[0]) {
          v_[2] = v_[1];
          v_[1] = v_[0];
          v_[0] = x;
        } else if (x < v_[1]) {
          v_[2] = v_[1];
          v_[1] = x;
        } else {
          v_[2] = x;
        }
      } else {
        if (x < v_[3]) {
          v_[4] = v_[3];
          v_[3] = x;
        } else {
          v_[4] = x;
        }
        from_above_ = false;
      }
    } else {  // drop v_[0]
      if (v_[2] < x) {
        v_[0] = v_[1];
        v_[1] = v_[2];
        if (v_[4] < x) {
          v_[2] = v_[3];
          v_[3] = v_[4];
          v_[4] = x;
        } else if (v_[3] < x) {
          v_[2] = v_[3];
          v_[3] = x;
        } else {
          v_[2] = x;
        }
      } else {
        if (v_[1] < x) {
          v_[0] = v_[1];
          v_[1] = x;
        } else {
          v_[0] = x;
        }
        from_above_ = true;
      }
    }
  }

 private:
  std::array<std::int32_t, 5> v_{};
  bool from_above_ = true;
};

std::int32_t medianOf3(const std::array<std::int32_t, 3>& v) {
  return std::max(std::min(v[0], v[1]), std::min(std::max(v[0], v[1]), v[2]));
}

// The context of y from x's corrector bits, of z from the mean of x's and y's (version 2): even
// bit counts only, capped, plus one for single-return pulses.
std::uint32_t yContext(std::uint32_t k, bool single) {
  return (single ? 1 : 0) + (k < 20 ? k & ~1u : 20);
}
std::uint32_t zContext(std::uint32_t k, bool single) {
  return (single ? 1 : 0) + (k < 18 ? k & ~1u : 18);
}

// Everything version 2 keeps, shared by its decoder and encoder.
template <bool kDecoding>
struct StateV2 {
  Point10 last{};
  std::array<std::uint16_t, 16> last_intensity{};
  std::array<std::int32_t, 8> last_height{};
  std::array<StreamingMedian5, 16> x_median, y_median;
  SymbolModel changed{64, kDecoding};
  std::array<SymbolModel, 2> scan_angle{SymbolModel(256, kDecoding), SymbolModel(256, kDecoding)};
  ModelsByByte flags{kDecoding}, classification{kDecoding}, user_data{kDecoding};

  void reset(const std::byte* first) {
    std::memcpy(&last, first, sizeof last);
    last.intensity = 0;  // predicted per context from last_intensity, never from the raw point
    last_intensity.fill(0);
    last_height.fill(0);
    for (auto& m : x_median) m.reset();
    for (auto& m : y_median) m.reset();
    changed.reset();
    for (auto& m : scan_angle) m.reset();
    flags.startChunk();
    classification.startChunk();
    user_data.startChunk();
  }
};

const IntegerCodecShape kIntensityV2{.bits = 16, .contexts = 4};
const IntegerCodecShape kSourceId{.bits = 16, .contexts = 1};
const IntegerCodecShape kDxV2{.bits = 32, .contexts = 2};
const IntegerCodecShape kDyV2{.bits = 32, .contexts = 22};
const IntegerCodecShape kZV2{.bits = 32, .contexts = 20};

class Point10DecoderV2 final : public ItemDecoder {
 public:
  void start(const std::byte* first) override {
    s_.reset(first);
    intensity_.reset();
    source_id_.reset();
    dx_.reset();
    dy_.reset();
    z_.reset();
  }

  void decode(ArithmeticDecoder& dec, std::byte* out) override {
    Point10& p = s_.last;
    const std::uint32_t changed = dec.decodeSymbol(s_.changed);
    if (changed & 32) p.flags = std::uint8_t(dec.decodeSymbol(s_.flags[p.flags]));
    const unsigned r = p.returnNumber(), n = p.numberOfReturns();
    const unsigned m = kReturnContext[n][r], l = kReturnLevel[n][r];
    if (changed & 16) {
      p.intensity = std::uint16_t(intensity_.decode(dec, s_.last_intensity[m], m < 3 ? m : 3));
      s_.last_intensity[m] = p.intensity;
    } else if (changed != 0) {
      p.intensity = s_.last_intensity[m];
    }
    if (changed & 8) {
      p.classification = std::uint8_t(dec.decodeSymbol(s_.classification[p.classification]));
    }
    if (changed & 4) {
      const std::uint32_t delta = dec.decodeSymbol(s_.scan_angle[p.scanDirection()]);
      p.scan_angle_rank = std::uint8_t(delta + p.scan_angle_rank);
    }
    if (changed & 2) p.user_data = std::uint8_t(dec.decodeSymbol(s_.user_data[p.user_data]));
    if (changed & 1) p.point_source_id = std::uint16_t(source_id_.decode(dec, p.point_source_id));

    const bool single = n == 1;
    std::int32_t diff = dx_.decode(dec, s_.x_median[m].get(), single ? 1 : 0);
    p.x = wrapAdd(p.x, diff);
    s_.x_median[m].add(diff);
    diff = dy_.decode(dec, s_.y_median[m].get(), yContext(dx_.lastK(), single));
    p.y = wrapAdd(p.y, diff);
    s_.y_median[m].add(diff);
    p.z = z_.decode(dec, s_.last_height[l], zContext((dx_.lastK() + dy_.lastK()) / 2, single));
    s_.last_height[l] = p.z;
    std::memcpy(out, &p, sizeof p);
  }

 private:
  StateV2<true> s_;
  IntegerDecoder intensity_{kIntensityV2}, source_id_{kSourceId};
  IntegerDecoder dx_{kDxV2}, dy_{kDyV2}, z_{kZV2};
};

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

std::unique_ptr<ItemDecoder> makePoint10Decoder(int version) {
  assert((version == 1 || version == 2) && "POINT10 has versions 1 and 2");
  if (version == 1) return std::make_unique<Point10DecoderV1>();
  return std::make_unique<Point10DecoderV2>();
}

std::unique_ptr<ItemEncoder> makePoint10Encoder(int version) {
  assert((version == 1 || version == 2) && "POINT10 has versions 1 and 2");
  if (version == 1) return std::make_unique<Point10EncoderV1>();
  return std::make_unique<Point10EncoderV2>();
}

}  // namespace parallax::laz::pointwise
