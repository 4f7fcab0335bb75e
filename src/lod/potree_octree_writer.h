// Writing any octree (a COPC file, another Potree directory) as a Potree 2.0 directory node by
// node: the tree is the source's, unchanged (cube, spacing, nodes, and each node's points in the
// same order), each node's points re-encoded as DEFAULT records (potree_layout.h) in the layout
// of the nodes' columns. `parallax convert X.copc.laz -o DIR` uses it: no rebuilding.
//
// Nodes go to octree.bin level by level (the top of the tree first), a batch of nodes encoded on
// every core at a time; hierarchy.bin as the converter writes it (chunks of 4 levels, proxies);
// metadata.json last, in a temporary directory renamed at the end, as convertToPotree does.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

#include "core/progress.h"
#include "lod/octree.h"

namespace parallax {

struct PotreeWriteOptions {
  std::string name;                       // metadata "name"; empty: the directory's name
  std::uint64_t batch_points = 1u << 20;  // points encoded at once
  Progress* progress = nullptr;           // advanced by points written
};

struct PotreeWriteResult {
  std::uint64_t points = 0;
  std::size_t nodes = 0;
  int depth = 0;
};

// Reads the whole hierarchy of `octree` and writes it to `output`. Throws InputError for a source
// that fails to read or an `output` that is neither absent, empty nor a Potree directory;
// std::runtime_error on I/O failure.
PotreeWriteResult writePotree(Octree& octree, const std::filesystem::path& output,
                              const PotreeWriteOptions& options = {});

}  // namespace parallax
