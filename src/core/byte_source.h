// Random-access bytes: what every reader of a range-addressable format reads through (Potree 2.0
// octree.bin and hierarchy.bin, COPC and LAS headers and chunks). A local file is one source
// (pread); an HTTP(S) server or object store is another (net/http_byte_source.h); tests and
// fuzzers use bytes in memory. A reader asks for ranges and never learns which it has.
//
// Contract of every source:
// - size() and version() are fixed when the source is opened. version() identifies the bytes
//   (an HTTP ETag or Last-Modified, a local file's size, inode and modification time): a source
//   that sees its version change under it throws InputError rather than return bytes of two
//   versions.
// - read() is thread-safe: any number of threads may read at once (no shared file offset).
// - Errors are InputErrors naming the file or URL, the byte offset, the element being read (the
//   caller's ReadContext::element, e.g. "node r0142"), what was expected and what was found.
// - prefetch() is a hint and never waits: sources with latency start fetching the ranges, a
//   local file asks the kernel to read them ahead, memory ignores it.
#pragma once

#include <compare>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <stdexcept>
#include <stop_token>
#include <string>
#include <string_view>
#include <vector>

namespace parallax {

struct ByteRange {
  std::uint64_t offset = 0;
  std::uint64_t size = 0;
  std::uint64_t end() const { return offset + size; }
  friend auto operator<=>(const ByteRange&, const ByteRange&) = default;
};

// What a read is for, and whether it is still wanted.
struct ReadContext {
  // Requested: the caller no longer wants the bytes; a source that waits for them (the
  // network) gives up and throws ReadCancelled. Local sources ignore it (a read is quick).
  std::stop_token cancel;
  // Names what the bytes are for in error messages ("node r0142", "hierarchy chunk of r0").
  std::string_view element;
};

// Thrown by ByteSource::read when ReadContext::cancel was requested before the bytes arrived.
// Not an input error: nothing is wrong with the data, the caller stopped wanting it.
class ReadCancelled : public std::runtime_error {
 public:
  ReadCancelled() : std::runtime_error("read cancelled: the bytes are no longer wanted") {}
};

class ByteSource {
 public:
  virtual ~ByteSource() = default;

  // The path or URL, as messages name it.
  virtual const std::string& name() const = 0;
  // Bytes in the source.
  virtual std::uint64_t size() const = 0;
  // Identity of these bytes (see the file comment); empty when the source has none.
  virtual const std::string& version() const = 0;
  // False for sources where a read may wait on a network: callers keep such reads off threads
  // that must not block (the frame loop).
  virtual bool local() const { return true; }

  // Reads out.size() bytes at `offset`. A range past size() is an InputError; so is every
  // failure of the medium. Throws ReadCancelled (see ReadContext::cancel).
  virtual void read(std::uint64_t offset, std::span<std::byte> out,
                    const ReadContext& context = {}) const = 0;

  // The ranges that will be read soon, most urgent first; replaces the previous hint (ranges
  // it named that this one does not may be dropped, unless a read is waiting for them). Reads
  // of hinted ranges are served from what was fetched. Never waits. Default: nothing.
  virtual void prefetch(std::span<const ByteRange> ranges) const { (void)ranges; }

  // The whole source as bytes (small files: metadata, headers). Throws as read().
  std::vector<std::byte> readAll(const ReadContext& context = {}) const;
  // Checks [offset, offset + size) against size(); throws InputError naming `context.element`.
  void checkRange(std::uint64_t offset, std::uint64_t size, const ReadContext& context) const;
};

// A local file read with pread. Throws InputError (the path, what failed, strerror) when it
// cannot be opened or is not a regular file. Its version is "size-inode-mtime_ns"; read()
// checks that the file did not shrink under it.
std::unique_ptr<ByteSource> openFileSource(const std::filesystem::path& path);

// Bytes in memory (tests, fuzzers, files fetched whole). `name` stands for them in messages.
std::unique_ptr<ByteSource> makeMemorySource(std::vector<std::byte> bytes, std::string name,
                                             std::string version = {});
// Bytes in memory that the caller owns and keeps alive as long as the source (a file read or
// mapped whole by a reader). `name` stands for them in messages; the version is empty.
std::unique_ptr<ByteSource> viewMemorySource(std::span<const std::byte> bytes, std::string name);

}  // namespace parallax
