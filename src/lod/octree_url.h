// The octrees `parallax` opens from an http(s) URL, by what the URL names: a Potree 2.0
// directory (potree_reader.h: ".../cloud", ".../cloud/", ".../cloud/metadata.json") or a COPC
// file (".copc.laz"). Other files are no octrees: `info`, `render`, `pick` and `convert` read
// them from a URL through the format table (core's openByteSource; a LAS or LAZ file by range),
// while `view` and `bench render` take octree URLs only (checkOctreeUrl).
//
// Both read through core's openByteSource, which net serves (one connection pool, merged
// ranges, the on-disk cache); a COPC file's hierarchy pages and chunks are ranges like a Potree
// directory's hierarchy.bin and octree.bin.
#pragma once

#include <memory>
#include <string>
#include <string_view>

#include "lod/octree.h"

namespace parallax {

enum class OctreeUrlKind {
  NotUrl,  // a local path
  Potree,  // a Potree 2.0 directory or its metadata.json
  Copc,    // a .copc.laz file
  Other,   // a URL of anything else
};

OctreeUrlKind octreeUrlKind(std::string_view input);

// Throws InputError (naming the URL, with a way out) for URLs openOctreeUrl cannot open;
// returns for local paths and openable URLs. Never touches the network.
void checkOctreeUrl(std::string_view input);

// Opens the octree an http(s) URL names. Throws InputError (checkOctreeUrl's, or the reader's).
std::unique_ptr<Octree> openOctreeUrl(const std::string& url);

}  // namespace parallax
