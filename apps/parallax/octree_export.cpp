#include "octree_export.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <optional>
#include <vector>

#include "core/byte_source.h"
#include "core/error.h"
#include "core/point_gather.h"
#include "core/progress.h"
#include "io/point_file.h"
#include "lod/copc_reader.h"
#include "lod/in_memory_octree.h"
#include "lod/octree_open.h"
#include "lod/potree_reader.h"
#include "net/network.h"
#include "net/network_counters.h"

namespace parallax::cli {
namespace {

// A copy's blocks, and how many are hinted ahead of the one being written.
constexpr std::uint64_t kCopyBlockBytes = 8ull << 20;
constexpr std::size_t kCopyBlocksAhead = 4;

// Removes a directory unless released (the copy got to its rename).
class PartialDirectory {
 public:
  explicit PartialDirectory(std::filesystem::path path) : path_(std::move(path)) {
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~PartialDirectory() {
    std::error_code ignored;
    if (!path_.empty()) std::filesystem::remove_all(path_, ignored);
  }
  PartialDirectory(const PartialDirectory&) = delete;
  PartialDirectory& operator=(const PartialDirectory&) = delete;
  const std::filesystem::path& path() const { return path_; }
  void release() { path_.clear(); }

 private:
  std::filesystem::path path_;
};

void copyFile(const ByteSource& source, const std::filesystem::path& target, Progress* progress) {
  OutputFile out(target);
  const std::uint64_t size = source.size();
  std::vector<std::byte> block;
  for (std::uint64_t at = 0; at < size; at += kCopyBlockBytes) {
    std::vector<ByteRange> ahead;
    for (std::size_t i = 0; i < kCopyBlocksAhead; ++i) {
      const std::uint64_t offset = at + i * kCopyBlockBytes;
      if (offset >= size) break;
      ahead.push_back({offset, std::min(kCopyBlockBytes, size - offset)});
    }
    source.prefetch(ahead);
    block.resize(std::size_t(ahead.front().size));
    source.read(at, block, {.element = "bytes " + std::to_string(at)});
    out.write(block.data(), block.size());
    if (progress) progress->advance(block.size());
  }
  out.commit();
}

int copyOctree(const OctreeExportOptions& o) {
  // Opened (and checked) first: a URL that is no octree fails before anything is written.
  const std::unique_ptr<Octree> octree = openPotree(o.input);
  std::filesystem::path target = std::filesystem::absolute(o.output).lexically_normal();
  if (!target.has_filename()) target = target.parent_path();
  if (std::filesystem::exists(target) && !std::filesystem::is_directory(target)) {
    throw InputError({.file = target.string(),
                      .expected = "a directory (or nothing) to write the octree to",
                      .found = "a file"});
  }
  std::filesystem::create_directories(target.parent_path());
  std::string temp_name = ".";
  temp_name += target.filename().string();
  temp_name += ".partial-";
  temp_name += std::to_string(::getpid());
  PartialDirectory temp(target.parent_path() / temp_name);

  const std::optional<PotreeReadStats> stats = potreeReadStats(*octree);
  std::optional<TerminalProgress> progress;
  if (!o.quiet) progress.emplace("copying", stats ? stats->file_bytes : 0, "bytes");
  // metadata.json last: a directory without it is never taken for a finished octree.
  for (const char* name : {"hierarchy.bin", "octree.bin", "metadata.json"}) {
    const std::unique_ptr<ByteSource> source = openByteSource(potreeFileLocation(o.input, name));
    copyFile(*source, temp.path() / name, progress ? &*progress : nullptr);
  }
  if (progress) progress->finish();
  if (std::filesystem::exists(target)) std::filesystem::remove_all(target);
  std::filesystem::rename(temp.path(), target);
  temp.release();
  if (!o.quiet) std::fprintf(stderr, "wrote %s: a copy of %s\n", o.output.c_str(), o.input.c_str());
  return 0;
}

// Appends `part`'s columns to `all` at point `at` (the columns of `all` sized already).
void appendColumns(const PointCloud& part, PointCloud& all, std::uint64_t at) {
  auto copy = [&](auto& to, const auto& from) {
    if (!to.empty() && !from.empty()) {
      std::memcpy(to.data() + at, from.data(), from.size() * sizeof(*from.data()));
    }
  };
  copy(all.positions, part.positions);
  copy(all.colors, part.colors);
  copy(all.normals, part.normals);
  copy(all.intensity, part.intensity);
  copy(all.classification, part.classification);
  for (std::size_t i = 0; i < all.scalars.size() && i < part.scalars.size(); ++i) {
    const std::size_t width = scalarSize(part.scalars[i].type);
    std::memcpy(all.scalars[i].data.data() + at * width, part.scalars[i].data.data(),
                part.count * width);
  }
}

// The columns of `first` (a node), sized for `count` points.
PointCloud emptyLike(const PointCloud& first, std::uint64_t count) {
  PointCloud all;
  all.count = count;
  all.quantization = first.quantization;
  all.source = first.source;
  all.positions = Column<Int3>(count);
  if (first.hasColors()) all.colors = Column<Rgba8>(count);
  if (first.hasNormals()) all.normals = Column<Float3>(count);
  if (first.hasIntensity()) all.intensity = Column<float>(count);
  if (first.hasClassification()) all.classification = Column<std::uint8_t>(count);
  for (const ScalarColumn& scalar : first.scalars) {
    all.scalars.push_back({scalar.name, scalar.type, ByteBuffer(count * scalarSize(scalar.type))});
  }
  return all;
}

int writeOctreePoints(const OctreeExportOptions& o) {
  if (formatForExtension(o.output) == PointFormat::Unknown) {
    writePointFile(PointCloud{}, o.output);  // reports the supported extensions
  }
  const std::unique_ptr<Octree> octree = openOctree(o.input);  // Potree or COPC, local or URL
  const bool copc = copcDetails(*octree).has_value();
  expandWholeHierarchy(*octree);
  // In file order: over HTTP, neighbours in the file come in one request. Nodes whose cube the
  // filter's region or elevation range cannot meet are never read: an extract of a region of a
  // remote octree fetches the hierarchy and the nodes that meet it, not the whole file.
  std::vector<OctreeNode> nodes(octree->nodes().begin(), octree->nodes().end());
  std::sort(nodes.begin(), nodes.end(),
            [](const OctreeNode& a, const OctreeNode& b) { return a.byte_offset < b.byte_offset; });
  const std::size_t all_nodes = nodes.size();
  std::erase_if(
      nodes, [&](const OctreeNode& n) { return n.point_count == 0 || !o.filter.mayKeepIn(n.box); });
  const std::uint64_t total = octree->info().point_count;
  std::optional<TerminalProgress> progress;
  if (!o.quiet) progress.emplace("reading nodes", total);

  PointCloud all;
  std::uint64_t at = 0;
  constexpr std::size_t kAhead = 32;
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    if (i % (kAhead / 2) == 0) {
      const std::size_t end = std::min(nodes.size(), i + kAhead);
      octree->prefetch(std::span(nodes).subspan(i, end - i), {});
    }
    PointCloud part = octree->loadNode(nodes[i]);
    if (i == 0) all = emptyLike(part, total);
    const std::uint64_t node_points = part.count;
    if (!o.filter.keepsAll()) part = filterPoints(part, o.filter);
    if (at + part.count > total) {
      throw InputError({.file = o.input,
                        .element = "node " + nodes[i].name,
                        .expected = std::to_string(total) + " points in all (metadata.json)",
                        .found = "more in the nodes"});
    }
    appendColumns(part, all, at);
    at += part.count;
    if (progress) progress->advance(node_points);
  }
  if (progress) progress->finish();
  // Filtered: the columns were sized for every point, the cloud holds the kept ones.
  if (at < all.count) all = slicePoints(all, 0, at);
  all.computeBounds();
  const PointWriteOptions options{.ply_ascii = o.ply_ascii,
                                  .las_minor_version = o.las_minor_version};
  if (!o.quiet) {
    std::fprintf(stderr, "%s: %s, %llu points in %zu nodes\n", o.input.c_str(),
                 copc ? "COPC" : "Potree 2.0", static_cast<unsigned long long>(all.count),
                 nodes.size());
    for (const std::string& loss : describeWriteLosses(all, o.output, options)) {
      std::fprintf(stderr, "dropped or changed: %s\n", loss.c_str());
    }
  }
  writePointFile(all, o.output, options);
  if (!o.quiet) std::fprintf(stderr, "wrote %s\n", o.output.c_str());
  if (o.verbose) {
    const NetworkStats net = networkStats();
    std::uint64_t node_bytes = 0;
    for (const OctreeNode& node : nodes) node_bytes += node.byte_size;
    std::fprintf(stderr,
                 "convert: read %zu of %zu nodes (%llu bytes of points); network: %llu requests, "
                 "%llu bytes received, %llu reads from the cache\n",
                 nodes.size(), all_nodes, static_cast<unsigned long long>(node_bytes),
                 static_cast<unsigned long long>(net.requests),
                 static_cast<unsigned long long>(net.bytes_received),
                 static_cast<unsigned long long>(net.cache_hits));
  }
  return 0;
}

}  // namespace

void expandWholeHierarchy(Octree& octree) {
  for (std::size_t done = 0; done < octree.nodes().size();) {
    std::vector<std::int32_t> pending;
    std::vector<OctreeNode> hint;
    for (std::size_t i = done; i < octree.nodes().size(); ++i) {
      if (octree.nodes()[i].hierarchy_pending) {
        pending.push_back(std::int32_t(i));
        hint.push_back(octree.nodes()[i]);
      }
    }
    done = octree.nodes().size();
    octree.prefetch({}, hint);
    for (const std::int32_t node : pending) octree.expandHierarchy(node);
  }
}

int runOctreeExport(const OctreeExportOptions& options) {
  return options.to_directory ? copyOctree(options) : writeOctreePoints(options);
}

}  // namespace parallax::cli
