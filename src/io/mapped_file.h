// A whole file, read-only, as bytes: memory-mapped where possible, read into memory otherwise
// (pipes, special files, and URLs, fetched whole through core's openByteSource). The bytes live
// as long as the MappedFile.
#pragma once

#include <cstddef>
#include <filesystem>
#include <span>
#include <string>

#include "core/column.h"

namespace parallax {

class MappedFile {
 public:
  // Throws InputError (file named, reason from the system) when it cannot be opened or read.
  explicit MappedFile(const std::filesystem::path& path);
  ~MappedFile();
  MappedFile(MappedFile&& other) noexcept;
  MappedFile& operator=(MappedFile&&) = delete;
  MappedFile(const MappedFile&) = delete;
  MappedFile& operator=(const MappedFile&) = delete;

  std::span<const std::byte> bytes() const { return {data_, size_}; }
  std::size_t size() const { return size_; }
  const std::string& path() const { return path_; }

  // Drops the whole pages inside [offset, offset + length) from this process's resident set
  // once they have been read (the page cache keeps them; a later read faults them back in), so
  // a large file read front to back does not count twice in the loader's peak memory.
  void releaseRead(std::size_t offset, std::size_t length) const;

  // Tells the kernel the range will be read soon, front to back (read-ahead on a cold cache).
  void adviseSequential(std::size_t offset, std::size_t length) const;

 private:
  std::string path_;
  const std::byte* data_ = nullptr;
  std::size_t size_ = 0;
  bool mapped_ = false;
  ByteBuffer fallback_;  // holds the bytes when the file could not be mapped
};

}  // namespace parallax
