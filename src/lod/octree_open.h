// Where a path is opened as an octree: the two on-disk octree formats Parallax reads without
// converting, a Potree 2.0 directory (potree_reader.h) and a COPC file (copc_reader.h), told
// apart by what is there (a directory with metadata.json; a LAS 1.4 file whose first VLR is the
// COPC info VLR), never by the name. An http(s) URL is told by what it names (octree_url.h) and
// opened through the network's byte sources.
#pragma once

#include <filesystem>
#include <memory>

#include "lod/octree.h"

namespace parallax {

enum class OctreeFormat { None, Potree, Copc };

// What `path` holds. Never throws (an unreadable path is None); never touches the network.
OctreeFormat detectOctreeFormat(const std::filesystem::path& path);
inline bool isOctreePath(const std::filesystem::path& path) {
  return detectOctreeFormat(path) != OctreeFormat::None;
}

// Opens a Potree directory or a COPC file. Throws InputError (the reader's, or for a path that is
// neither).
std::unique_ptr<Octree> openOctree(const std::filesystem::path& path);

}  // namespace parallax
