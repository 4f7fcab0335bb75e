// Conversion of point files (PLY, LAS, text; several merged into one) to a Potree 2.0 directory:
// metadata.json, hierarchy.bin and octree.bin in the DEFAULT encoding (potree_layout.h,
// potree_hierarchy_writer.h), which Potree 2 clients and potree_reader.h open.
//
// Out of core: the inputs are read in batches (three passes: scan, count, distribute), spilled
// into chunks on disk and each chunk built in memory (convert_stages.h), so memory stays within
// options.build.memory_bytes for any input size (text inputs too: io/text_reader.h's
// TextChunkReader).
// The budget is split in a quarter for the batch in flight and half for the chunk being built;
// a grid cell of 1/128 of the cube's edge holding more points than a chunk may hold is built
// whole anyway (a pathological density; noted in NOTES.md).
//
// The directory is written under a temporary sibling name (".NAME.partial-PID") and renamed to
// `output` only when complete; on failure the temporary directory is removed. An interrupted
// process (killed) leaves only the temporary name, never a directory that looks complete, and
// the next conversion to the same output removes it (io/partial_output.h) when its process is
// gone.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "io/coordinate_system.h"
#include "io/partial_output.h"
#include "lod/convert_stages.h"
#include "lod/octree_build_options.h"

namespace parallax {

struct PotreeConvertOptions {
  OctreeBuildOptions build;
  ProgressFactory progress;  // one bar per stage; empty: none
  std::string name;          // metadata "name"; empty: the output directory's name
  // Tests: throw after this many bytes of octree.bin (0: never), as an interruption would stop.
  std::uint64_t fail_after_octree_bytes = 0;
};

struct PotreeConvertResult {
  std::uint64_t points = 0;
  std::size_t nodes = 0;
  std::size_t chunks = 0;
  int depth = 0;
  std::uint64_t octree_bytes = 0;
  double seconds_scan = 0, seconds_count = 0, seconds_distribute = 0, seconds_build = 0,
         seconds_total = 0;
  // Partial outputs of earlier, killed conversions to the same target, removed before this one
  // started (those of running processes are left).
  PartialCleanup cleanup;
  CoordinateSystem crs;  // the inputs', written as metadata.json "projection" (empty: none)
  // The decoded points the scan kept for the later passes (inputs that do not reread cheaply,
  // lod/point_spill.h): points, and bytes held in memory and written to scratch files.
  std::uint64_t kept_points = 0, kept_memory_bytes = 0, kept_file_bytes = 0;
};

// metadata.json of a Potree 2.0 directory in the DEFAULT encoding (what convertToPotree writes;
// potree_octree_writer.h writes it too).
struct PotreeMetadataFields {
  std::uint64_t points = 0;
  Quantization quantization;
  double spacing = 0.0;
  Bounds3 cube;
  const PotreeLayout* layout = nullptr;
  const AttributeStats* stats = nullptr;
  std::uint64_t first_chunk_size = 0;
  int depth = 0;
  std::string name;
  std::string projection;  // potreeProjection (io/coordinate_system.h); empty: none
};
std::string potreeMetadataText(const PotreeMetadataFields& fields);

// Removes a directory unless released: the temporary directory of a conversion, renamed to its
// real name at the end (release() then).
class TemporaryDirectory {
 public:
  explicit TemporaryDirectory(std::filesystem::path path);  // created empty
  ~TemporaryDirectory();
  TemporaryDirectory(const TemporaryDirectory&) = delete;
  TemporaryDirectory& operator=(const TemporaryDirectory&) = delete;
  const std::filesystem::path& path() const { return path_; }
  void release() { released_ = true; }

 private:
  std::filesystem::path path_;
  bool released_ = false;
};

// Throws InputError unless `output` is absent, an empty directory or a Potree directory (to be
// replaced).
void checkPotreeOutput(const std::filesystem::path& output);

// ".NAME.partial-PID" beside `target`: where a conversion writes before its rename.
std::filesystem::path partialPathFor(const std::filesystem::path& target);

// The end of a conversion whose octree.bin is complete in `temp`: hierarchy.bin from `entries`
// (linked here), metadata.json (last), then `temp` renamed to `target` (a Potree directory
// there is replaced). Shared by convertToPotree and the distributed build's last task, so both
// write the same bytes.
EncodedHierarchy writePotreeIndex(const ConvertPlan& plan, std::vector<PotreeNodeEntry>& entries,
                                  const std::string& name, const std::string& projection,
                                  TemporaryDirectory& temp, const std::filesystem::path& target);

// Throws InputError for unreadable or malformed inputs and when `output` exists and is not a
// Potree directory (one with metadata.json is replaced); std::runtime_error for I/O failures.
PotreeConvertResult convertToPotree(const std::vector<ConvertInput>& inputs,
                                    const std::filesystem::path& output,
                                    const PotreeConvertOptions& options = {});

}  // namespace parallax
