// POINT14, versions 3 and 4: the 30 bytes that start every record of point formats 6-10, coded
// in nine layers (LAZ 1.4 specification, "layered compression"; Isenburg's LASzip design notes for
// LAS 1.4 points):
//   0 channel, returns and X/Y  (always present: the per-point "what changed" symbol lives here)
//   1 Z, 2 classification, 3 flags, 4 intensity, 5 scan angle, 6 user data, 7 point source ID,
//   8 GPS time.
// Each scanner channel has its own models and its own "last point"; a point is predicted from the
// last point of its channel. Internal to the LAZ codec.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "io/laz/integer_codec.h"
#include "io/laz/layered_items.h"
#include "io/laz/wrapping_int32.h"

namespace parallax::laz::layered {

inline constexpr std::size_t kPoint14Size = 30;
inline constexpr std::size_t kPoint14Layers = 9;
enum Point14Layer : unsigned {
  kLayerChannelReturnsXY = 0,
  kLayerZ,
  kLayerClassification,
  kLayerFlags,
  kLayerIntensity,
  kLayerScanAngle,
  kLayerUserData,
  kLayerPointSource,
  kLayerGpsTime,
};
extern const char* const kPoint14LayerNames[kPoint14Layers];

// The fields of a POINT14 record (LAS 1.4 R15, table 14), as the codec predicts them.
struct Point14 {
  std::int32_t x = 0, y = 0, z = 0;
  std::uint16_t intensity = 0;
  std::uint8_t return_number = 0;      // 4 bits
  std::uint8_t number_of_returns = 0;  // 4 bits
  // edge of flight line << 5 | scan direction << 4 | classification flags: the symbol the flags
  // layer codes (the scanner channel, between them in the record, is coded elsewhere).
  std::uint8_t flags = 0;
  std::uint8_t channel = 0;  // 2 bits
  std::uint8_t classification = 0;
  std::uint8_t user_data = 0;
  std::int16_t scan_angle = 0;
  std::uint16_t point_source = 0;
  std::uint64_t gps_time = 0;  // the double's bits
  // Not in the record: whether this point's GPS time differed from its predecessor's, a context
  // for the next point of the channel.
  bool gps_time_changed = false;

  static Point14 load(const std::byte* record) {
    Point14 p;
    p.x = loadLE<std::int32_t>(record + 0);
    p.y = loadLE<std::int32_t>(record + 4);
    p.z = loadLE<std::int32_t>(record + 8);
    p.intensity = loadLE<std::uint16_t>(record + 12);
    const auto returns = std::uint8_t(record[14]);
    p.return_number = returns & 0x0F;
    p.number_of_returns = returns >> 4;
    const auto flags = std::uint8_t(record[15]);
    p.flags = std::uint8_t(((flags >> 2) & 0x30) | (flags & 0x0F));
    p.channel = (flags >> 4) & 0x03;
    p.classification = std::uint8_t(record[16]);
    p.user_data = std::uint8_t(record[17]);
    p.scan_angle = loadLE<std::int16_t>(record + 18);
    p.point_source = loadLE<std::uint16_t>(record + 20);
    p.gps_time = loadLE<std::uint64_t>(record + 22);
    return p;
  }
  void store(std::byte* record) const {
    storeLE(record + 0, x);
    storeLE(record + 4, y);
    storeLE(record + 8, z);
    storeLE(record + 12, intensity);
    record[14] = std::byte(return_number | (number_of_returns << 4));
    record[15] = std::byte(((flags & 0x30) << 2) | (channel << 4) | (flags & 0x0F));
    record[16] = std::byte(classification);
    record[17] = std::byte(user_data);
    storeLE(record + 18, scan_angle);
    storeLE(record + 20, point_source);
    storeLE(record + 22, gps_time);
  }
};

// LASzip's running "median of five" of coordinate differences: five sorted values; each new value
// replaces the largest or the smallest, alternating as the new values fall above or below the
// middle one. Not a true median of the last five, but the prediction the format defines.
class Median5 {
 public:
  void reset() {
    values_ = {};
    high_ = true;
  }
  std::int32_t get() const { return values_[2]; }
  void add(std::int32_t v) {
    const std::int32_t mid = values_[2];
    if (high_) {
      // Drop the largest value, insert v in order.
      int i = 4;
      for (; i > 0 && values_[i - 1] > v; --i) values_[i] = values_[i - 1];
      values_[i] = v;
      high_ = v < mid;
    } else {
      // Drop the smallest value, insert v in order.
      int i = 0;
      for (; i < 4 && values_[i + 1] < v; ++i) values_[i] = values_[i + 1];
      values_[i] = v;
      high_ = !(mid < v);
    }
  }

