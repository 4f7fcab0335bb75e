// `parallax convert IN... -o OUT.copc.laz`: point files to a COPC file, through the out-of-core
// builder (potree_converter.h: same stages, same sampling, within the same memory budget) and
// then the COPC writer (copc_writer.h), which re-encodes the built tree node by node. The tree is
// built into a temporary Potree directory beside the output (removed at the end, also on
// failure) and the COPC file is written under a temporary name and renamed.
//
// The CRS of LAS and LAZ inputs is carried over as WKT (COPC requires WKT): the first input's
// WKT record. An input whose CRS is GeoTIFF keys only cannot be carried (turning EPSG codes into
// WKT needs a CRS database); that, and inputs with different CRSs, are reported in `notes`.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "lod/copc_writer.h"
#include "lod/potree_converter.h"

namespace parallax {

struct CopcConvertOptions {
  PotreeConvertOptions potree;  // the builder's options; `progress` also gets a "writing COPC" bar
  int page_levels = 4;          // levels a hierarchy page covers
};

struct CopcConvertResult {
  PotreeConvertResult build;
  CopcWriteResult copc;
  double seconds_write = 0, seconds_total = 0;
  std::vector<std::string> notes;  // what was not carried over, one phrase each
};

// The CRS records (WKT) and GPS time type of the LAS and LAZ inputs, and notes on what cannot be
// carried. Inputs of other formats are skipped.
struct CarriedCrs {
  std::vector<LasVlr> vlrs;
  std::optional<bool> gps_time_standard;
  std::vector<std::string> notes;
};
CarriedCrs crsOfInputs(const std::vector<ConvertInput>& inputs);

// The points the COPC writer encodes at once for a memory budget (a quarter of it).
std::uint64_t copcBatchPoints(std::uint64_t memory_bytes);

// Throws as convertToPotree and writeCopc do.
CopcConvertResult convertToCopc(const std::vector<ConvertInput>& inputs,
                                const std::filesystem::path& output,
                                const CopcConvertOptions& options = {});

}  // namespace parallax
