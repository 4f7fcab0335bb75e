// Decoding POINT14 (versions 3 and 4) from its nine layers. The order of the decoding steps and
// every context below is the format's (LASzip's writer makes the same choices in the same order;
// see layered_point14_encoder.cpp for the other side).
#include <cassert>

#include "io/laz/layered_point14.h"

namespace parallax::laz::layered {

void Point14Decoder::startChannel(unsigned channel, const Point14& seed) {
  if (!channels_[channel]) channels_[channel] = std::make_unique<Channel>();
  Channel& c = *channels_[channel];
  c.models.reset();
  c.history.reset(seed);
  used_[channel] = true;
}

unsigned Point14Decoder::start(const std::byte* first,
                               std::span<const std::span<const std::byte>> layers) {
  assert(layers.size() == kPoint14Layers && "POINT14 has nine layers");
  for (std::size_t i = 0; i < kPoint14Layers; ++i) {
    dec_[i].start(layers[i]);
    // Layer 0 always decodes (LASzip reads it even when empty); the others only when present.
    present_[i] = i == kLayerChannelReturnsXY || !layers[i].empty();
  }
  gps_corrupt_ = false;
  used_.fill(false);
  const Point14 seed = Point14::load(first);
  current_ = seed.channel;
  startChannel(current_, seed);
  return current_;
}

LayerFailure Point14Decoder::failure() const {
  for (std::size_t i = 0; i < kPoint14Layers; ++i) {
    if (LayerFailure f = checkLayer(dec_[i], present_[i], i)) return f;
  }
  if (gps_corrupt_) return {int(kLayerGpsTime), false};
  return {};
}

unsigned Point14Decoder::decode(std::byte* record) {
  ArithmeticDecoder& dec = dec_[kLayerChannelReturnsXY];
  Channel* c = channels_[current_].get();
  Point14* last = &c->history.last;

  // The kind of the channel's last return (first, last, both, neither) and whether its GPS time
  // changed choose the model of the "what changed" symbol.
  const std::uint32_t lpr = (last->return_number == 1 ? 1u : 0u) +
                            (last->return_number >= last->number_of_returns ? 2u : 0u) +
                            (last->gps_time_changed ? 4u : 0u);
  const std::uint32_t changed = dec.decodeSymbol(*c->models.changed_values[lpr]);

  bool switched = false;
  if (changed & (1u << 6)) {
    // A new scanner channel: coded as the step (1-3) from the current one.
    const std::uint32_t step = dec.decodeSymbol(*c->models.scanner_channel) + 1;
    const unsigned channel = (current_ + step) & 3;
    if (!used_[channel]) startChannel(channel, *last);
    current_ = channel;
    c = channels_[channel].get();
    last = &c->history.last;
    last->channel = std::uint8_t(channel);
    switched = true;
  }
  const bool point_source_change = (changed & (1u << 5)) != 0;
  const bool gps_time_change = (changed & (1u << 4)) != 0;
  const bool scan_angle_change = (changed & (1u << 3)) != 0;
  Point14Models<IntegerDecoder>& m = c->models;
  Point14History& h = c->history;

  // Returns: the number of returns when it changed, the return number as +1, -1 or coded.
  const std::uint32_t last_n = last->number_of_returns;
  const std::uint32_t last_r = last->return_number;
  std::uint32_t n = last_n;
  if (changed & (1u << 2)) {
    n = dec.decodeSymbol(m.number_of_returns[last_n]);
    last->number_of_returns = std::uint8_t(n);
  }
  std::uint32_t r = last_r;
  switch (changed & 3) {
    case 0:
      break;
    case 1:
      r = (last_r + 1) & 15;
      break;
    case 2:
      r = (last_r + 15) & 15;
      break;
    default:
      if (gps_time_change) {
        r = dec.decodeSymbol(m.return_number[last_r]);
      } else {
        r = (last_r + dec.decodeSymbol(*m.return_number_gps_same) + 2) & 15;
      }
      break;
  }
  last->return_number = std::uint8_t(r);

  const std::uint32_t map = returnMap(n, r);
  const std::uint32_t level = returnLevel(n, r);
  // cpr: 3 single, 2 first, 1 last, 0 intermediate return.
  const std::uint32_t cpr = (r == 1 ? 2u : 0u) + (r >= n ? 1u : 0u);
  const std::uint32_t single = n == 1 ? 1u : 0u;
  const std::uint32_t median_index = (map << 1) | (gps_time_change ? 1u : 0u);

  // X and Y: differences from the last point, predicted by a running median per return kind;
  // Y's context is X's corrector size.
  std::int32_t diff = m.dx->decode(dec, h.median_x[median_index].get(), single);
  last->x = wrapAdd(last->x, diff);
  h.median_x[median_index].add(diff);
  std::uint32_t k_bits = m.dx->lastK();
  diff = m.dy->decode(dec, h.median_y[median_index].get(),
                      single + (k_bits < 20 ? (k_bits & ~1u) : 20u));
  last->y = wrapAdd(last->y, diff);
  h.median_y[median_index].add(diff);

  if (present_[kLayerZ]) {
    k_bits = (m.dx->lastK() + m.dy->lastK()) / 2;
    last->z =
        m.z->decode(dec_[kLayerZ], h.last_z[level], single + (k_bits < 18 ? (k_bits & ~1u) : 18u));
    h.last_z[level] = last->z;
  }
  if (present_[kLayerClassification]) {
    const std::uint32_t ccc = ((last->classification & 0x1Fu) << 1) + (cpr == 3 ? 1u : 0u);
    last->classification =
        std::uint8_t(dec_[kLayerClassification].decodeSymbol(m.classification[ccc]));
  }
  if (present_[kLayerFlags]) {
    last->flags = std::uint8_t(dec_[kLayerFlags].decodeSymbol(m.flags[last->flags]));
  }
  if (present_[kLayerIntensity]) {
    const std::uint32_t i = (cpr << 1) | (gps_time_change ? 1u : 0u);
    const auto intensity =
        std::uint16_t(m.intensity->decode(dec_[kLayerIntensity], h.last_intensity[i], cpr));
    h.last_intensity[i] = intensity;
    last->intensity = intensity;
  }
  if (present_[kLayerScanAngle] && scan_angle_change) {
    last->scan_angle = std::int16_t(
        m.scan_angle->decode(dec_[kLayerScanAngle], last->scan_angle, gps_time_change ? 1u : 0u));
  }
  if (present_[kLayerUserData]) {
    last->user_data =
        std::uint8_t(dec_[kLayerUserData].decodeSymbol(m.user_data[last->user_data / 4]));
  }
  if (present_[kLayerPointSource] && point_source_change) {
    last->point_source =
        std::uint16_t(m.point_source->decode(dec_[kLayerPointSource], last->point_source));
  }
  if (present_[kLayerGpsTime] && gps_time_change) {
    decodeGpsTime(*c);
    last->gps_time = h.gps_time[h.gps_last];
  }

  last->store(record);
  last->gps_time_changed = gps_time_change;
  // Version 3 hands the other items the channel only on a switch, else context 0.
  if (version_ >= 4) return current_;
  return switched ? current_ : 0;
}

void Point14Decoder::decodeGpsTime(Channel& c) {
  ArithmeticDecoder& dec = dec_[kLayerGpsTime];
  Point14Models<IntegerDecoder>& m = c.models;
  Point14History& h = c.history;
  std::uint32_t& last = h.gps_last;
  // A new sequence: its upper 32 bits predicted by the current sequence's, its lower 32 raw.
  const auto new_sequence = [&] {
    h.gps_next = (h.gps_next + 1) & 3;
    const std::int32_t high =
        m.gps->decode(dec, std::int32_t(std::uint32_t(h.gps_time[last] >> 32)), 8);
    const std::uint32_t low = dec.readInt();
    h.gps_time[h.gps_next] = (std::uint64_t(std::uint32_t(high)) << 32) | low;
    last = h.gps_next;
    h.gps_diff[last] = 0;
    h.gps_extreme[last] = 0;
  };
  // A writer switches to another sequence at most once per point, then codes the time in it;
  // a bound on the rounds keeps a corrupt stream from looping.
  for (int round = 0; round < 4; ++round) {
    if (h.gps_diff[last] == 0) {
      // The last difference was zero: code the difference itself.
      const std::uint32_t multi = dec.decodeSymbol(*m.gps_0diff);
      if (multi == 0) {
        h.gps_diff[last] = m.gps->decode(dec, 0, 0);
        h.gps_time[last] += std::uint64_t(std::int64_t(h.gps_diff[last]));
        h.gps_extreme[last] = 0;
      } else if (multi == 1) {
        new_sequence();
      } else {
        last = (last + multi - 1) & 3;  // the time continues another sequence
        continue;
      }
      return;
    }
    const std::uint32_t multi = dec.decodeSymbol(*m.gps_multi);
    const std::int32_t last_diff = h.gps_diff[last];
    if (multi == 1) {
      // The same difference again, plus a corrector.
      h.gps_time[last] += std::uint64_t(std::int64_t(m.gps->decode(dec, last_diff, 1)));
      h.gps_extreme[last] = 0;
      return;
    }
    if (multi < kGpsMultiCodeFull) {
      // A multiple of the last difference (0 stands for "no multiple"; above kGpsMulti the
      // multiplier is negative). An extreme multiplier four times running becomes the new
      // difference.
      std::int32_t d;
      bool extreme = false;
      if (multi == 0) {
        d = m.gps->decode(dec, 0, 7);
        extreme = true;
      } else if (multi < kGpsMulti) {
        d = m.gps->decode(dec, wrapMul(std::int32_t(multi), last_diff), multi < 10 ? 2 : 3);
      } else if (multi == kGpsMulti) {
        d = m.gps->decode(dec, wrapMul(std::int32_t(kGpsMulti), last_diff), 4);
        extreme = true;
      } else {
        const std::int32_t negative = std::int32_t(kGpsMulti) - std::int32_t(multi);
        if (negative > kGpsMultiMinus) {
          d = m.gps->decode(dec, wrapMul(negative, last_diff), 5);
        } else {
          d = m.gps->decode(dec, wrapMul(kGpsMultiMinus, last_diff), 6);
          extreme = true;
        }
      }
      if (extreme && ++h.gps_extreme[last] > 3) {
        h.gps_diff[last] = d;
        h.gps_extreme[last] = 0;
      }
      h.gps_time[last] += std::uint64_t(std::int64_t(d));
      return;
    }
    if (multi == kGpsMultiCodeFull) {
      new_sequence();
      return;
    }
    last = (last + multi - kGpsMultiCodeFull) & 3;  // another sequence
  }
  gps_corrupt_ = true;
}

}  // namespace parallax::laz::layered
