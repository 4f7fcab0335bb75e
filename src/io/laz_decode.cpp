#include "io/laz_decode.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <atomic>
#include <cstring>
#include <memory>

#include "core/byte_source_opener.h"
#include "core/error.h"
#include "io/las_header.h"
#include "io/laz_source.h"

namespace parallax {

LazDecodeResult decodeLazRecords(const std::filesystem::path& file,
                                 const LazDecodeOptions& options) {
  LasHeader header = readLasHeader(file);
  if (!header.laszip) {
    throw InputError({.file = file.string(),
                      .byte_offset = 104,
                      .element = "header",
                      .property = "point data format",
                      .expected = "a LAZ file (LASzip's compression bit in the point format)",
                      .found = "an uncompressed LAS file"});
  }
  std::unique_ptr<LazSource> source =
      openLazSource(openByteSource(file.string()), std::move(header));
  const std::size_t length = source->records.record_length;
  tbb::enumerable_thread_specific<std::unique_ptr<LazChunkDecoder>> decoders;
  std::atomic<std::uint64_t> checksum{0};
  const auto decodeChunk = [&](std::size_t index) {
    std::unique_ptr<LazChunkDecoder>& decoder = decoders.local();
    if (!decoder) {
      decoder = std::make_unique<LazChunkDecoder>(*source, options.fields, options.path);
    }
    const std::byte* records = decoder->decode(*source, index);
    std::uint64_t sum = 0;
    for (std::uint64_t i = 0; i < source->chunks[index].points; ++i) {
      std::int32_t x;
      std::memcpy(&x, records + i * length, sizeof x);
      sum += std::uint64_t(std::int64_t(x));
    }
    checksum += sum;
  };
  if (options.parallel && !source->sequential) {
    tbb::parallel_for(std::size_t(0), source->chunks.size(), decodeChunk);
  } else {
    for (std::size_t i = 0; i < source->chunks.size(); ++i) decodeChunk(i);
  }
  return {source->records.point_count, checksum.load()};
}

}  // namespace parallax
