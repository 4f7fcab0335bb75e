// A Potree 2.0 directory (metadata.json, hierarchy.bin, octree.bin in the DEFAULT encoding) as
// an Octree: what PotreeConverter 2 writes, and what `parallax convert` writes.
//
// Opening reads metadata.json (potree_metadata_reader.h) and the first hierarchy chunk; deeper
// chunks are read when expandHierarchy() reaches a proxy (potree_hierarchy_reader.h). loadNode()
// reads one node's records with pread (no shared file offset, so any number of threads may load
// at once) and decodes them (potree_record_reader.h: which attribute becomes which column).
//
// Positions come back as the file's int32 values with the metadata's scale and offset as the
// cloud's quantization, so nothing is rounded. Node boxes are the metadata's cube halved per
// level; spacing is the root's spacing / 2^level.
//
// While a node is hierarchy_pending its byte_offset / byte_size are those of its chunk in
// hierarchy.bin; loadNode() still works for it (it reads the chunk's first entry to find the
// node's points), and expandHierarchy() replaces them with the node's range in octree.bin.
//
// Every inconsistency is an InputError naming the file, the byte offset, the node, what was
// expected and what was found: missing files, malformed JSON, ranges past the end of a file,
// point counts that disagree with byte sizes or with metadata's total, proxies that point
// outside hierarchy.bin or back at a chunk already read (a cycle), trees deeper than
// kPotreeMaxLevel.
#pragma once

#include <cstddef>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "lod/octree.h"
#include "lod/potree_metadata_reader.h"

namespace parallax {

// True when `path` is a directory holding metadata.json, or a file named metadata.json (as
// PotreeConverter's users pass it to Potree). Never throws.
bool isPotreeDirectory(const std::filesystem::path& path);

// Opens the Potree 2.0 directory `dir` (or `dir` = its metadata.json). Throws InputError for a
// missing or malformed file (see above).
std::unique_ptr<Octree> openPotree(const std::filesystem::path& dir);

// The same from the three files' bytes in memory (tests, fuzzing); `name` stands for the
// directory in messages ("name/hierarchy.bin").
std::unique_ptr<Octree> openPotreeFromMemory(std::string metadata_json,
                                             std::vector<std::byte> hierarchy,
                                             std::vector<std::byte> octree,
                                             const std::string& name);

// The metadata of an open Potree octree (for `parallax info`); nullptr for other octrees.
const PotreeMetadata* potreeMetadata(const Octree& octree);

}  // namespace parallax
