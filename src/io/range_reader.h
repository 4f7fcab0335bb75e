// Byte ranges of a file read on demand into the caller's buffers (pread), or of bytes already
// in memory (tests, fuzzing). Readers that decode a large file in parallel copy each range into
// a small per-thread buffer instead of mapping the file: the file's pages then stay in the page
// cache only, and the process holds the decoded columns plus a few buffers (a mapping keeps every
// page it touched resident until it is released).
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>

namespace parallax {

class RangeReader {
 public:
  // Opens `path`; throws InputError (file named, reason from the system) when it cannot.
  explicit RangeReader(const std::filesystem::path& path);
  // Reads from `bytes`, which must outlive the reader; `name` stands for the file in messages.
  RangeReader(std::span<const std::byte> bytes, std::string name);
  ~RangeReader();
  RangeReader(RangeReader&& other) noexcept;
  RangeReader& operator=(RangeReader&&) = delete;
  RangeReader(const RangeReader&) = delete;
  RangeReader& operator=(const RangeReader&) = delete;

  std::uint64_t size() const { return size_; }
  const std::string& name() const { return name_; }

  // Copies [offset, offset + length) into `out`; throws InputError naming the file and the
  // offset when the range is not inside the file or the read fails. Thread-safe.
  void read(std::uint64_t offset, std::size_t length, std::byte* out) const;

  // Tells the kernel that [offset, offset + length) will be read soon (read-ahead).
  void willNeed(std::uint64_t offset, std::uint64_t length) const;

 private:
  std::string name_;
  int fd_ = -1;
  std::span<const std::byte> memory_;
  std::uint64_t size_ = 0;
};

}  // namespace parallax
