// `parallax convert OCTREE -o OUT`, where OCTREE is a Potree 2.0 directory or its http(s) URL
// (or, for a point file OUT, a COPC file's URL):
// - OUT a directory (no extension, or --format potree): a copy of the octree's three files, read
//   through their byte sources (over HTTP: ranges of 8 MiB, several in flight) and written under
//   a temporary name beside OUT, renamed to OUT at the end;
// - OUT a point file (.ply, .las, .xyz, ...): every node's points in one cloud, written as
//   `convert FILE -o FILE` writes (the whole cloud in memory, as there), only the points the
//   filter keeps; nodes whose cube the filter's region misses are not read (PointFilter::
//   mayKeepIn), so a region of a remote octree costs its nodes, not the file.
// The copy and the reading are the library's (lod/octree_export.h); here, the messages, the
// progress bars and the written file.
#pragma once

#include <string>

#include "core/point_filter.h"

namespace parallax::cli {

struct OctreeExportOptions {
  std::string input, output;
  bool to_directory = false;
  bool ply_ascii = false;
  int las_minor_version = 0;
  bool quiet = false;
  bool verbose = false;  // a point file: the nodes read and what the network fetched (stderr)
  PointFilter filter;    // the points written to a file (a directory copy takes no filter)
};

int runOctreeExport(const OctreeExportOptions& options);

}  // namespace parallax::cli
