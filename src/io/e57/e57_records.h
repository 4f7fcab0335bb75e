// Decoding a scan's compressed vector section (ASTM E2807 section 11): the section header, then
// data packets (with index and empty packets between them, skipped), each holding one buffer per
// field of the record. A field's buffers, concatenated over the packets, are its bytestream: the
// records bit-packed one after another, least significant bit first, a record free to straddle
// bytes and packets. Fields advance at their own pace (a 1-bit field fills a packet far later
// than a double), so each keeps its own place in the packets; packets are read once and shared.
#pragma once

#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <span>
#include <vector>

#include "io/e57/e57_document.h"
#include "io/e57/e57_pages.h"

namespace parallax {

class E57RecordDecoder {
 public:
  // Reads and checks the section header of `scan` (InputError naming its offset when it is not a
  // compressed vector section or its lengths do not fit the file). `pages` and `scan` must
  // outlive the decoder.
  E57RecordDecoder(const E57Pages& pages, const E57Scan& scan, std::size_t scan_index);
  ~E57RecordDecoder();

  std::uint64_t remaining() const { return remaining_; }

  // Decodes the next `count` records (at most remaining()) of each field whose `wanted` flag is
  // set into `values[field]` (resized to `count`), as doubles (Integer: the integer; ScaledInteger:
  // raw * scale + offset; Float: the float). Fields not wanted are decoded and dropped, since a
  // field's place in its bytestream can only be found by decoding. Throws InputError when a
  // bytestream ends early or a packet is malformed (its offset and field named).
  void decode(std::size_t count, const std::vector<bool>& wanted,
              std::vector<std::vector<double>>& values);

  struct Packet;
  struct Channel;

 private:
  std::shared_ptr<const Packet> packetAt(std::uint64_t logical);
  void advance(Channel& channel);

  const E57Pages& pages_;
  const E57Scan& scan_;
  std::size_t scan_index_;
  std::uint64_t remaining_;
  std::uint64_t section_end_ = 0;  // logical
  std::vector<Channel> channels_;
  std::map<std::uint64_t, std::weak_ptr<const Packet>> packets_;
  // The packets read last, kept alive: fields are decoded one after the other over a batch of
  // records, so each packet of the batch is wanted again by the next field (read and checked
  // once, not once a field).
  std::deque<std::shared_ptr<const Packet>> recent_;
};

}  // namespace parallax
