#include "io/laz_source.h"

#include <algorithm>
#include <cstring>

#include "core/error.h"
#include "io/laz/layered_codec.h"
#include "io/laz/pointwise_codec.h"

namespace parallax {
namespace {

// The most points a byte of compressed stream can hold. Every point codes at least a few
// adaptive symbols, and no model gives a symbol a probability above 1 - 2^-13 (bits) or
// 1 - (n - 1)/2^15 (n symbols), so a point costs at least about 0.006 bits (1 400 points a byte);
// twice that is the bound. It only caps what a lying count can make the reader allocate: real
// files hold a few bytes per point.
constexpr std::uint64_t kMaxPointsPerByte = 4096;

[[noreturn]] void fail(const LazSource& s, std::uint64_t offset, const std::string& element,
                       const std::string& expected, const std::string& found,
                       const std::string& hint = "") {
  throw InputError({.file = s.in->name(),
                    .byte_offset = offset,
                    .element = element,
                    .expected = expected,
                    .found = found,
                    .hint = hint});
}

std::string itemList(const laz::LaszipVlr& vlr) {
  std::string text;
  for (const laz::LazItem& item : vlr.items) {
    if (!text.empty()) text += ", ";
    text += "type " + std::to_string(unsigned(item.type)) + " (" + std::to_string(item.size) +
            " bytes, v" + std::to_string(item.version) + ")";
  }
  return text;
}

std::uint64_t load64(const ByteSource& in, std::uint64_t offset) {
  std::uint64_t value;
  in.read(offset, std::as_writable_bytes(std::span(&value, 1)));
  return value;
}
std::uint32_t load32(const ByteSource& in, std::uint64_t offset) {
  std::uint32_t value;
  in.read(offset, std::as_writable_bytes(std::span(&value, 1)));
  return value;
}

// How many fixed-size chunks hold `points`: counted before the list is made, which a lying
// point count could make larger than memory.
std::uint64_t fixedChunkCount(std::uint64_t points, std::uint64_t chunk_size) {
  return chunk_size == 0 ? 0 : points / chunk_size + (points % chunk_size != 0);
}

// Fixed-size chunks: the points of each (the last one holds the rest).
std::vector<laz::LazChunk> fixedChunks(std::uint64_t points, std::uint64_t chunk_size) {
  std::vector<laz::LazChunk> chunks;
  for (std::uint64_t first = 0; first < points; first += chunk_size) {
    chunks.push_back({.first_point = first, .points = std::min(chunk_size, points - first)});
  }
  return chunks;
}

// Reads the chunk table; returns false (with `note`) when there is none to use. Throws for a
// table that is there but contradicts the header.
bool readChunkTable(LazSource& s, std::uint64_t chunks_start, std::string& note) {
  const ByteSource& in = *s.in;
  const std::uint64_t data_start = s.header.point_data_offset;
  std::uint64_t table = load64(in, data_start);
  if (table == data_start) {
    note = "the writer was interrupted before it wrote the chunk table";
    return false;
  }
  if (table == ~std::uint64_t(0)) {  // -1: written at the end of the file instead
    if (in.size() < chunks_start + 8) {
      note = "the chunk table's offset should be the file's last 8 bytes, but the file ends";
      return false;
    }
    table = load64(in, in.size() - 8);
  }
  const std::uint64_t end = s.data_end;
  if (table < chunks_start || table > end || end - table < 8) {
    note = "the chunk table offset " + std::to_string(std::int64_t(table)) +
           " is outside the point data (bytes " + std::to_string(chunks_start) + " to " +
           std::to_string(end) + ")";
    return false;
  }
  const std::uint32_t version = load32(in, table);
  const std::uint32_t count = load32(in, table + 4);
  if (version != 0) {
    note = "the chunk table at byte " + std::to_string(table) + " has version " +
           std::to_string(version) + " (expected 0)";
    return false;
  }
  // Every chunk starts with its first point's raw record: no more chunks than that allows.
  const std::uint64_t max_chunks =
      (table - chunks_start) / std::max<std::size_t>(1, s.rawRecordLength());
  if (count > max_chunks) {
    fail(s, table + 4, "LAZ chunk table",
         "at most " + std::to_string(max_chunks) + " chunks in the " +
             std::to_string(table - chunks_start) + " bytes of chunk data",
         std::to_string(count) + " chunks", "the chunk table is damaged");
  }
  const bool variable = s.vlr.chunk_size == laz::kVariableChunkSize;
  const std::uint64_t stream_size = std::min<std::uint64_t>(end - table - 8, 16ull * count + 64);
  std::vector<std::byte> stream(stream_size);
  in.read(table + 8, stream, {.element = "LAZ chunk table"});
  std::vector<std::uint32_t> points, bytes;
  if (!laz::decodeChunkTable(stream, count, variable, points, bytes)) {
    note = "the chunk table at byte " + std::to_string(table) + " is truncated or corrupt";
    return false;
  }
  std::vector<laz::LazChunk> chunks;
  if (variable) {
    std::uint64_t first = 0;
    for (std::uint32_t i = 0; i < count; ++i) {
      chunks.push_back({.first_point = first, .points = points[i]});
      first += points[i];
    }
    if (first != s.records.point_count) {
      fail(s, table, "LAZ chunk table",
           "point counts adding up to the header's " + std::to_string(s.records.point_count),
           std::to_string(first) + " points in " + std::to_string(count) + " chunks",
           "the header's point count or the chunk table is wrong");
    }
  } else {
    const std::uint64_t expected = fixedChunkCount(s.records.point_count, s.vlr.chunk_size);
    if (expected != count) {
      fail(s, table + 4, "LAZ chunk table",
           std::to_string(expected) + " chunks of " + std::to_string(s.vlr.chunk_size) +
               " points for the header's " + std::to_string(s.records.point_count) + " points",
           std::to_string(count) + " chunks",
           "the header's point count or the chunk table is wrong");
    }
    chunks = fixedChunks(s.records.point_count, s.vlr.chunk_size);
  }
  std::uint64_t offset = chunks_start;
  for (std::uint32_t i = 0; i < count; ++i) {
    laz::LazChunk& chunk = chunks[i];
    chunk.offset = offset;
    chunk.bytes = bytes[i];
    const bool fits = chunk.bytes <= table - offset;
    const bool holds = chunk.bytes >= s.rawRecordLength() &&
                       chunk.points <= 1 + kMaxPointsPerByte * (chunk.bytes - s.rawRecordLength());
    if (!fits || (chunk.points > 0 && !holds)) {
      fail(s, table,
           "LAZ chunk table, chunk " + std::to_string(i + 1) + " of " + std::to_string(count),
           fits ? "enough bytes for " + std::to_string(chunk.points) + " points"
                : "a chunk ending before the chunk table at byte " + std::to_string(table),
           std::to_string(chunk.bytes) + " bytes at byte " + std::to_string(offset),
           "the chunk table is damaged");
    }
    offset += chunk.bytes;
  }
  s.chunks = std::move(chunks);
  s.data_end = table;
  return true;
}

}  // namespace

std::unique_ptr<LazSource> openLazSource(std::unique_ptr<ByteSource> in, LasHeader header) {
  auto s = std::make_unique<LazSource>(std::move(in), std::move(header));
  s->vlr = *s->header.laszip;
  const laz::LaszipVlr& vlr = s->vlr;
  const std::uint64_t vlr_at = s->header.laszip_vlr_offset;
  if (vlr.coder != 0) {
    fail(*s, vlr_at + 2, "laszip VLR", "coder 0 (arithmetic, the only one defined)",
         "coder " + std::to_string(vlr.coder));
  }
  if (vlr.compressor < 1 || vlr.compressor > 3) {
    fail(*s, vlr_at, "laszip VLR",
         "compressor 1 (point-wise), 2 (point-wise chunked) or 3 (layered chunked)",
         "compressor " + std::to_string(vlr.compressor),
         vlr.compressor == 0 ? "the points are not compressed although the header says LAZ" : "");
  }
  if (vlr.recordLength() != s->header.record_length) {
    fail(*s, vlr_at, "laszip VLR",
         "items adding up to the header's record length of " +
             std::to_string(s->header.record_length) + " bytes",
         std::to_string(vlr.recordLength()) + " bytes: " + itemList(vlr));
  }
  if (vlr.compressor != 1 && vlr.chunk_size == 0) {
    fail(*s, vlr_at + 12, "laszip VLR", "a chunk size of at least 1 point", "0");
  }
  s->records = s->header;
  s->compatibility = detectLazCompatibility(s->header, s->in->name(), s->records);

  // Where the compressed points end: EVLRs after them, or the end of the file.
  s->data_end = s->in->size();
  if (s->header.evlr_count != 0 && s->header.evlr_offset > s->header.point_data_offset &&
      s->header.evlr_offset < s->data_end) {
    s->data_end = s->header.evlr_offset;
  }
  const std::uint64_t data_start = s->header.point_data_offset;
  const std::uint64_t points = s->records.point_count;
  if (vlr.compressor == 1) {
    // One stream of every point, no chunk table.
    if (points > 0) {
      const std::uint64_t bytes = s->data_end - std::min(s->data_end, data_start);
      if (bytes < s->rawRecordLength() ||
          points > 1 + kMaxPointsPerByte * (bytes - s->rawRecordLength())) {
        fail(*s, data_start, "point data",
             "enough bytes for the header's " + std::to_string(points) + " points",
             std::to_string(bytes) + " bytes", "the file is truncated or its point count is wrong");
      }
      s->chunks.push_back(
          {.offset = data_start, .bytes = bytes, .first_point = 0, .points = points});
    }
    s->offsets_known = s->chunks.size();
    return s;
  }
  if (s->data_end < data_start + 8) {
    fail(*s, data_start, "point data", "the 8-byte chunk table offset of a chunked LAZ file",
         "the end of the file", "the file is truncated");
  }
  const std::uint64_t chunks_start = data_start + 8;
  std::string note;
  if (readChunkTable(*s, chunks_start, note)) {
    s->offsets_known = s->chunks.size();
    return s;
  }
  // No usable table. With a fixed chunk size every chunk's point count is known and its end is
  // where its decoder stops, so the chunks can be found by decoding them in order. The bound on
  // the points the bytes can hold still applies.
  if (vlr.chunk_size == laz::kVariableChunkSize || vlr.compressor == 3) {
    fail(*s, data_start, "LAZ chunk table",
         "a chunk table (this file's chunks have " +
             std::string(vlr.compressor == 3 ? "layered streams" : "variable sizes") +
             ", which cannot be found without it)",
         note, "the file was not written completely; write it again from its source");
  }
  const std::uint64_t bytes = s->data_end - chunks_start;
  if (points > 0 && (bytes < s->rawRecordLength() || points > kMaxPointsPerByte * bytes)) {
    fail(*s, chunks_start, "point data",
         "enough bytes for the header's " + std::to_string(points) + " points",
         std::to_string(bytes) + " bytes", note);
  }
  // Every chunk starts with its first point's raw record.
  const std::uint64_t chunk_count = fixedChunkCount(points, vlr.chunk_size);
  if (chunk_count > bytes / std::max<std::size_t>(1, s->rawRecordLength())) {
    fail(*s, chunks_start, "point data",
         "enough bytes for the " + std::to_string(chunk_count) + " chunks of " +
             std::to_string(vlr.chunk_size) + " points the header's " + std::to_string(points) +
             " points take (a raw record each at least)",
         std::to_string(bytes) + " bytes", note);
  }
  s->chunks = fixedChunks(points, vlr.chunk_size);
  if (!s->chunks.empty()) s->chunks[0].offset = chunks_start;
  s->sequential = true;
  s->offsets_known = s->chunks.empty() ? 0 : 1;
  s->table_note = note + "; its chunks are found by decoding them in order";
  return s;
}

std::string describeLazChunk(const LazSource& source, std::size_t index) {
  const laz::LazChunk& chunk = source.chunks[index];
  std::string text =
      "LAZ chunk " + std::to_string(index + 1) + " of " + std::to_string(source.chunks.size());
  if (chunk.points > 0) {
    text += " (points " + std::to_string(chunk.first_point) + "-" +
            std::to_string(chunk.first_point + chunk.points - 1) + ")";
  }
  return text;
}

LazChunkDecoder::LazChunkDecoder(const LazSource& source, std::uint32_t fields,
                                 laz::DecoderPath path) {
  try {
    codec_ = source.vlr.compressor == 3 ? laz::makeLayeredDecoder(source.vlr.items, path)
                                        : laz::makePointwiseDecoder(source.vlr.items, path);
    codec_->selectFields(fields);
  } catch (const laz::UnsupportedItems& e) {
    throw InputError({.file = source.in->name(),
                      .byte_offset = source.header.laszip_vlr_offset,
                      .element = "laszip VLR",
                      .expected = "LAZ items Parallax decodes (compressor " +
                                  std::to_string(source.vlr.compressor) + ")",
                      .found = e.what()});
  }
}

LazChunkDecoder::~LazChunkDecoder() = default;

void LazSource::planChunkReads(const std::vector<std::size_t>& indices) {
  // Chunks of 50 000 points are 0.3-1 MB compressed: 8 in flight ahead of two decoders.
  constexpr std::size_t kChunksAhead = 8;
  read_ahead.reset();
  if (in->local() || sequential || indices.size() < 2) return;
  std::vector<ByteRange> plan;
  read_ahead_slot.assign(chunks.size(), std::size_t(-1));
  for (std::size_t index : indices) {
    read_ahead_slot[index] = plan.size();
    plan.push_back({chunks[index].offset, chunks[index].bytes});
  }
  read_ahead = std::make_unique<ReadAhead>(*in, std::move(plan), kChunksAhead);
}

const std::byte* LazChunkDecoder::decode(LazSource& s, std::size_t index) {
  laz::LazChunk chunk;
  if (s.sequential) {
    const std::lock_guard lock(s.sequential_mutex);
    chunk = s.chunks[index];
  } else {
    chunk = s.chunks[index];
  }
  const std::size_t length = s.rawRecordLength();
  const std::size_t raw_bytes = std::size_t(chunk.points) * length;
  if (raw_.size() < raw_bytes) raw_ = ByteBuffer(raw_bytes);
  std::uint64_t window = chunk.bytes;
  if (s.sequential) {
    // The chunk's end is unknown: a window of the data large enough for any real chunk
    // (compressed points are smaller than raw ones; twice raw plus a margin).
    window = std::min<std::uint64_t>(s.data_end - std::min(s.data_end, chunk.offset),
                                     2 * raw_bytes + 4096);
  }
  compressed_.resize(std::size_t(window));
  s.in->read(chunk.offset, compressed_, {.element = "LAZ chunk"});
  if (s.read_ahead && index < s.read_ahead_slot.size() &&
      s.read_ahead_slot[index] != std::size_t(-1)) {
    s.read_ahead->finished(s.read_ahead_slot[index]);
  }
  try {
    if (s.sequential) {
      const std::size_t used = codec_->decodeUnsized(compressed_, chunk.points, raw_.data());
      const std::lock_guard lock(s.sequential_mutex);
      s.chunks[index].bytes = used;
      if (index + 1 < s.chunks.size()) {
        s.chunks[index + 1].offset = chunk.offset + used;
        s.offsets_known = std::max(s.offsets_known, index + 2);
      }
    } else {
      codec_->decode(compressed_, chunk.points, raw_.data());
    }
  } catch (const laz::ChunkCorrupt& e) {
    // An arithmetic stream has no checksums: a decoder notices damage only when it runs out of
    // bytes or meets an impossible value, possibly some way past it. Every point of the chunk
    // from its first on may be wrong.
    const std::uint64_t point = chunk.first_point + e.point();
    throw InputError(
        {.file = s.in->name(),
         .byte_offset = chunk.offset,
         .element = describeLazChunk(s, index),
         .expected = "a valid compressed chunk of " + std::to_string(chunk.points) + " points in " +
                     (s.sequential ? "at most the " + std::to_string(window) +
                                         " bytes from its start on (its size unknown without the "
                                         "chunk table)"
                                   : std::to_string(chunk.bytes) + " bytes"),
         .found = std::string(e.what()) + ", noticed at point " + std::to_string(point) +
                  "; first point affected: " + std::to_string(chunk.first_point) +
                  " (the chunk's first)",
         .hint = s.sequential ? s.table_note + "; the file is damaged (truncated or altered)"
                              : "the file is damaged (truncated or altered)"});
  }
  if (!s.compatibility) return raw_.data();
  const std::size_t out_bytes = std::size_t(chunk.points) * s.records.record_length;
  if (converted_.size() < out_bytes) converted_ = ByteBuffer(out_bytes);
  convertLazCompatibility(*s.compatibility, s.records, raw_.data(), chunk.points,
                          converted_.data());
  return converted_.data();
}

}  // namespace parallax
