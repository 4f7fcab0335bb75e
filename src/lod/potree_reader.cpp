#include "lod/potree_reader.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cassert>
#include <cerrno>
#include <cstring>
#include <set>

#include "core/error.h"
#include "lod/potree_hierarchy_reader.h"
#include "lod/potree_record_reader.h"

namespace parallax {
namespace {

// metadata.json of real clouds is a few kB; anything this large is not one.
constexpr std::uint64_t kMaxMetadataBytes = 64ull << 20;

// Random-access bytes of one of the directory's files.
class ByteSource {
 public:
  virtual ~ByteSource() = default;
  virtual std::uint64_t size() const = 0;
  // Reads out.size() bytes at `offset`; the caller has checked the range against size().
  virtual void read(std::uint64_t offset, std::span<std::byte> out) const = 0;
  const std::string& name() const { return name_; }

 protected:
  explicit ByteSource(std::string name) : name_(std::move(name)) {}

 private:
  std::string name_;
};

class MemorySource final : public ByteSource {
 public:
  MemorySource(std::vector<std::byte> bytes, std::string name)
      : ByteSource(std::move(name)), bytes_(std::move(bytes)) {}
  std::uint64_t size() const override { return bytes_.size(); }
  void read(std::uint64_t offset, std::span<std::byte> out) const override {
    assert(offset <= bytes_.size() && out.size() <= bytes_.size() - offset);
    if (!out.empty()) std::memcpy(out.data(), bytes_.data() + offset, out.size());
  }

 private:
  std::vector<std::byte> bytes_;
};

class FileSource final : public ByteSource {
 public:
  explicit FileSource(const std::filesystem::path& path) : ByteSource(path.string()) {
    fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd_ < 0) failSystem("the file", std::nullopt);
    struct stat st {};
    if (::fstat(fd_, &st) != 0) failSystem("its size", std::nullopt);
    if (!S_ISREG(st.st_mode)) {
      ::close(fd_);
      throw InputError({.file = name(), .expected = "a regular file", .found = "something else"});
    }
    size_ = std::uint64_t(st.st_size);
  }
  ~FileSource() override {
    if (fd_ >= 0) ::close(fd_);
  }
  FileSource(const FileSource&) = delete;
  FileSource& operator=(const FileSource&) = delete;

  std::uint64_t size() const override { return size_; }
  void read(std::uint64_t offset, std::span<std::byte> out) const override {
    std::size_t done = 0;
    while (done < out.size()) {
      const ssize_t n = ::pread(fd_, out.data() + done, out.size() - done, off_t(offset + done));
      if (n < 0 && errno == EINTR) continue;
      if (n < 0) failSystem(std::to_string(out.size()) + " bytes", offset + done);
      if (n == 0) {
        throw InputError({.file = name(),
                          .byte_offset = offset + done,
                          .expected = std::to_string(out.size() - done) + " more bytes",
                          .found = "the end of the file",
                          .hint = "the file shrank while it was read"});
      }
      done += std::size_t(n);
    }
  }

 private:
  [[noreturn]] void failSystem(const std::string& what, std::optional<std::uint64_t> at) const {
    const std::string reason = std::strerror(errno);
    if (fd_ >= 0 && !at) ::close(fd_);
    throw InputError({.file = name(),
                      .byte_offset = at,
                      .expected = "to read " + what,
                      .found = reason,
                      .hint = "a Potree 2.0 directory holds metadata.json, hierarchy.bin and "
                              "octree.bin"});
  }

  int fd_ = -1;
  std::uint64_t size_ = 0;
};

class PotreeOctree final : public Octree {
 public:
  PotreeOctree(PotreeMetadata metadata, std::unique_ptr<ByteSource> hierarchy,
               std::unique_ptr<ByteSource> octree)
      : metadata_(std::move(metadata)),
        records_(metadata_),
        hierarchy_(std::move(hierarchy)),
        octree_(std::move(octree)) {
    limits_ = {.hierarchy_file = hierarchy_->name(),
               .octree_file = octree_->name(),
               .hierarchy_size = hierarchy_->size(),
               .octree_size = octree_->size(),
               .record_size = metadata_.record_size};
    describe();

    OctreeNode root;
    root.name = "r";
    root.box = metadata_.cube;
    root.spacing = metadata_.spacing;
    root.children.fill(-1);
    nodes_.push_back(std::move(root));
    // The first chunk, named by metadata.json: an error there is metadata's.
    try {
      checkPotreeChunkRange(0, metadata_.hierarchy.first_chunk_size, "r", 0, limits_);
    } catch (const InputError& e) {
      InputErrorInfo info = e.info();
      info.byte_offset.reset();
      info.element = "hierarchy.firstChunkSize (of metadata.json)";
      throw InputError(std::move(info));
    }
    total_points_ = 0;
    pending_nodes_ = 0;
    readChunk(0, 0, metadata_.hierarchy.first_chunk_size);
  }

