// Writing an octree as a COPC 1.0 file (copc_format.h), node by node: one LAZ chunk per node, so
// the tree is the source's, unchanged (same cube, spacing, nodes and points in each node, in
// the same order). `parallax convert IN... -o OUT.copc.laz` builds the tree with the out-of-core
// builder first (copc_converter.h); `convert DIR -o OUT.copc.laz` re-encodes a Potree directory.
//
// The file:
//   LAS 1.4 header; point format 6, 7 (colour) or 8 (NIR) with extra bytes for the other
//     attributes, chosen from the nodes' columns as las_writer.h chooses; the source's scale
//     and offset (positions are not re-rounded); the WKT bit set (COPC requires WKT);
//   VLRs: the COPC info VLR first, then the "laszip encoded" VLR (layered, compressor 3, items
//     version 3, variable chunk size), the caller's VLRs (the CRS as WKT), the extra bytes;
//   the point data: the chunk table's offset, one chunk per node with points, level by level
//     (the top of the tree first), then the ordinary LAZ chunk table (point counts and sizes),
//     so that any LAZ reader reads the file front to back;
//   one EVLR ("copc", 1000): the hierarchy pages, the root's first. A page covers `page_levels`
//     levels below its node; a node that far down with children of its own heads a child page
//     (an entry of -1 points in its parent's page).
// Chunks are encoded on every core, a batch of nodes at a time, and written in order; the file is
// written under a temporary name and renamed at the end (io/point_file.h OutputFile).
#pragma once

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "core/progress.h"
#include "io/las_header.h"
#include "lod/octree.h"

namespace parallax {

struct CopcWriteOptions {
  // VLRs copied after the laszip VLR: the CRS as a LASF_Projection 2112 (WKT) record. Others
  // are copied too; LASF_Spec 4 (extra bytes, written here) and GeoTIFF keys are skipped (a
  // COPC file's CRS is WKT).
  std::vector<LasVlr> vlrs;
  std::optional<bool> gps_time_standard;  // global encoding bit 0; default false
  int page_levels = 4;                    // levels a hierarchy page covers (>= 1)
  std::uint64_t batch_points = 1u << 20;  // points encoded at once (memory: ~150 bytes each)
  Progress* progress = nullptr;           // advanced by points written
  // Checked once a node written (OctreeBuildOptions::cancel): throws OctreeBuildCancelled, the
  // unfinished file removed. Null: not cancellable.
  const std::atomic<bool>* cancel = nullptr;
};

struct CopcWriteResult {
  std::uint64_t points = 0;
  std::size_t nodes = 0, chunks = 0, pages = 0;
  int point_format = 0;
  std::uint64_t bytes = 0;
};

// Why `info` cannot be written as COPC node by node (its root box is not a cube, or there is no
// spacing); nullopt when it can.
std::optional<std::string> copcLayoutProblem(const OctreeInfo& info);

// Reads the whole hierarchy of `octree` and writes it to `path`. Throws InputError for a source
// that fails to read, std::invalid_argument when copcLayoutProblem() has one, std::runtime_error
// on I/O failure.
CopcWriteResult writeCopc(Octree& octree, const std::filesystem::path& path,
                          const CopcWriteOptions& options = {});

}  // namespace parallax
