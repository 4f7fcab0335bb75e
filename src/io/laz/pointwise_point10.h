// POINT10 version 2's state and decoder (see pointwise_point10.cpp for the format), in a header
// so that the specialised chunk decoders (pointwise_codec.cpp) call it directly, inlined, with no
// virtual call per point. Internal to io/laz.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>

#include "io/laz/integer_codec.h"
#include "io/laz/pointwise_items.h"

namespace parallax::laz::pointwise::point10 {

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
inline constexpr std::uint8_t kReturnContext[8][8] = {
    {15, 14, 13, 12, 11, 10, 9, 8},  {14, 0, 1, 3, 6, 10, 10, 9},
    {13, 1, 2, 4, 7, 11, 11, 10},    {12, 3, 4, 5, 8, 12, 12, 11},
    {11, 6, 7, 8, 9, 13, 13, 12},    {10, 10, 11, 12, 13, 14, 14, 13},
    {9, 10, 11, 12, 13, 14, 15, 14}, {8, 9, 10, 11, 12, 13, 14, 15},
};
// The level l: |n - r|, the returns still to come.
inline constexpr std::uint8_t kReturnLevel[8][8] = {
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

inline std::int32_t medianOf3(const std::array<std::int32_t, 3>& v) {
  return std::max(std::min(v[0], v[1]), std::min(std::max(v[0], v[1]), v[2]));
}

// The context of y from x's corrector bits, of z from the mean of x's and y's (version 2): even
// bit counts only, capped, plus one for single-return pulses.
inline std::uint32_t yContext(std::uint32_t k, bool single) {
  return (single ? 1 : 0) + (k < 20 ? k & ~1u : 20);
}
inline std::uint32_t zContext(std::uint32_t k, bool single) {
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

inline const IntegerCodecShape kIntensityV2{.bits = 16, .contexts = 4};
inline const IntegerCodecShape kSourceId{.bits = 16, .contexts = 1};
inline const IntegerCodecShape kDxV2{.bits = 32, .contexts = 2};
inline const IntegerCodecShape kDyV2{.bits = 32, .contexts = 22};
inline const IntegerCodecShape kZV2{.bits = 32, .contexts = 20};

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

}  // namespace parallax::laz::pointwise::point10