 private:
  std::array<std::int32_t, 5> values_{};
  bool high_ = true;
};

// GPS times: LASzip codes the double's bits as 64-bit integers in up to four "sequences" (time
// bases, e.g. of interleaved flight lines), each with its last time and last difference; a
// difference is coded as a multiple of the last one plus a corrector.
inline constexpr std::uint32_t kGpsMulti = 500;          // largest multiplier coded directly
inline constexpr std::int32_t kGpsMultiMinus = -10;      // smallest (negative) multiplier
inline constexpr std::uint32_t kGpsMultiCodeFull = 511;  // kGpsMulti - kGpsMultiMinus + 1
inline constexpr std::uint32_t kGpsMultiSymbols = 515;   // + 3 sequence switches + 1

// What a channel remembers between points (besides its models).
struct Point14History {
  Point14 last;
  std::array<std::uint16_t, 8> last_intensity{};
  std::array<Median5, 12> median_x, median_y;
  std::array<std::int32_t, 8> last_z{};
  std::uint32_t gps_last = 0, gps_next = 0;
  std::array<std::uint64_t, 4> gps_time{};
  std::array<std::int32_t, 4> gps_diff{};
  std::array<std::int32_t, 4> gps_extreme{};

  void reset(const Point14& seed);
};

// The models of one channel. `IntegerCodec` is IntegerDecoder or IntegerEncoder.
template <class IntegerCodec>
struct Point14Models {
  explicit Point14Models(bool for_decoding);
  void reset();

  std::vector<Lazy<SymbolModel>> changed_values;  // 8 contexts: last return kind, time change
  Lazy<SymbolModel> scanner_channel;
  LazySymbolModels<16> number_of_returns;  // by the last number of returns
  LazySymbolModels<16> return_number;      // by the last return number
  Lazy<SymbolModel> return_number_gps_same;
  Lazy<IntegerCodec> dx, dy, z;
  LazySymbolModels<64> classification;  // by the last classification and the return kind
  LazySymbolModels<64> flags;           // by the last flags
  LazySymbolModels<64> user_data;       // by the last user data / 4
  Lazy<IntegerCodec> intensity, scan_angle, point_source;
  Lazy<SymbolModel> gps_multi, gps_0diff;
  Lazy<IntegerCodec> gps;
};

// Context maps of the format (the level of a return, and the kind of return pair), both indexed
// [number of returns][return number].
std::uint32_t returnMap(std::uint32_t n, std::uint32_t r);
inline std::uint32_t returnLevel(std::uint32_t n, std::uint32_t r) {
  const std::uint32_t d = n > r ? n - r : r - n;
  return d < 7 ? d : 7;
}

class Point14Decoder {
 public:
  explicit Point14Decoder(unsigned version) : version_(version) {}

  // Starts a chunk from its first record; `layers` holds the nine layers. Returns the context
  // for the other items (the first record's channel).
  unsigned start(const std::byte* first, std::span<const std::span<const std::byte>> layers);
  // Decodes the next record; returns the context for the other items of this record.
  unsigned decode(std::byte* record);
  // The first layer that ran past its bytes or held an impossible value, if any.
  LayerFailure failure() const;

 private:
  struct Channel {
    Point14Models<IntegerDecoder> models{true};
    Point14History history;
  };
  void startChannel(unsigned channel, const Point14& seed);
  void decodeGpsTime(Channel& c);

  unsigned version_;
  std::array<std::unique_ptr<Channel>, kChannels> channels_;
  std::array<bool, kChannels> used_{};
  unsigned current_ = 0;
  std::array<ArithmeticDecoder, kPoint14Layers> dec_;
  std::array<bool, kPoint14Layers> present_{};
  bool gps_corrupt_ = false;
};

class Point14Encoder {
 public:
  explicit Point14Encoder(unsigned version) : version_(version) {}

  unsigned start(const std::byte* first);
  unsigned encode(const std::byte* record);
  void finish();
  // Layer i as the chunk stores it (empty when LASzip leaves it out: never changed).
  std::span<const std::uint8_t> layer(std::size_t i) const;

 private:
  struct Channel {
    Point14Models<IntegerEncoder> models{false};
    Point14History history;
  };
  void startChannel(unsigned channel, const Point14& seed);
  void encodeGpsTime(Channel& c, std::uint64_t time);

  unsigned version_;
  std::array<std::unique_ptr<Channel>, kChannels> channels_;
  std::array<bool, kChannels> used_{};
  unsigned current_ = 0;
  std::array<LayerStream, kPoint14Layers> layers_;
  std::array<bool, kPoint14Layers> changed_{};
};

}  // namespace parallax::laz::layered
