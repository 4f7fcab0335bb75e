#include "octree_export.h"

#include <cstdio>
#include <optional>

#include "core/progress.h"
#include "io/point_file.h"
#include "lod/octree_export.h"
#include "net/network.h"
#include "net/network_counters.h"

namespace parallax::cli {
namespace {

int copyOctree(const OctreeExportOptions& o) {
  std::optional<TerminalProgress> progress;
  copyPotreeOctree(o.input, o.output, [&](std::uint64_t total) -> Progress* {
    if (o.quiet) return nullptr;
    return &progress.emplace("copying", total, "bytes");
  });
  if (progress) progress->finish();
  if (!o.quiet) std::fprintf(stderr, "wrote %s: a copy of %s\n", o.output.c_str(), o.input.c_str());
  return 0;
}

int writeOctreePoints(const OctreeExportOptions& o) {
  if (formatForExtension(o.output) == PointFormat::Unknown) {
    writePointFile(PointCloud{}, o.output);  // reports the supported extensions
  }
  std::optional<TerminalProgress> progress;
  const OctreePoints read = readOctreePoints(o.input, o.filter, [&](std::uint64_t total) {
    return o.quiet ? nullptr : &progress.emplace("reading nodes", total);
  });
  if (progress) progress->finish();
  const PointCloud& all = read.cloud;
  // A COPC file is a LAZ file: a LAS or LAZ output keeps its header fields and records (the CRS
  // above all) as `convert` of the local file, read as LAZ, does. A Potree directory has none.
  const PointWriteOptions options{.ply_ascii = o.ply_ascii,
                                  .las_minor_version = o.las_minor_version,
                                  .source = read.copc ? o.input : std::string()};
  if (!o.quiet) {
    std::fprintf(stderr, "%s: %s, %llu points in %zu nodes\n", o.input.c_str(),
                 read.copc ? "COPC" : "Potree 2.0", static_cast<unsigned long long>(all.count),
                 read.nodes_read);
    for (const std::string& loss : describeWriteLosses(all, o.output, options)) {
      std::fprintf(stderr, "dropped or changed: %s\n", loss.c_str());
    }
  }
  writePointFile(all, o.output, options);
  if (!o.quiet) std::fprintf(stderr, "wrote %s\n", o.output.c_str());
  if (o.verbose) {
    const NetworkStats net = networkStats();
    std::fprintf(stderr,
                 "convert: read %zu of %zu nodes (%llu bytes of points); network: %llu requests, "
                 "%llu bytes received, %llu reads from the cache\n",
                 read.nodes_read, read.nodes_total,
                 static_cast<unsigned long long>(read.node_bytes),
                 static_cast<unsigned long long>(net.requests),
                 static_cast<unsigned long long>(net.bytes_received),
                 static_cast<unsigned long long>(net.cache_hits));
  }
  return 0;
}

}  // namespace

int runOctreeExport(const OctreeExportOptions& options) {
  return options.to_directory ? copyOctree(options) : writeOctreePoints(options);
}

}  // namespace parallax::cli
