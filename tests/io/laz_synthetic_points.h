// Synthetic point records of LAS point formats 6-10 for the layered LAZ codec tests: raw records
// (LAS 1.4 R15, tables 14-18) that exercise every context of the codec: several scanner
// channels, pulses of up to 15 returns (and impossible return pairs), GPS times that jump between
// sequences, colours, near infrared, wave packets and extra bytes. Every `quiet_span` points,
// every third span keeps all fields but the coordinates constant, so whole chunks leave layers
// empty. Deterministic (integer arithmetic only), so that tests/io/tools/laszip_expectations.cpp
// builds the same records and has LASzip compress them (see test_laz_layered.cpp).
#pragma once

#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

#include "io/laz/chunk_codec.h"

namespace parallax::laz::testing {

struct SyntheticSpec {
  int format = 6;               // LAS point format, 6-10
  std::size_t extra_bytes = 0;  // per record, after the standard fields
  std::size_t count = 0;
  std::uint64_t seed = 1;
  std::size_t quiet_span = 0;  // 0: no quiet spans
  // Extreme values too: coordinates at the int32 limits, -0.0, +0.0 and NaN GPS times. (LASzip's
  // encoder compares GPS times as doubles, so its bytes differ from ours for those.)
  bool edge_values = false;
};

inline std::size_t syntheticRecordLength(int format, std::size_t extra_bytes) {
  static constexpr std::size_t kBase[] = {30, 36, 38, 59, 67};  // formats 6-10
  return kBase[format - 6] + extra_bytes;
}

class SplitMix64 {
 public:
  explicit SplitMix64(std::uint64_t seed) : state_(seed) {}
  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  std::uint32_t below(std::uint32_t n) { return std::uint32_t(next() % n); }
  bool chance(std::uint32_t one_in) { return below(one_in) == 0; }
  std::int32_t around(std::int32_t spread) {
    return std::int32_t(below(2 * std::uint32_t(spread) + 1)) - spread;
  }

