// Internal to the Potree 2.0 reader: the byte sources of an opened directory (potree_open.cpp
// opens them from a path, a URL or memory; potree_reader.cpp reads through them).
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "core/byte_source.h"
#include "lod/octree.h"
#include "lod/potree_metadata_reader.h"

namespace parallax {

struct PotreeSources {
  std::string location;  // the directory or URL, for reports
  std::uint64_t metadata_bytes = 0;
  std::unique_ptr<ByteSource> hierarchy, octree;
};

// The octree over opened sources; reads the first hierarchy chunk. Throws InputError.
std::unique_ptr<Octree> makePotreeOctree(PotreeMetadata metadata, PotreeSources sources);

}  // namespace parallax
