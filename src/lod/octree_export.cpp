#include "lod/octree_export.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "core/byte_source.h"
#include "core/byte_source_opener.h"
#include "core/error.h"
#include "core/point_gather.h"
#include "io/point_file.h"
#include "lod/copc_reader.h"
#include "lod/octree_open.h"
#include "lod/potree_reader.h"

namespace parallax {
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

// Appends `part`'s columns to `all` at point `at` (the columns of `all` sized already).
void appendColumns(const PointCloud& part, PointCloud& all, std::uint64_t at) {
  auto copy = [&](auto& to, const auto& from) {
    if (!to.empty() && !from.empty()) {
      std::memcpy(to.data() + at, from.data(), from.size() * sizeof(*from.data()));
    }
  };
  copy(all.positions, part.positions);
  copy(all.colors, part.colors);
  copy(all.stored_colors, part.stored_colors);
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
  // The 16-bit values as stored (a COPC or Potree node's): a LAS output writes them back
  // unchanged, not the 8-bit display colours scaled up (100 would become 25700).
  if (!first.stored_colors.empty()) all.stored_colors = Column<Rgb16>(count);
  if (first.hasNormals()) all.normals = Column<Float3>(count);
  if (first.hasIntensity()) all.intensity = Column<float>(count);
  if (first.hasClassification()) all.classification = Column<std::uint8_t>(count);
  for (const ScalarColumn& scalar : first.scalars) {
    all.scalars.push_back({scalar.name, scalar.type, ByteBuffer(count * scalarSize(scalar.type))});
  }
  return all;
}

}  // namespace

void copyPotreeOctree(const std::string& input, const std::filesystem::path& output,
                      const ProgressFor& progress_for) {
  // Opened (and checked) first: a URL that is no octree fails before anything is written.
  const std::unique_ptr<Octree> octree = openPotree(input);
  std::filesystem::path target = std::filesystem::absolute(output).lexically_normal();
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
  Progress* progress = progress_for ? progress_for(stats ? stats->file_bytes : 0) : nullptr;
  // metadata.json last: a directory without it is never taken for a finished octree.
  for (const char* name : {"hierarchy.bin", "octree.bin", "metadata.json"}) {
    const std::unique_ptr<ByteSource> source = openByteSource(potreeFileLocation(input, name));
    copyFile(*source, temp.path() / name, progress);
  }
  if (std::filesystem::exists(target)) std::filesystem::remove_all(target);
  std::filesystem::rename(temp.path(), target);
  temp.release();
}

OctreePoints queryOctree(Octree& octree, const OctreeQuery& query, const std::string& input,
                         const ProgressFor& progress_for) {
  OctreePoints result;
  const PointFilter& filter = query.filter;
  const bool copc = copcDetails(octree).has_value();
  expandWholeHierarchy(octree);
  // In file order: over HTTP, neighbours in the file come in one request. Nodes whose cube the
  // filter's region or elevation range cannot meet are never read: an extract of a region of a
  // remote octree fetches the hierarchy and the nodes that meet it, not the whole file.
  std::vector<OctreeNode> nodes(octree.nodes().begin(), octree.nodes().end());
  std::sort(nodes.begin(), nodes.end(),
            [](const OctreeNode& a, const OctreeNode& b) { return a.byte_offset < b.byte_offset; });
  const std::size_t all_nodes = nodes.size();
  std::erase_if(nodes, [&](const OctreeNode& n) {
    return n.point_count == 0 || (query.max_level >= 0 && n.level > query.max_level) ||
           !filter.mayKeepIn(n.box);
  });
  // Sized for the nodes read, not the octree: a small region of a large octree holds little.
  std::uint64_t total = 0;
  for (const OctreeNode& node : nodes) total += node.point_count;
  Progress* progress = progress_for ? progress_for(total) : nullptr;

  PointCloud all;
  std::uint64_t at = 0;
  constexpr std::size_t kAhead = 32;
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    if (i % (kAhead / 2) == 0) {
      const std::size_t end = std::min(nodes.size(), i + kAhead);
      octree.prefetch(std::span(nodes).subspan(i, end - i), {});
    }
    PointCloud part = octree.loadNode(nodes[i]);
    if (i == 0) all = emptyLike(part, total);
    const std::uint64_t node_points = part.count;
    if (!filter.keepsAll()) part = filterPoints(part, filter);
    if (at + part.count > total) {
      throw InputError(
          {.file = input,
           .element = "node " + nodes[i].name,
           .expected = std::to_string(total) + " points in the nodes read (the hierarchy's counts)",
           .found = "more in the nodes"});
    }
    appendColumns(part, all, at);
    at += part.count;
    if (progress) progress->advance(node_points);
  }
  // Filtered: the columns were sized for every point, the cloud holds the kept ones.
  if (at < all.count) all = slicePoints(all, 0, at);
  all.computeBounds();
  result.cloud = std::move(all);
  result.copc = copc;
  result.nodes_read = nodes.size();
  result.nodes_total = all_nodes;
  for (const OctreeNode& node : nodes) result.node_bytes += node.byte_size;
  return result;
}

int levelOfSpacing(Octree& octree, double spacing) {
  expandWholeHierarchy(octree);
  int deepest = 0;
  for (const OctreeNode& node : octree.nodes()) deepest = std::max(deepest, node.level);
  const double root = octree.info().spacing;
  for (int level = 0; level < deepest; ++level) {
    if (std::ldexp(root, -level) <= spacing) return level;
  }
  return deepest;
}

OctreePoints readOctreePoints(const std::string& input, const PointFilter& filter,
                              const ProgressFor& progress_for) {
  const std::unique_ptr<Octree> octree = openOctree(input);  // Potree or COPC, local or URL
  return queryOctree(*octree, {.filter = filter}, input, progress_for);
}

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

}  // namespace parallax
