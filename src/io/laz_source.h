// An opened LAZ file (internal to io: the LAZ reader, its chunk reader and the preview): the
// header, where every chunk is and how many points it holds, and the decoding of one chunk into
// raw LAS records, with every failure turned into an InputError that names the file, the chunk,
// its byte offset and the first point affected.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/byte_source.h"
#include "core/column.h"
#include "io/las_header.h"
#include "io/laz/chunk_codec.h"
#include "io/laz/laz_layout.h"
#include "io/read_ahead.h"

namespace parallax {

// LASzip's "LAS 1.4 compatibility mode": points of formats 6-10 stored as formats 1, 3, 4 or 5
// plus five (seven with NIR) extra bytes, so that LAZ readers of LAS 1.3 could read them. Where
// the new attributes sit in the legacy record (laz_compatibility.cpp).
struct LazCompatibility {
  int legacy_format = 0;
  std::size_t legacy_length = 0;
  std::size_t scan_angle = 0, extended_returns = 0, classification = 0, flags_and_channel = 0;
  std::optional<std::size_t> nir;
  std::vector<std::pair<std::size_t, std::size_t>> user_extra;  // (legacy offset, size) runs
};

struct LazSource {
  LazSource(std::unique_ptr<ByteSource> bytes, LasHeader file_header)
      : in(std::move(bytes)), header(std::move(file_header)) {}

  std::unique_ptr<ByteSource> in;  // the file (local, in memory or a URL); never null
  LasHeader header;   // what the file's header says (point format without LASzip's bits)
  LasHeader records;  // the records the decoder hands out: `header`, or 1.4's in compatibility
  laz::LaszipVlr vlr;
  std::vector<laz::LazChunk> chunks;
  std::uint64_t data_end = 0;  // where the chunks must end (the chunk table, EVLRs or the end)
  // No usable chunk table, fixed chunk size: the chunks' offsets are found by decoding them in
  // order (`offsets_known` of them are known so far; the first always is).
  bool sequential = false;
  std::size_t offsets_known = 0;
  std::string table_note;  // why the table was not used, for `info`
  std::optional<LazCompatibility> compatibility;
  std::mutex sequential_mutex;  // guards `chunks` offsets while they are being found

  std::size_t rawRecordLength() const { return header.record_length; }

  // A remote file's chunks hinted ahead of the decoders (io/read_ahead.h): a reader names the
  // chunks it is about to decode, in order, and LazChunkDecoder::decode marks each one read.
  // Called between decodes, never during them; nothing for a local file or a `sequential` one
  // (whose chunks' ends are not known).
  void planChunkReads(const std::vector<std::size_t>& indices);
  std::unique_ptr<ReadAhead> read_ahead;
  std::vector<std::size_t> read_ahead_slot;  // chunk index -> its place in the plan, or npos
};

// Opens a LAZ file whose header `header` has been parsed (header.laszip set). Reads and checks
// the chunk table. Throws InputError for an unknown compressor, coder or item, a record length
// that does not match the items, a missing or lying chunk table that cannot be recovered, and
// point counts the file cannot hold.
std::unique_ptr<LazSource> openLazSource(std::unique_ptr<ByteSource> in, LasHeader header);

// One thread's decoding state: the codec and its buffers (reused from chunk to chunk).
class LazChunkDecoder {
 public:
  // `fields` (laz::fields::k*): the groups to decode, where the codec can skip the others
  // (layered chunks; see laz::ChunkDecoder::selectFields); `path`: the specialised chunk loop
  // or the general one (benchmarks compare them).
  explicit LazChunkDecoder(const LazSource& source, std::uint32_t fields = laz::fields::kAll,
                           laz::DecoderPath path = laz::DecoderPath::kSpecialised);
  ~LazChunkDecoder();

  // Decodes chunk `index` and returns its records (records.record_length bytes each; valid until
  // the next call). Chunks of a `sequential` source must be decoded in order (the caller holds
  // them to that).
  const std::byte* decode(LazSource& source, std::size_t index);

 private:
  std::unique_ptr<laz::ChunkDecoder> codec_;
  std::vector<std::byte> compressed_;
  ByteBuffer raw_, converted_;
};

// For messages: "LAZ chunk 3 of 20 (points 100000-149999)".
std::string describeLazChunk(const LazSource& source, std::size_t index);

// Recognises the compatibility mode (a "lascompatible" VLR and the extra bytes that hold the new
// attributes) and returns the records' header (format 6-10) and where the attributes are; no
// value for an ordinary file. Throws InputError for a compatibility VLR it cannot follow.
std::optional<LazCompatibility> detectLazCompatibility(const LasHeader& header,
                                                       const std::string& file, LasHeader& records);
// Turns `count` legacy records into 1.4 records.
void convertLazCompatibility(const LazCompatibility& compatibility, const LasHeader& records,
                             const std::byte* legacy, std::size_t count, std::byte* out);

}  // namespace parallax
