// URLs on the command line: the process's network settings from the commands' options, and the
// report of what the network did (stderr).
#pragma once

#include <cstdint>
#include <string>

#include "lod/octree.h"
#include "render_options.h"

namespace parallax::cli {

// The environment's settings (net/network.h), with --cache-dir DIR putting the HTTP range cache
// in DIR/http and --no-cache turning it off.
void configureNetworkFrom(const LodOptions& lod);

// For an octree read over HTTP, a line on stderr: requests, bytes received, cache hits, retries,
// and the bytes the view needed (the drawn nodes' records plus the hierarchy read), with the
// ratio of the two. Nothing for local octrees.
void printNetworkReport(const char* command, const Octree& octree, std::uint64_t drawn_points);

// For a point file read from a URL (`convert -v`), a line on stderr: the requests sent, the bytes
// received against the file's size, and the reads the disk cache answered. Nothing for a path.
void printFetchReport(const char* command, const std::string& input);

}  // namespace parallax::cli
