// A LAZ file's chunks decoded into raw LAS records and dropped, without building columns: the
// codec alone, as `parallax bench laz` times it beside LASzip's laszip_read_point loop (which also
// hands out records, not columns).
#pragma once

#include <cstdint>
#include <filesystem>

#include "io/laz/chunk_codec.h"

namespace parallax {

struct LazDecodeOptions {
  std::uint32_t fields = laz::fields::kAll;  // the groups decoded (layered chunks skip the rest)
  laz::DecoderPath path = laz::DecoderPath::kSpecialised;
  bool parallel = false;  // chunks on every core TBB allows (else the calling thread only)
};

struct LazDecodeResult {
  std::uint64_t points = 0;
  // A sum over the decoded records' x (so that no decode can be optimised away; the same for
  // every path and every choice of fields).
  std::uint64_t checksum = 0;
};

// Throws InputError for a file that is not LAZ or is damaged.
LazDecodeResult decodeLazRecords(const std::filesystem::path& file,
                                 const LazDecodeOptions& options = {});

}  // namespace parallax
