#include "io/point_file.h"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <exception>
#include <memory>
#include <stdexcept>
#include <system_error>
#include <utility>

#include "core/byte_source.h"
#include "core/byte_source_opener.h"
#include "core/error.h"
#include "io/partial_output.h"

namespace parallax {
namespace {

constexpr std::size_t kSniffBytes = 64 << 10;

[[noreturn]] void throwUnknownFormat(const std::filesystem::path& path) {
  // What a user most often gives by mistake, said as such: a folder that is no octree, an empty
  // file (a download or a copy that failed).
  std::error_code error;
  if (std::filesystem::is_directory(path, error)) {
    throw InputError({.file = path.string(),
                      .expected = "a point cloud file, or a Potree 2.0 octree directory "
                                  "(metadata.json, hierarchy.bin, octree.bin)",
                      .found = "a directory without them",
                      .hint = supportedFormatsText()});
  }
  const bool empty = std::filesystem::is_regular_file(path, error) &&
                     std::filesystem::file_size(path, error) == 0 && !error;
  throw InputError({.file = path.string(),
                    .byte_offset = 0,
                    .expected = "a point cloud file",
                    .found = empty ? "an empty file (0 bytes)" : "an unknown format",
                    .hint = supportedFormatsText()});
}

// The row of the file's format; InputError for an unknown one.
const PointFormatEntry& rowOf(const std::filesystem::path& path) {
  const PointFormatEntry* row = detectPointFormat(path).entry();
  if (row == nullptr) throwUnknownFormat(path);
  return *row;
}

// ".ply, .las, ..., .asc or .pts".
std::string extensionsOr() {
  const std::vector<std::string> extensions = writableExtensions();
  std::string out;
  for (std::size_t i = 0; i < extensions.size(); ++i) {
    if (i > 0) out += i + 1 == extensions.size() ? " or " : ", ";
    out += extensions[i];
  }
  return out;
}

[[noreturn]] void throwUnknownOutput(const std::filesystem::path& path) {
  throw InputError({.file = path.string(),
                    .expected = "an output name ending in " + extensionsOr(),
                    .found = "'" + path.extension().string() + "'",
                    .hint = supportedFormatsText()});
}

}  // namespace

std::string pointFormatName(PointFormat format) {
  const PointFormatEntry* row = format.entry();
  return row ? row->name : "unknown";
}

std::string supportedFormatsText() {
  std::string out = "supported formats: ";
  bool first = true;
  for (const PointFormatEntry* row : pointFormats()) {
    out += (first ? "" : ", ") + row->description;
    first = false;
  }
  return out;
}

PointFormat detectPointFormatFromMemory(std::span<const std::byte> bytes) {
  return detectFormatOf(bytes);
}

namespace {

// The first kSniffBytes of a file (fewer where it is shorter): local files with stdio, so that
// pipes and special files are detected too; URLs through their byte source (one range).
std::vector<std::byte> fileHead(const std::filesystem::path& path) {
  std::vector<std::byte> head;
  if (isUrl(path.string())) {
    const std::unique_ptr<ByteSource> source = openByteSource(path.string(), kSniffBytes);
    head.resize(std::size_t(std::min<std::uint64_t>(source->size(), kSniffBytes)));
    source->read(0, head, {.element = "the first bytes (format detection)"});
    return head;
  }
  std::FILE* file = std::fopen(path.c_str(), "rb");
  if (file == nullptr) {
    throw InputError(
        {.file = path.string(), .expected = "a readable file", .found = std::strerror(errno)});
  }
  head.resize(kSniffBytes);
  const std::size_t got = std::fread(head.data(), 1, head.size(), file);
  std::fclose(file);
  head.resize(got);
  return head;
}

}  // namespace

PointFormat detectPointFormat(const std::filesystem::path& path) {
  const std::vector<std::byte> head = fileHead(path);
  const PointFormat format = detectFormatOf(head);
  // A file whose content matched no signature (the fallback, text, or nothing) but whose name
  // asks for a format with one: that format's reader says what is wrong with it (a PCD without
  // its header would otherwise be read as plain text, silently).
  const PointFormatEntry* row = format.entry();
  if (row == nullptr || row->fallback) {
    const PointFormatEntry* named = formatOfExtension(path).entry();
    if (named != nullptr && !named->fallback && named->read) return formatOfExtension(path);
  }
  return format;
}

PointFileHeader readPointFileHeader(const std::filesystem::path& path) {
  const PointFormatEntry& row = rowOf(path);
  return row.header ? row.header(path) : PointFileHeader{};
}

std::optional<std::uint64_t> headerPointCount(const std::filesystem::path& path) {
  try {
    return readPointFileHeader(path).point_count;
  } catch (const std::exception&) {
    return std::nullopt;  // the ordinary read says what is wrong
  }
}

PointCloud readPointFile(const std::filesystem::path& path, const PointReadOptions& options) {
  return rowOf(path).read(path, options);
}

bool hasPointFilePreview(PointFormat format) {
  const PointFormatEntry* row = format.entry();
  return row != nullptr && bool(row->preview);
}

PointCloud readPointFilePreview(const std::filesystem::path& path, std::uint64_t max_points) {
  const PointFormatEntry& row = rowOf(path);
  if (!row.preview) {
    throw InputError(
        {.file = path.string(),
         .expected = "a " + previewFormatNamesText() + " file (a sample is read from those only)",
         .found = row.name});
  }
  return row.preview(path, max_points);
}

std::unique_ptr<PointChunkSource> openPointChunks(const std::filesystem::path& path,
                                                  const ChunkSourceOptions& options) {
  const PointFormatEntry& row = rowOf(path);
  if (!row.open_chunks) {
    throw InputError({.file = path.string(),
                      .expected = "a format that streams in chunks",
                      .found = row.name,
                      .hint = "convert it to PLY or LAS first"});
  }
  return row.open_chunks(path, options);
}

bool rereadsCheaply(const std::filesystem::path& path) {
  const PointFormatEntry& row = rowOf(path);
  return row.rereads_cheaply && row.rereads_cheaply(path);
}

PointFormat formatForExtension(const std::filesystem::path& path) {
  return formatOfExtension(path);
}

std::vector<std::string> describeWriteLosses(const PointCloud& cloud,
                                             const std::filesystem::path& path,
                                             const PointWriteOptions& options) {
  const PointFormatEntry* row = formatForExtension(path).entry();
  if (row == nullptr) return {};
  std::vector<std::string> losses;
  if (row->write_losses) losses = row->write_losses(cloud, path, options);
  if (!options.source.empty() && !row->writes_crs) {
    const CoordinateSystem crs = readPointFileHeader(options.source).crs;
    if (!crs.empty()) {
      losses.push_back("the coordinate reference system (" + crs.summary() + "): " + row->name +
                       " has no place for it");
    }
  }
  return losses;
}

void writePointFile(const PointCloud& cloud, const std::filesystem::path& path,
                    const PointWriteOptions& options) {
  const PointFormatEntry* row = formatForExtension(path).entry();
  if (row == nullptr || !row->write) throwUnknownOutput(path);
  row->write(cloud, path, options);
}

OutputFile::OutputFile(const std::filesystem::path& path) : path_(path) {
  // A hidden ".NAME.partial-PID-N" beside the target (partial_output.h), unique per writer.
  temp_ = newPartialFilePath(path);
  file_ = std::fopen(temp_.c_str(), "wb");
  if (file_ == nullptr) fail("cannot create");
  std::setvbuf(file_, nullptr, _IOFBF, 1 << 20);
}

OutputFile::~OutputFile() {
  if (committed_) return;
  if (file_) std::fclose(file_);
  std::error_code ignored;
  std::filesystem::remove(temp_, ignored);
}

void OutputFile::fail(const char* what) {
  throw std::runtime_error(std::string(what) + " '" + temp_.string() + "' (for '" + path_.string() +
                           "'): " + std::strerror(errno));
}

void OutputFile::write(const void* data, std::size_t size) {
  if (size != 0 && std::fwrite(data, 1, size, file_) != size) fail("cannot write");
}

void OutputFile::writeAt(std::uint64_t offset, const void* data, std::size_t size) {
  if (std::fflush(file_) != 0) fail("cannot write");
  long back = std::ftell(file_);
  if (back < 0 || std::fseek(file_, long(offset), SEEK_SET) != 0) fail("cannot seek in");
  write(data, size);
  if (std::fflush(file_) != 0 || std::fseek(file_, back, SEEK_SET) != 0) fail("cannot seek in");
}

void OutputFile::commit() {
  std::FILE* file = std::exchange(file_, nullptr);
  if (std::fclose(file) != 0) fail("cannot write");
  std::error_code error;
  std::filesystem::rename(temp_, path_, error);
  if (error) {
    throw std::runtime_error("cannot rename '" + temp_.string() + "' to '" + path_.string() +
                             "': " + error.message());
  }
  committed_ = true;
}

}  // namespace parallax
