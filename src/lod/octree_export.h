// Octree export: a Potree 2.0 octree copied to a directory, or the points of a Potree or COPC
// octree (local or a URL) gathered into one cloud, only the nodes a filter's region can meet read.
// What `parallax convert OCTREE -o OUT` does below its messages (apps/parallax/octree_export.h).
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>

#include "core/point_cloud.h"
#include "core/point_filter.h"
#include "core/progress.h"
#include "lod/octree.h"

namespace parallax {

// Made once the total is known (bytes to copy, points to read; 0 unknown); may return nullptr.
using ProgressFor = std::function<Progress*(std::uint64_t total)>;

// Copies the three files of the Potree 2.0 octree at `input` (a directory or its http(s) URL),
// read through their byte sources (over HTTP: ranges of 8 MiB, several in flight), into a
// temporary directory beside `target`, renamed to `target` at the end (metadata.json written
// last). Opens and checks the octree first: a URL that is no octree fails before anything is
// written. Throws InputError where `target` is a file.
void copyPotreeOctree(const std::string& input, const std::filesystem::path& target,
                      const ProgressFor& progress_for = {});

struct OctreePoints {
  PointCloud cloud;              // the points the filter keeps, bounds computed
  bool copc = false;             // COPC (else Potree 2.0)
  std::size_t nodes_read = 0;    // nodes with points the filter's region may meet
  std::size_t nodes_total = 0;   // nodes in the whole hierarchy
  std::uint64_t node_bytes = 0;  // bytes of the nodes read
};

// What queryOctree reads: the points `filter` keeps, of the nodes down to `max_level`.
struct OctreeQuery {
  PointFilter filter;
  // The deepest level read (0: the root alone); -1 every level. Additive LOD: levels 0..L hold
  // the whole cloud at level L's spacing (lod/octree.h), so this is the query's resolution.
  int max_level = -1;
};

// The first level whose spacing (root spacing / 2^level) is at most `spacing` (world units),
// or the deepest level `octree` has where none is: the level a query of that resolution reads
// (as PDAL's COPC reader's `resolution`). Reads the whole hierarchy.
int levelOfSpacing(Octree& octree, double spacing);

// The points of an open octree that `query` keeps, in one cloud. Reads the whole hierarchy
// first; then as readOctreePoints below (nodes in file order, only those the filter's region can
// meet and within max_level; columns sized for those nodes' points). `input` names the octree
// in messages. Progress counts the points of the nodes read.
OctreePoints queryOctree(Octree& octree, const OctreeQuery& query, const std::string& input,
                         const ProgressFor& progress_for = {});

// Every point of the octree at `input` (Potree or COPC, local or a URL) that `filter` keeps, in
// one cloud. Nodes are read in file order (over HTTP, neighbours come in one request); nodes whose
// cube the filter's region or elevation range cannot meet (PointFilter::mayKeepIn) are never
// read, so a region of a remote octree costs its nodes, not the file. Progress counts the points
// of the nodes read. Throws InputError where the nodes hold more points than the octree states.
OctreePoints readOctreePoints(const std::string& input, const PointFilter& filter,
                              const ProgressFor& progress_for = {});

// Reads every hierarchy chunk (a level of proxies at a time, each level's chunks hinted to the
// octree together, so that over HTTP they come in few requests).
void expandWholeHierarchy(Octree& octree);

}  // namespace parallax