  const OctreeInfo& info() const override { return info_; }
  std::span<const OctreeNode> nodes() const override { return nodes_; }
  const PotreeMetadata& metadata() const { return metadata_; }

  void expandHierarchy(std::int32_t index) override {
    assert(index >= 0 && std::size_t(index) < nodes_.size() && "expandHierarchy: no such node");
    // A chain of proxies (a chunk starting with another proxy) ends, or cycles: readChunk
    // refuses a chunk read before, so this loop runs at most once per chunk of the file.
    while (nodes_[std::size_t(index)].hierarchy_pending) {
      const OctreeNode& node = nodes_[std::size_t(index)];
      readChunk(index, node.byte_offset, node.byte_size);
    }
  }

  PointCloud loadNode(const OctreeNode& node) const override {
    PotreeEntry entry;
    entry.point_count = node.point_count;
    entry.byte_offset = node.byte_offset;
    entry.byte_size = node.byte_size;
    std::optional<std::uint64_t> where;  // the entry's offset in hierarchy.bin, when read here
    if (node.hierarchy_pending) {
      // The node's own entry opens its chunk (a chain of proxies is followed a few steps).
      std::uint64_t chunk = node.byte_offset;
      for (int step = 0;; ++step) {
        checkPotreeChunkRange(chunk, kPotreeEntrySize, node.name, chunk, limits_);
        std::array<std::byte, kPotreeEntrySize> bytes;
        hierarchy_->read(chunk, bytes);
        entry = decodePotreeEntry(bytes);
        where = chunk;
        if (entry.type > 2) {
          throw InputError({.file = limits_.hierarchy_file,
                            .byte_offset = chunk,
                            .element = "node " + node.name,
                            .expected = "node type 0, 1 or 2",
                            .found = "type " + std::to_string(entry.type)});
        }
        if (entry.type != 2) break;
        if (step == kPotreeMaxLevel) {
          throw InputError({.file = limits_.hierarchy_file,
                            .byte_offset = chunk,
                            .element = "node " + node.name,
                            .expected = "a chunk that lists the node",
                            .found = "a chain of proxies that does not end"});
        }
        chunk = entry.byte_offset;
      }
      if (entry.point_count != node.point_count) {
        throw InputError({.file = limits_.hierarchy_file,
                          .byte_offset = where,
                          .element = "node " + node.name,
                          .expected = std::to_string(node.point_count) +
                                      " points, as the proxy entry of the node says",
                          .found = std::to_string(entry.point_count) + " in its chunk's entry"});
      }
    }
    checkPotreeDataRange(entry, node.name, where, limits_);
    ByteBuffer bytes(entry.byte_size);
    octree_->read(entry.byte_offset, {bytes.data(), bytes.size()});
    return records_.decode({bytes.data(), bytes.size()}, entry.point_count);
  }

 private:
  void describe() {
    info_.point_count = metadata_.points;
    info_.cube = metadata_.cube;
    info_.quantization = metadata_.quantization;
    info_.spacing = metadata_.spacing;
    info_.bounds = metadata_.cube;
    for (const auto& a : metadata_.attributes) {
      // The position attribute's min and max are the tight bounds PotreeConverter writes.
      if (a.name == "position" && a.min.size() == 3 && a.max.size() == 3) {
        info_.bounds.min = {a.min[0], a.min[1], a.min[2]};
        info_.bounds.max = {a.max[0], a.max[1], a.max[2]};
      }
    }
    records_.describe(info_);
  }

  void readChunk(std::int32_t top, std::uint64_t offset, std::uint64_t size) {
    if (!chunks_read_.insert(offset).second) {
      throw InputError({.file = limits_.hierarchy_file,
                        .byte_offset = offset,
                        .element = "node " + nodes_[std::size_t(top)].name,
                        .expected = "a proxy pointing at a hierarchy chunk not read yet",
                        .found = "a chunk already read (a cycle)"});
    }
    std::vector<std::byte> bytes(size);
    hierarchy_->read(offset, bytes);
    // Running totals over all nodes (a proxy's entry carries its node's count too), updated
    // for the top node and the nodes the chunk appends.
    const std::size_t first_new = nodes_.size();
    const OctreeNode& before = nodes_[std::size_t(top)];
    total_points_ -= before.point_count;  // 0 for the root before the first chunk
    pending_nodes_ -= before.hierarchy_pending ? 1 : 0;
    readPotreeChunk(bytes, offset, top, nodes_, limits_);
    const OctreeNode& after = nodes_[std::size_t(top)];
    total_points_ += after.point_count;
    pending_nodes_ += after.hierarchy_pending ? 1 : 0;
    for (std::size_t i = first_new; i < nodes_.size(); ++i) {
      total_points_ += nodes_[i].point_count;
      pending_nodes_ += nodes_[i].hierarchy_pending ? 1 : 0;
    }
    checkTotal();
  }