 private:
  std::uint64_t state_;
};

inline std::vector<std::byte> makeSyntheticRecords(const SyntheticSpec& spec) {
  const std::size_t length = syntheticRecordLength(spec.format, spec.extra_bytes);
  const bool rgb = spec.format == 7 || spec.format == 8 || spec.format == 10;
  const bool nir = spec.format == 8 || spec.format == 10;
  const bool wave = spec.format == 9 || spec.format == 10;
  std::vector<std::byte> out(spec.count * length);
  SplitMix64 rng(spec.seed);

  struct ChannelState {
    std::int32_t x = 0, y = 0, z = 0;
    std::uint64_t time_ticks = 0;  // GPS time in 1/65536 s of the current epoch
    std::uint32_t epoch = 0;
    std::uint32_t n = 1, r = 1;  // the current pulse
    std::uint16_t point_source = 0;
    std::uint8_t scan_direction = 0;
  };
  std::array<ChannelState, 4> ch;
  for (std::uint32_t c = 0; c < 4; ++c) {
    ch[c].x = std::int32_t(rng.below(1u << 20)) - (1 << 19);
    ch[c].y = std::int32_t(rng.below(1u << 20));
    ch[c].z = std::int32_t(rng.below(1u << 12));
    ch[c].epoch = c % 3;
    ch[c].time_ticks = rng.below(1u << 24);
    ch[c].point_source = std::uint16_t(100 + c);
  }
  // Epochs far apart in the doubles' bits: a week in seconds, adjusted standard GPS time, and a
  // time near zero.
  static constexpr double kEpochs[] = {604800.0 * 0.5, 1.0e9, 12.0};
  unsigned channel = unsigned(spec.seed % 4);
  std::uint16_t intensity = 1000, scan_angle_base = 0;
  std::uint8_t classification = 2, class_flags = 0, user_data = 7;
  std::array<std::uint16_t, 4> colour = {30000, 20000, 10000, 40000};
  std::uint64_t wave_offset = 1u << 20;
  std::uint32_t wave_size = 256;
  std::vector<std::byte> quiet_fields;  // the record frozen at the start of a quiet span

  for (std::size_t i = 0; i < spec.count; ++i) {
    std::byte* rec = out.data() + i * length;
    const bool quiet = spec.quiet_span != 0 && (i / spec.quiet_span) % 3 == 1;
    const bool quiet_start = quiet && i % spec.quiet_span == 0;

    if (!quiet && rng.chance(40)) channel = (channel + 1 + rng.below(3)) % 4;
    ChannelState& c = ch[channel];

    // Returns: the next return of the pulse, or a new pulse.
    if (c.r < c.n && !rng.chance(20)) {
      ++c.r;
    } else {
      const std::uint32_t kind = rng.below(100);
      c.n = kind < 60 ? 1 : kind < 85 ? 2 + rng.below(3) : kind < 97 ? 5 + rng.below(11) : 0;
      c.r = c.n == 0 ? rng.below(16) : 1;
      if (rng.chance(50)) c.r = rng.below(16);  // impossible pairs happen in real files
      c.time_ticks += 1 + rng.below(40);
      if (rng.chance(300)) c.epoch = rng.below(3);      // another flight line's times
      if (rng.chance(700)) c.time_ticks += 1ull << 40;  // a jump beyond 32 bits
      if (rng.chance(60)) c.time_ticks += rng.below(1u << 20);
    }

    // Coordinates: a walk, with the occasional leap.
    c.x += rng.around(rng.chance(10) ? 100000 : 300);
    c.y += rng.around(rng.chance(10) ? 100000 : 300);
    c.z += rng.around(rng.chance(20) ? 5000 : 40);
    std::int32_t x = c.x, y = c.y, z = c.z;
    if (spec.edge_values && rng.chance(50)) {
      const std::int32_t extremes[] = {std::numeric_limits<std::int32_t>::min(),
                                       std::numeric_limits<std::int32_t>::max(), 0, -1};
      x = extremes[rng.below(4)];
      y = extremes[rng.below(4)];
      z = extremes[rng.below(4)];
    }
    std::memcpy(rec + 0, &x, 4);
    std::memcpy(rec + 4, &y, 4);
    std::memcpy(rec + 8, &z, 4);

    if (quiet && !quiet_start) {
      // Everything but the coordinates as at the start of the span.
      std::memcpy(rec + 12, quiet_fields.data() + 12, length - 12);
      continue;
    }

    if (rng.chance(3)) intensity = std::uint16_t(intensity + rng.around(200));
    if (rng.chance(100)) intensity = std::uint16_t(rng.next());
    std::memcpy(rec + 12, &intensity, 2);
    rec[14] = std::byte((c.r & 15) | (c.n & 15) << 4);
    if (rng.chance(200)) c.scan_direction ^= 1;
    if (rng.chance(150)) class_flags = std::uint8_t(rng.below(16));
    const std::uint8_t edge = rng.chance(300) ? 1 : 0;
    rec[15] = std::byte(class_flags | channel << 4 | c.scan_direction << 6 | edge << 7);
    if (rng.chance(8)) {
      static constexpr std::uint8_t kClasses[] = {1, 2, 3, 5, 6, 9};
      classification = rng.chance(30) ? std::uint8_t(rng.next()) : kClasses[rng.below(6)];
    }
    rec[16] = std::byte(classification);
    if (rng.chance(100)) user_data = std::uint8_t(rng.next());
    rec[17] = std::byte(user_data);
    if (rng.chance(500)) scan_angle_base = std::uint16_t(rng.next());
    std::int16_t scan_angle = std::int16_t(scan_angle_base + rng.around(rng.chance(4) ? 3000 : 0));
    if (spec.edge_values && rng.chance(40)) scan_angle = rng.chance(2) ? -32768 : 32767;
    std::memcpy(rec + 18, &scan_angle, 2);
    if (rng.chance(400)) c.point_source = std::uint16_t(rng.next());
    std::memcpy(rec + 20, &c.point_source, 2);
    double time = kEpochs[c.epoch] + double(c.time_ticks) / 65536.0;
    if (spec.edge_values && rng.chance(30)) {
      const double specials[] = {0.0, -0.0, std::numeric_limits<double>::quiet_NaN()};
      time = specials[rng.below(3)];
    }
    std::memcpy(rec + 22, &time, 8);

    std::size_t at = 30;
    if (rgb) {
      const bool grey = rng.chance(5);
      for (int k = 0; k < (nir ? 4 : 3); ++k) {
        if (rng.chance(2))
          colour[k] = std::uint16_t(colour[k] + rng.around(rng.chance(10) ? 9000 : 300));
      }
      if (grey) colour[1] = colour[2] = colour[0];
      for (int k = 0; k < (nir ? 4 : 3); ++k) std::memcpy(rec + at + 2 * k, &colour[k], 2);
      at += nir ? 8 : 6;
    }
    if (wave) {
      const std::uint32_t kind = rng.below(10);
      if (kind < 6) {
        wave_offset += wave_size;
      } else if (kind < 8) {
        wave_offset += rng.below(1u << 16);
      } else if (kind == 8) {
        wave_offset = rng.next() >> rng.below(64);
      }
      if (rng.chance(20)) wave_size = 128 + rng.below(512);
      rec[at] = std::byte(rng.chance(10) ? rng.below(256) : 1);
      std::memcpy(rec + at + 1, &wave_offset, 8);
      std::memcpy(rec + at + 9, &wave_size, 4);
      const float floats[4] = {float(rng.below(100000)) / 7.0f, float(rng.around(1000)) * 1e-3f,
                               float(rng.around(1000)) * 1e-3f, -0.5f};
      std::memcpy(rec + at + 13, floats, 16);
      at += 29;
    }
    for (std::size_t k = 0; k < spec.extra_bytes; ++k) {
      std::uint8_t v;
      switch (k % 4) {
        case 0:
          v = 42;
          break;  // never changes
        case 1:
          v = std::uint8_t(i);
          break;  // a counter
        case 2:
          v = std::uint8_t(rng.next());
          break;  // noise
        default:
          v = std::uint8_t(rng.chance(50) ? rng.next() : 0);
          break;  // mostly zero
      }
      rec[at + k] = std::byte(v);
    }
    if (quiet_start) quiet_fields.assign(rec, rec + length);
  }
  return out;
}

// The layered items (LAS 1.4 R15 formats 6-10, as LASzip lists them) of a format with `extra`
// extra bytes, at one layered version (3 or 4).
inline std::vector<LazItem> layeredItemsFor(int format, std::size_t extra, std::uint16_t version) {
  std::vector<LazItem> items{{ItemType::Point14, 30, version}};
  if (format == 7) items.push_back({ItemType::Rgb14, 6, version});
  if (format == 8 || format == 10) items.push_back({ItemType::RgbNir14, 8, version});
  if (format == 9 || format == 10) items.push_back({ItemType::Wavepacket14, 29, version});
  if (extra != 0) items.push_back({ItemType::Byte14, std::uint16_t(extra), version});
  return items;
}

}  // namespace parallax::laz::testing
