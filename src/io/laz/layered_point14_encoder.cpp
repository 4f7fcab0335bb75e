// Encoding POINT14 (versions 3 and 4) into its nine layers, making LASzip's choices in LASzip's
// order so that the layers come out byte for byte as LASzip writes them (see
// layered_point14_decoder.cpp for the other side).
//
// One deliberate difference: LASzip decides whether a GPS time changed by comparing the doubles,
// so -0.0 after +0.0 counts as unchanged (and is lost) and a NaN always counts as changed. This
// encoder compares the bits: every time survives, and the stream decodes in every LAZ reader; the
// bytes differ from LASzip's only for those two cases.
#include <cmath>

#include "io/laz/layered_point14.h"

namespace parallax::laz::layered {

namespace {

// LASzip rounds the ratio of two time differences as (int)(ratio ± 0.5) on x86-64, where a
// double beyond the int range converts to INT_MIN (cvttsd2si). Only a ratio of exactly 2^31 gets
// there; reproducing it keeps the bytes LASzip's.
std::int32_t quantizeRatio(float ratio) {
  const double shifted = ratio >= 0 ? double(ratio) + 0.5 : double(ratio) - 0.5;
  if (!(shifted > -2147483649.0 && shifted < 2147483648.0)) return INT32_MIN;
  return std::int32_t(shifted);
}

// Fits a 64-bit difference in 32 bits?
bool fits32(std::int64_t d) {
  return d == std::int64_t(std::int32_t(d));
}

}  // namespace

void Point14Encoder::startChannel(unsigned channel, const Point14& seed) {
  if (!channels_[channel]) channels_[channel] = std::make_unique<Channel>();
  Channel& c = *channels_[channel];
  c.models.reset();
  c.history.reset(seed);
  used_[channel] = true;
}

unsigned Point14Encoder::start(const std::byte* first) {
  for (LayerStream& l : layers_) l.restart();
  changed_.fill(false);
  // LASzip always writes the first two layers, whatever they hold.
  changed_[kLayerChannelReturnsXY] = changed_[kLayerZ] = true;
  used_.fill(false);
  const Point14 seed = Point14::load(first);
  current_ = seed.channel;
  startChannel(current_, seed);
  return current_;
}

void Point14Encoder::finish() {
  for (LayerStream& l : layers_) l.finish();
}

std::span<const std::uint8_t> Point14Encoder::layer(std::size_t i) const {
  if (!changed_[i]) return {};
  return layers_[i].bytes;
}

unsigned Point14Encoder::encode(const std::byte* record) {
  ArithmeticEncoder& enc = layers_[kLayerChannelReturnsXY].encoder;
  const Point14 p = Point14::load(record);
  Channel* c = channels_[current_].get();
  const Point14* last = &c->history.last;

  const std::uint32_t lpr = (last->return_number == 1 ? 1u : 0u) +
                            (last->return_number >= last->number_of_returns ? 2u : 0u) +
                            (last->gps_time_changed ? 4u : 0u);
  // A point on another channel that the chunk already used is compared with that channel's last
  // point; on a channel new to the chunk, with the current one's (the new channel starts as its
  // copy).
  const bool switched = p.channel != current_;
  if (switched && used_[p.channel]) last = &channels_[p.channel]->history.last;

  const bool point_source_change = p.point_source != last->point_source;
  const bool gps_time_change = p.gps_time != last->gps_time;
  const bool scan_angle_change = p.scan_angle != last->scan_angle;
  const std::uint32_t last_n = last->number_of_returns;
  const std::uint32_t last_r = last->return_number;
  const std::uint32_t n = p.number_of_returns;
  const std::uint32_t r = p.return_number;
  std::uint32_t changed = (switched ? 1u << 6 : 0u) | (point_source_change ? 1u << 5 : 0u) |
                          (gps_time_change ? 1u << 4 : 0u) | (scan_angle_change ? 1u << 3 : 0u) |
                          (n != last_n ? 1u << 2 : 0u);
  if (r != last_r) {
    if (r == ((last_r + 1) & 15)) {
      changed |= 1;
    } else if (r == ((last_r + 15) & 15)) {
      changed |= 2;
    } else {
      changed |= 3;
    }
  }
  enc.encodeSymbol(*c->models.changed_values[lpr], changed);

  if (switched) {
    enc.encodeSymbol(*c->models.scanner_channel, (p.channel - current_ + 3) & 3);
    if (!used_[p.channel]) {
      startChannel(p.channel, c->history.last);
      last = &channels_[p.channel]->history.last;
    }
    current_ = p.channel;
    c = channels_[current_].get();
  }
  Point14Models<IntegerEncoder>& m = c->models;
  Point14History& h = c->history;

  if (n != last_n) enc.encodeSymbol(m.number_of_returns[last_n], n);
  if ((changed & 3) == 3) {
    if (gps_time_change) {
      enc.encodeSymbol(m.return_number[last_r], r);
    } else {
      // r = last_r + symbol + 2 (mod 16)
      enc.encodeSymbol(*m.return_number_gps_same, (r - last_r + 14) & 15);
    }
  }

  const std::uint32_t map = returnMap(n, r);
  const std::uint32_t level = returnLevel(n, r);
  const std::uint32_t cpr = (r == 1 ? 2u : 0u) + (r >= n ? 1u : 0u);
  const std::uint32_t single = n == 1 ? 1u : 0u;
  const std::uint32_t median_index = (map << 1) | (gps_time_change ? 1u : 0u);

  std::int32_t diff = wrapSub(p.x, last->x);
  m.dx->encode(enc, h.median_x[median_index].get(), diff, single);
  h.median_x[median_index].add(diff);
  std::uint32_t k_bits = m.dx->lastK();
  diff = wrapSub(p.y, last->y);
  m.dy->encode(enc, h.median_y[median_index].get(), diff,
               single + (k_bits < 20 ? (k_bits & ~1u) : 20u));
  h.median_y[median_index].add(diff);

  k_bits = (m.dx->lastK() + m.dy->lastK()) / 2;
  m.z->encode(layers_[kLayerZ].encoder, h.last_z[level], p.z,
              single + (k_bits < 18 ? (k_bits & ~1u) : 18u));
  h.last_z[level] = p.z;

  if (p.classification != last->classification) changed_[kLayerClassification] = true;
  const std::uint32_t ccc = ((last->classification & 0x1Fu) << 1) + (cpr == 3 ? 1u : 0u);
  layers_[kLayerClassification].encoder.encodeSymbol(m.classification[ccc], p.classification);

  if (p.flags != last->flags) changed_[kLayerFlags] = true;
  layers_[kLayerFlags].encoder.encodeSymbol(m.flags[last->flags], p.flags);

  if (p.intensity != last->intensity) changed_[kLayerIntensity] = true;
  const std::uint32_t i = (cpr << 1) | (gps_time_change ? 1u : 0u);
  m.intensity->encode(layers_[kLayerIntensity].encoder, h.last_intensity[i], p.intensity, cpr);
  h.last_intensity[i] = p.intensity;

  if (scan_angle_change) {
    changed_[kLayerScanAngle] = true;
    m.scan_angle->encode(layers_[kLayerScanAngle].encoder, last->scan_angle, p.scan_angle,
                         gps_time_change ? 1u : 0u);
  }

  if (p.user_data != last->user_data) changed_[kLayerUserData] = true;
  layers_[kLayerUserData].encoder.encodeSymbol(m.user_data[last->user_data / 4], p.user_data);

  if (point_source_change) {
    changed_[kLayerPointSource] = true;
    m.point_source->encode(layers_[kLayerPointSource].encoder, last->point_source, p.point_source);
  }
  if (gps_time_change) {
    changed_[kLayerGpsTime] = true;
    encodeGpsTime(*c, p.gps_time);
  }

  Point14& stored = channels_[current_]->history.last;
  stored = p;
  stored.gps_time_changed = gps_time_change;
  if (version_ >= 4) return current_;
  return switched ? current_ : 0;
}

void Point14Encoder::encodeGpsTime(Channel& c, std::uint64_t time) {
  ArithmeticEncoder& enc = layers_[kLayerGpsTime].encoder;
  Point14Models<IntegerEncoder>& m = c.models;
  Point14History& h = c.history;
  std::uint32_t& last = h.gps_last;
  const auto difference = [&](std::uint32_t sequence) {
    return std::int64_t(time - h.gps_time[sequence]);
  };
  // The index of another sequence (1-3 ahead) the time is within 32 bits of, or 0.
  const auto other_sequence = [&]() -> std::uint32_t {
    for (std::uint32_t i = 1; i < 4; ++i) {
      if (fits32(difference((last + i) & 3))) return i;
    }
    return 0;
  };
  // A time far from every sequence starts a new one.
  const auto new_sequence = [&](SymbolModel& model, std::uint32_t symbol) {
    enc.encodeSymbol(model, symbol);
    m.gps->encode(enc, std::int32_t(std::uint32_t(h.gps_time[last] >> 32)),
                  std::int32_t(std::uint32_t(time >> 32)), 8);
    enc.writeInt(std::uint32_t(time));
    h.gps_next = (h.gps_next + 1) & 3;
    last = h.gps_next;
    h.gps_diff[last] = 0;
    h.gps_extreme[last] = 0;
  };

  // At most two rounds: a switch to another sequence, then the time coded in it.
  for (;;) {
    const std::int64_t diff64 = difference(last);
    if (h.gps_diff[last] == 0) {
      if (fits32(diff64)) {
        enc.encodeSymbol(*m.gps_0diff, 0);
        m.gps->encode(enc, 0, std::int32_t(diff64), 0);
        h.gps_diff[last] = std::int32_t(diff64);
        h.gps_extreme[last] = 0;
      } else if (const std::uint32_t i = other_sequence(); i != 0) {
        enc.encodeSymbol(*m.gps_0diff, i + 1);
        last = (last + i) & 3;
        continue;
      } else {
        new_sequence(*m.gps_0diff, 1);
      }
      h.gps_time[last] = time;
      return;
    }
    if (fits32(diff64)) {
      const std::int32_t d = std::int32_t(diff64);
      const std::int32_t last_diff = h.gps_diff[last];
      const std::int32_t multi = quantizeRatio(float(d) / float(last_diff));
      bool extreme = false;
      if (multi == 1) {
        enc.encodeSymbol(*m.gps_multi, 1);
        m.gps->encode(enc, last_diff, d, 1);
        h.gps_extreme[last] = 0;
      } else if (multi > 0) {
        if (multi < std::int32_t(kGpsMulti)) {
          enc.encodeSymbol(*m.gps_multi, std::uint32_t(multi));
          m.gps->encode(enc, wrapMul(multi, last_diff), d, multi < 10 ? 2 : 3);
        } else {
          enc.encodeSymbol(*m.gps_multi, kGpsMulti);
          m.gps->encode(enc, wrapMul(std::int32_t(kGpsMulti), last_diff), d, 4);
          extreme = true;
        }
      } else if (multi < 0) {
        if (multi > kGpsMultiMinus) {
          enc.encodeSymbol(*m.gps_multi, std::uint32_t(std::int32_t(kGpsMulti) - multi));
          m.gps->encode(enc, wrapMul(multi, last_diff), d, 5);
        } else {
          enc.encodeSymbol(*m.gps_multi, std::uint32_t(std::int32_t(kGpsMulti) - kGpsMultiMinus));
          m.gps->encode(enc, wrapMul(kGpsMultiMinus, last_diff), d, 6);
          extreme = true;
        }
      } else {
        enc.encodeSymbol(*m.gps_multi, 0);
        m.gps->encode(enc, 0, d, 7);
        extreme = true;
      }
      if (extreme && ++h.gps_extreme[last] > 3) {
        h.gps_diff[last] = d;
        h.gps_extreme[last] = 0;
      }
    } else if (const std::uint32_t i = other_sequence(); i != 0) {
      enc.encodeSymbol(*m.gps_multi, kGpsMultiCodeFull + i);
      last = (last + i) & 3;
      continue;
    } else {
      new_sequence(*m.gps_multi, kGpsMultiCodeFull);
    }
    h.gps_time[last] = time;
    return;
  }
}

}  // namespace parallax::laz::layered