  // Once every chunk is read, the nodes' counts must add up to metadata's total.
  void checkTotal() const {
    if (pending_nodes_ > 0) return;
    const std::uint64_t total = total_points_;
    if (total != metadata_.points) {
      throw InputError({.file = limits_.hierarchy_file,
                        .expected = "nodes holding " + std::to_string(metadata_.points) +
                                    " points in all (metadata.json \"points\")",
                        .found = std::to_string(total) + " points in " +
                                 std::to_string(nodes_.size()) + " nodes"});
    }
  }

  PotreeMetadata metadata_;
  PotreeRecordReader records_;
  std::unique_ptr<ByteSource> hierarchy_, octree_;
  PotreeHierarchyLimits limits_;
  OctreeInfo info_;
  std::vector<OctreeNode> nodes_;
  std::set<std::uint64_t> chunks_read_;
  std::uint64_t total_points_ = 0;  // sum of point_count over nodes_
  std::size_t pending_nodes_ = 0;   // nodes with hierarchy_pending
};

std::filesystem::path directoryOf(const std::filesystem::path& path) {
  std::error_code error;
  if (path.filename() == "metadata.json" && !std::filesystem::is_directory(path, error)) {
    return path.parent_path().empty() ? std::filesystem::path(".") : path.parent_path();
  }
  return path;
}

std::string readMetadataText(const std::filesystem::path& file) {
  FileSource source(file);
  if (source.size() > kMaxMetadataBytes) {
    throw InputError({.file = file.string(),
                      .expected = "a metadata.json of at most 64 MiB",
                      .found = std::to_string(source.size()) + " bytes"});
  }
  std::string text(source.size(), '\0');
  source.read(0, std::as_writable_bytes(std::span(text)));
  return text;
}

}  // namespace

bool isPotreeDirectory(const std::filesystem::path& path) {
  std::error_code error;
  const std::filesystem::path dir = directoryOf(path);
  return std::filesystem::is_directory(dir, error) &&
         std::filesystem::is_regular_file(dir / "metadata.json", error);
}

std::unique_ptr<Octree> openPotree(const std::filesystem::path& path) {
  const std::filesystem::path dir = directoryOf(path);
  std::error_code error;
  if (!std::filesystem::is_directory(dir, error)) {
    throw InputError({.file = dir.string(),
                      .expected = "a Potree 2.0 directory",
                      .found = std::filesystem::exists(dir, error) ? "a file" : "nothing",
                      .hint = "a Potree 2.0 directory holds metadata.json, hierarchy.bin and "
                              "octree.bin"});
  }
  const std::filesystem::path metadata_file = dir / "metadata.json";
  PotreeMetadata metadata =
      parsePotreeMetadata(readMetadataText(metadata_file), metadata_file.string());
  auto hierarchy = std::make_unique<FileSource>(dir / "hierarchy.bin");
  auto octree = std::make_unique<FileSource>(dir / "octree.bin");
  return std::make_unique<PotreeOctree>(std::move(metadata), std::move(hierarchy),
                                        std::move(octree));
}

std::unique_ptr<Octree> openPotreeFromMemory(std::string metadata_json,
                                             std::vector<std::byte> hierarchy,
                                             std::vector<std::byte> octree,
                                             const std::string& name) {
  PotreeMetadata metadata = parsePotreeMetadata(metadata_json, name + "/metadata.json");
  return std::make_unique<PotreeOctree>(
      std::move(metadata),
      std::make_unique<MemorySource>(std::move(hierarchy), name + "/hierarchy.bin"),
      std::make_unique<MemorySource>(std::move(octree), name + "/octree.bin"));
}

const PotreeMetadata* potreeMetadata(const Octree& octree) {
  const auto* potree = dynamic_cast<const PotreeOctree*>(&octree);
  return potree ? &potree->metadata() : nullptr;
}

}  // namespace parallax
