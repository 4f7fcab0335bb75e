// A Potree 2.0 directory (metadata.json, hierarchy.bin, octree.bin in the DEFAULT encoding) as
// an Octree: what PotreeConverter 2 writes, and what `parallax convert` writes; on the local
// disk or on any HTTP(S) server (static files read with Range requests, net/).
//
// Every byte is read through a ByteSource (core/byte_source.h): local files with pread, URLs
// through the opener net installs behind core (core/byte_source_opener.h: the process's HTTP
// client and range cache). Opening reads metadata.json
// (potree_metadata_reader.h) and the first hierarchy chunk; deeper chunks are read when
// expandHierarchy() reaches a proxy (potree_hierarchy_reader.h). loadNode() reads one node's
// records (no shared file offset, so any number of threads may load at once) and decodes them
// (potree_record_reader.h: which attribute becomes which column).
//
// Over HTTP, the three files' first requests go out together (one round trip); metadata.json
// comes whole and hierarchy.bin's first 64 KiB (the first chunk, usually) with them. Afterwards
// hierarchyReady() is false for a proxy whose chunk is not in memory yet, fetchHierarchy() brings
// it (and the chunks a chain of proxies leads to), and prefetch() passes the nodes' ranges in
// octree.bin and the chunks' ranges in hierarchy.bin on to the sources, which fetch them
// together. For local directories hierarchyReady() is always true.
//
// Positions come back as the file's int32 values with the metadata's scale and offset as the
// cloud's quantization, so nothing is rounded. Node boxes are the metadata's cube halved per
// level; spacing is the root's spacing / 2^level.
//
// While a node is hierarchy_pending its byte_offset / byte_size are those of its chunk in
// hierarchy.bin; loadNode() still works for it (it reads the chunk's first entry to find the
// node's points), and expandHierarchy() replaces them with the node's range in octree.bin.
//
// Every inconsistency is an InputError naming the file or URL, the byte offset, the node, what
// was expected and what was found: missing files, malformed JSON, ranges past the end of a file,
// point counts that disagree with byte sizes or with metadata's total, proxies that point
// outside hierarchy.bin or back at a chunk already read (a cycle), trees deeper than
// kPotreeMaxLevel; over HTTP also the network's failures (net/http_byte_source.h), each naming
// the node being read.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "lod/octree.h"
#include "lod/potree_metadata_reader.h"

namespace parallax {

// True when `path` is a directory holding metadata.json, or a file named metadata.json (as
// PotreeConverter's users pass it to Potree), or an http(s) URL of such a directory
// (isPotreeUrl). Never throws; never touches the network.
bool isPotreeDirectory(const std::filesystem::path& path);

// True for an http(s) URL that may name a Potree directory: ".../cloud", ".../cloud/" or
// ".../cloud/metadata.json"; false for URLs of files of other formats (".copc.laz", ".laz",
// ".las", ".ply", ".json" other than metadata.json, ...: anything whose last segment has an
// extension).
bool isPotreeUrl(std::string_view url);

// Where one of the directory's files is: `file` ("metadata.json", "hierarchy.bin", "octree.bin")
// beside the metadata.json that `dir` (a path or URL, as openPotree takes) names; a URL keeps its
// query (a signed container's token).
std::string potreeFileLocation(const std::string& dir, std::string_view file);

// Opens the Potree 2.0 directory `dir` (or `dir` = its metadata.json; or such a URL). Throws
// InputError for a missing or malformed file (see above).
std::unique_ptr<Octree> openPotree(const std::filesystem::path& dir);

// The same from the three files' bytes in memory (tests, fuzzing); `name` stands for the
// directory in messages ("name/hierarchy.bin").
std::unique_ptr<Octree> openPotreeFromMemory(std::string metadata_json,
                                             std::vector<std::byte> hierarchy,
                                             std::vector<std::byte> octree,
                                             const std::string& name);

// The metadata of an open Potree octree (for `parallax info`); nullptr for other octrees.
const PotreeMetadata* potreeMetadata(const Octree& octree);

// What an open Potree octree has read so far (for the commands' reports).
struct PotreeReadStats {
  std::string location;               // the directory or URL
  bool remote = false;                // read over HTTP
  std::uint64_t file_bytes = 0;       // sizes of the three files
  std::uint64_t hierarchy_bytes = 0;  // of the chunks read (the first included)
  std::uint64_t node_bytes = 0;       // of the nodes loaded (each load counted)
  std::uint64_t nodes_loaded = 0;
};
// Nothing for other octrees.
std::optional<PotreeReadStats> potreeReadStats(const Octree& octree);

}  // namespace parallax
