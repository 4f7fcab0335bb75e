#include "io/e57/e57_records.h"

#include <bit>
#include <cstring>

#include "core/error.h"

namespace parallax {
namespace {

constexpr std::size_t kSectionHeaderSize = 32;
constexpr std::size_t kPadding = 16;        // after a packet's bytes: room for 9-byte loads
constexpr std::size_t kRecentPackets = 48;  // at most 3 MB
// Packet types; 0, an index packet, is stepped over like an empty one.
constexpr std::uint8_t kDataPacket = 1, kEmptyPacket = 2;

std::uint64_t load64(const std::byte* p) {
  std::uint64_t v;
  std::memcpy(&v, p, 8);
  if constexpr (std::endian::native == std::endian::big) v = __builtin_bswap64(v);
  return v;
}
std::uint16_t load16(const std::byte* p) {
  return std::uint16_t(p[0]) | std::uint16_t(p[1]) << 8;
}

}  // namespace

struct E57RecordDecoder::Packet {
  std::uint64_t logical = 0;  // offset of the packet
  std::uint64_t next = 0;     // logical offset of the packet after it
  std::vector<std::byte> bytes;
  std::vector<std::uint32_t> stream_start;  // per field, into bytes
  std::vector<std::uint32_t> stream_length;
};

struct E57RecordDecoder::Channel {
  const E57Field* field = nullptr;
  std::shared_ptr<const Packet> packet;  // null before the first packet
  std::uint64_t next_packet = 0;         // logical offset of the next packet to look at
  const std::byte* data = nullptr;       // this field's buffer in `packet`
  std::uint64_t bit = 0;                 // next bit to read in `data`
  std::uint64_t bits_in_buffer = 0;
  std::uint64_t records_done = 0;
};

E57RecordDecoder::E57RecordDecoder(const E57Pages& pages, const E57Scan& scan,
                                   std::size_t scan_index)
    : pages_(pages), scan_(scan), scan_index_(scan_index), remaining_(scan.record_count) {
  const std::string element = "compressed vector section of scan " + std::to_string(scan_index);
  auto bad = [&](const std::string& property, const std::string& expected,
                 const std::string& found) {
    throw InputError({.file = pages.name(),
                      .byte_offset = scan.section_offset,
                      .element = element,
                      .property = property,
                      .expected = expected,
                      .found = found});
  };
  if (scan.section_offset % kE57PageSize >= kE57PageData ||
      scan.section_offset >= pages.physicalSize()) {
    bad("fileOffset", "an offset inside the file's data",
        std::to_string(scan.section_offset) + " (file of " + std::to_string(pages.physicalSize()) +
            " bytes)");
  }
  const std::uint64_t start = e57PhysicalToLogical(scan.section_offset);
  std::byte header[kSectionHeaderSize];
  pages.read(start, header, "compressed vector section header");
  if (header[0] != std::byte{1}) {
    bad("section id", "1 (compressed vector)", std::to_string(int(header[0])));
  }
  const std::uint64_t length = load64(header + 8);
  const std::uint64_t data_physical = load64(header + 16);
  if (length < kSectionHeaderSize || length > pages.logicalSize() - start) {
    bad("sectionLogicalLength", "a length inside the file", std::to_string(length));
  }
  section_end_ = start + length;
  const bool data_in_page = data_physical % kE57PageSize < kE57PageData;
  const std::uint64_t data_logical = e57PhysicalToLogical(data_physical);
  if (scan.record_count > 0 && (!data_in_page || data_logical < start + kSectionHeaderSize ||
                                data_logical >= section_end_)) {
    bad("dataPhysicalOffset", "an offset inside the section", std::to_string(data_physical));
  }
  channels_.resize(scan.fields.size());
  for (std::size_t f = 0; f < scan.fields.size(); ++f) {
    channels_[f].field = &scan.fields[f];
    channels_[f].next_packet = data_logical;
    if (scan.fields[f].kind == E57Field::Kind::String && scan.record_count > 0) {
      throw InputError({.file = pages.name(),
                        .byte_offset = scan.section_offset,
                        .element = element,
                        .property = scan.fields[f].name,
                        .expected = "number fields (Parallax does not read String fields)",
                        .found = "a String field"});
    }
  }
}

E57RecordDecoder::~E57RecordDecoder() = default;

std::shared_ptr<const E57RecordDecoder::Packet> E57RecordDecoder::packetAt(std::uint64_t logical) {
  if (auto found = packets_.find(logical); found != packets_.end()) {
    if (auto packet = found->second.lock()) return packet;
  }
  if (packets_.size() > 4 * channels_.size() + 8)
    std::erase_if(packets_, [](const auto& entry) { return entry.second.expired(); });
  const std::string element = "packet of scan " + std::to_string(scan_index_);
  auto bad = [&](const std::string& property, const std::string& expected,
                 const std::string& found) {
    throw InputError({.file = pages_.name(),
                      .byte_offset = e57LogicalToPhysical(logical),
                      .element = element,
                      .property = property,
                      .expected = expected,
                      .found = found});
  };
  if (logical + 4 > section_end_) {
    bad("packet header", "a packet inside the section", "the section's end");
  }
  std::byte head[4];
  pages_.read(logical, head, "packet header");
  const auto type = std::uint8_t(head[0]);
  const std::uint64_t length = std::uint64_t(load16(head + 2)) + 1;
  if (type > kEmptyPacket)
    bad("packet type", "0 (index), 1 (data) or 2 (empty)", std::to_string(type));
  if (logical + length > section_end_) {
    bad("packetLogicalLengthMinus1", "a packet ending inside the section",
        std::to_string(length) + " bytes");
  }
  auto packet = std::make_shared<Packet>();
  packet->logical = logical;
  packet->next = logical + length;
  if (type == kDataPacket) {
    packet->bytes.resize(length + kPadding);
    pages_.read(logical, {packet->bytes.data(), length}, "data packet");
    const std::size_t streams = length >= 6 ? load16(packet->bytes.data() + 4) : 0;
    if (length < 6 || streams != channels_.size()) {
      bad("bytestreamCount", std::to_string(channels_.size()) + " (the fields of the prototype)",
          std::to_string(streams));
    }
    std::uint64_t at = 6 + 2 * streams;
    if (at > length) bad("bytestreamBufferLength", "lengths inside the packet", "past its end");
    packet->stream_start.resize(streams);
    packet->stream_length.resize(streams);
    for (std::size_t s = 0; s < streams; ++s) {
      const std::uint16_t n = load16(packet->bytes.data() + 6 + 2 * s);
      packet->stream_start[s] = std::uint32_t(at);
      packet->stream_length[s] = n;
      at += n;
    }
    if (at > length) {
      bad("bytestreamBufferLength",
          "buffers that fit the packet's " + std::to_string(length) + " bytes",
          std::to_string(at) + " bytes");
    }
  }
  packets_[logical] = packet;
  recent_.push_back(packet);
  if (recent_.size() > kRecentPackets) recent_.pop_front();
  return packet;
}

void E57RecordDecoder::advance(Channel& channel) {
  // The next data packet with bytes for this field; index and empty packets are stepped over.
  while (true) {
    if (channel.next_packet >= section_end_) {
      throw InputError(
          {.file = pages_.name(),
           .byte_offset =
               e57LogicalToPhysical(channel.packet ? channel.packet->logical : section_end_),
           .element = "scan " + std::to_string(scan_index_),
           .property = channel.field->name,
           .expected = std::to_string(scan_.record_count) + " records (recordCount)",
           .found = "the bytestream ends after " + std::to_string(channel.records_done),
           .hint = "the file is truncated or its recordCount is wrong"});
    }
    channel.packet = packetAt(channel.next_packet);
    channel.next_packet = channel.packet->next;
    if (channel.packet->stream_start.empty()) continue;  // index or empty packet
    const std::size_t f = std::size_t(channel.field - scan_.fields.data());
    channel.data = channel.packet->bytes.data() + channel.packet->stream_start[f];
    channel.bits_in_buffer = std::uint64_t(channel.packet->stream_length[f]) * 8;
    channel.bit = 0;
    if (channel.bits_in_buffer > 0) return;
  }
}

namespace {

// Decodes `count` records of `bits` bits (1..64) from `data` at `bit` into raw values; the
// caller made sure they lie inside the buffer (plus kPadding bytes readable after it).
template <class Convert>
void unpack(const std::byte* data, std::uint64_t bit, unsigned bits, std::size_t count, double* out,
            Convert convert) {
  if (bits == 64) {
    for (std::size_t i = 0; i < count; ++i, bit += 64) {
      const std::byte* p = data + (bit >> 3);
      const unsigned shift = unsigned(bit & 7);
      std::uint64_t v = load64(p) >> shift;
      if (shift) v |= std::uint64_t(p[8]) << (64 - shift);
      out[i] = convert(v);
    }
    return;
  }
  const std::uint64_t mask = (std::uint64_t{1} << bits) - 1;
  if (bits <= 56) {
    for (std::size_t i = 0; i < count; ++i, bit += bits) {
      out[i] = convert((load64(data + (bit >> 3)) >> (bit & 7)) & mask);
    }
    return;
  }
  for (std::size_t i = 0; i < count; ++i, bit += bits) {
    const std::byte* p = data + (bit >> 3);
    const unsigned shift = unsigned(bit & 7);
    std::uint64_t v = load64(p) >> shift;
    if (shift) v |= std::uint64_t(p[8]) << (64 - shift);
    out[i] = convert(v & mask);
  }
}

}  // namespace

void E57RecordDecoder::decode(std::size_t count, const std::vector<bool>& wanted,
                              std::vector<std::vector<double>>& values) {
  values.resize(channels_.size());
  std::vector<double> dropped;
  for (std::size_t f = 0; f < channels_.size(); ++f) {
    Channel& channel = channels_[f];
    const E57Field& field = *channel.field;
    std::vector<double>& out = wanted[f] ? values[f] : dropped;
    out.resize(count);
    auto run = [&](auto convert) {
      if (field.bits == 0) {
        std::fill(out.begin(), out.end(), convert(0));
        channel.records_done += count;
        return;
      }
      std::size_t i = 0;
      while (i < count) {
        const std::uint64_t whole = (channel.bits_in_buffer - channel.bit) / field.bits;
        const std::size_t n = std::size_t(std::min<std::uint64_t>(whole, count - i));
        if (n > 0) {
          unpack(channel.data, channel.bit, field.bits, n, out.data() + i, convert);
          channel.bit += std::uint64_t(n) * field.bits;
          channel.records_done += n;
          i += n;
          continue;
        }
        // A record straddling this buffer's end (or none left in it): gather it bit by bit.
        std::uint64_t value = 0;
        unsigned got = 0;
        while (got < field.bits) {
          if (channel.bit >= channel.bits_in_buffer) advance(channel);
          const unsigned in_byte = unsigned(channel.bit & 7);
          const unsigned take = std::min<unsigned>(
              {8 - in_byte, field.bits - got, unsigned(channel.bits_in_buffer - channel.bit)});
          const std::uint64_t byte = std::uint64_t(channel.data[channel.bit >> 3]) >> in_byte;
          value |= (byte & ((std::uint64_t{1} << take) - 1)) << got;
          got += take;
          channel.bit += take;
        }
        out[i++] = convert(value);
        ++channel.records_done;
      }
    };
    switch (field.kind) {
      case E57Field::Kind::Float:
        if (field.single_precision) {
          run([](std::uint64_t raw) { return double(std::bit_cast<float>(std::uint32_t(raw))); });
        } else {
          run([](std::uint64_t raw) { return std::bit_cast<double>(raw); });
        }
        break;
      case E57Field::Kind::Integer: {
        const std::uint64_t minimum = std::uint64_t(field.minimum);
        run([minimum](std::uint64_t raw) { return double(std::int64_t(minimum + raw)); });
        break;
      }
      case E57Field::Kind::ScaledInteger: {
        const std::uint64_t minimum = std::uint64_t(field.minimum);
        const double scale = field.scale, offset = field.offset;
        run([=](std::uint64_t raw) {
          return double(std::int64_t(minimum + raw)) * scale + offset;
        });
        break;
      }
      case E57Field::Kind::String:
        break;  // refused by the constructor
    }
  }
  remaining_ -= count;
}

}  // namespace parallax
