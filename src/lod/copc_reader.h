// A COPC 1.0 file (copc_format.h) as an Octree, read without converting: what PDAL, untwine and
// `parallax convert -o X.copc.laz` write.
//
// Opening reads the LAS header and VLRs (the info VLR must be the first), the LAZ chunk table
// and the root hierarchy page; child pages are read when expandHierarchy() reaches a node whose
// entry pointed at one (hierarchy_pending, as Potree's proxies; copc_hierarchy.h). loadNode()
// reads the node's chunk (its byte range is its LAZ chunk) and decodes it with the layered LAZ
// codec (io/laz), on the calling thread, so loader threads decode nodes in parallel.
//
// Nodes: names, boxes and child order as octree.h says (a key (level, x, y, z) is the node
// whose name has one digit 4 * x bit + 2 * y bit + z bit a level); the root cube is the info
// VLR's center +- halfsize and the spacing its spacing halved per level. Points come back as
// the LAS reader gives them (las_reader.h: the same columns, positions as the file's int32
// values with the header's scale and offset), so a node's points equal the plain LAZ reader's
// points of the same chunk. The one difference: the 8-bit colour rule of las_reader.h is decided
// once, from the root's points, and holds for every node (nodes are read alone, so the rule
// cannot look at the whole file).
//
// OctreeInfo: the header's point count and bounds, the info VLR's cube and spacing.
//
// While a node is hierarchy_pending its byte range is its page's and its point count 0;
// loadNode() still works (it finds the node's entry in the page).
//
// Every inconsistency is an InputError naming the file, what was being read (the page and the
// entry, or the node) and the byte offset; see copc_hierarchy.h for the hierarchy's checks.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "core/byte_source.h"
#include "io/las_header.h"
#include "lod/copc_format.h"
#include "lod/octree.h"

namespace parallax {

// True when `head` (the file's first bytes, at least 393 of them) is a LAS 1.4 file whose first
// VLR is the COPC info VLR: how a COPC file is told from a plain LAZ file, by content.
bool looksLikeCopc(std::span<const std::byte> head);
// The same for a file on disk; false for directories and unreadable files. Never throws.
bool isCopcFile(const std::filesystem::path& path);

// Opens a COPC file. Throws InputError (see above).
std::unique_ptr<Octree> openCopc(const std::filesystem::path& path);
// From any byte source: a local file's, bytes in memory, an http(s) URL's (core/byte_source.h).
std::unique_ptr<Octree> openCopc(std::unique_ptr<ByteSource> source);
// From bytes in memory (tests, fuzzing); `name` stands for the file in messages.
std::unique_ptr<Octree> openCopcFromMemory(std::vector<std::byte> bytes, const std::string& name);

// What `parallax info` shows of a COPC file beside the octree.
struct CopcDetails {
  std::string file;
  std::uint64_t file_bytes = 0;
  LasHeader header;  // the file's (header, VLRs, the laszip VLR, the CRS)
  CopcInfo info;
  std::uint64_t chunks = 0;  // in the LAZ chunk table
  std::size_t pages_read = 0;
  std::size_t pending_nodes = 0;  // nodes whose page is not read yet
};
// The details of an open COPC octree; nullopt for other octrees.
std::optional<CopcDetails> copcDetails(const Octree& octree);

}  // namespace parallax
