// What the POINT14 decoder and encoder share: the channel state, the models and the format's
// context maps.
#include "io/laz/layered_point14.h"

namespace parallax::laz::layered {

const char* const kPoint14LayerNames[kPoint14Layers] = {
    "channel/returns/XY", "Z",         "classification",  "flags",    "intensity",
    "scan angle",         "user data", "point source ID", "GPS time",
};

namespace {

// The kind of a (number of returns, return number) pair in six classes, for the median
// predictors of X and Y. The format's table: single (0), first of two (1), last of two (2), ...
// with the impossible pairs (r > n, r or n zero) folded onto the others, so that files which
// misuse the fields still compress. Indexed [n][r].
constexpr std::uint8_t kReturnMap[16][16] = {
    {0, 1, 2, 3, 4, 5, 3, 4, 4, 5, 5, 5, 5, 5, 5, 5},
    {1, 0, 1, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3},
    {2, 1, 2, 4, 4, 4, 4, 4, 4, 4, 4, 3, 3, 3, 3, 3},
    {3, 3, 4, 5, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4},
    {4, 3, 4, 4, 5, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4},
    {5, 3, 4, 4, 4, 5, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4},
    {3, 3, 4, 4, 4, 4, 5, 4, 4, 4, 4, 4, 4, 4, 4, 4},
    {4, 3, 4, 4, 4, 4, 4, 5, 4, 4, 4, 4, 4, 4, 4, 4},
    {4, 3, 4, 4, 4, 4, 4, 4, 5, 4, 4, 4, 4, 4, 4, 4},
    {5, 3, 4, 4, 4, 4, 4, 4, 4, 5, 4, 4, 4, 4, 4, 4},
    {5, 3, 4, 4, 4, 4, 4, 4, 4, 4, 5, 4, 4, 4, 4, 4},
    {5, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4, 5, 5, 4, 4, 4},
    {5, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4, 5, 5, 5, 4, 4},
    {5, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4, 4, 5, 5, 5, 4},
    {5, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 5, 5, 5},
    {5, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 5, 5},
};

constexpr IntegerCodecShape shape(std::uint32_t bits, std::uint32_t contexts) {
  return {.bits = bits, .contexts = contexts};
}

}  // namespace

std::uint32_t returnMap(std::uint32_t n, std::uint32_t r) {
  return kReturnMap[n & 15][r & 15];
}

void Point14History::reset(const Point14& seed) {
  last = seed;
  last.gps_time_changed = false;
  last_intensity.fill(seed.intensity);
  for (Median5& m : median_x) m.reset();
  for (Median5& m : median_y) m.reset();
  last_z.fill(seed.z);
  gps_last = gps_next = 0;
  gps_time = {seed.gps_time, 0, 0, 0};
  gps_diff.fill(0);
  gps_extreme.fill(0);
}

template <class IntegerCodec>
Point14Models<IntegerCodec>::Point14Models(bool for_decoding)
    : scanner_channel(3, for_decoding),
      number_of_returns(16, for_decoding),
      return_number(16, for_decoding),
      return_number_gps_same(13, for_decoding),
      dx(shape(32, 2)),
      dy(shape(32, 22)),
      z(shape(32, 20)),
      classification(256, for_decoding),
      flags(64, for_decoding),
      user_data(256, for_decoding),
      intensity(shape(16, 4)),
      scan_angle(shape(16, 2)),
      point_source(shape(16, 1)),
      gps_multi(kGpsMultiSymbols, for_decoding),
      gps_0diff(5, for_decoding),
      gps(shape(32, 9)) {
  changed_values.reserve(8);
  for (int i = 0; i < 8; ++i) changed_values.emplace_back(128, for_decoding);
}

template <class IntegerCodec>
void Point14Models<IntegerCodec>::reset() {
  for (Lazy<SymbolModel>& m : changed_values) m.reset();
  scanner_channel.reset();
  number_of_returns.reset();
  return_number.reset();
  return_number_gps_same.reset();
  dx.reset();
  dy.reset();
  z.reset();
  classification.reset();
  flags.reset();
  user_data.reset();
  intensity.reset();
  scan_angle.reset();
  point_source.reset();
  gps_multi.reset();
  gps_0diff.reset();
  gps.reset();
}

template struct Point14Models<IntegerDecoder>;
template struct Point14Models<IntegerEncoder>;

}  // namespace parallax::laz::layered
