#include "io/mapped_file.h"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <utility>
#include <vector>

#include "core/byte_source.h"
#include "core/byte_source_opener.h"
#include "core/error.h"

namespace parallax {
namespace {

[[noreturn]] void throwSystemError(const std::string& path, const char* what) {
  throw InputError({.file = path, .expected = what, .found = std::strerror(errno)});
}

// Reads a stream of unknown length (a pipe, /dev/stdin) into memory.
ByteBuffer readWhole(int fd, const std::string& path, std::size_t& size) {
  std::vector<std::byte> bytes;
  std::byte block[1 << 16];
  for (;;) {
    ssize_t got = ::read(fd, block, sizeof block);
    if (got < 0) {
      if (errno == EINTR) continue;
      throwSystemError(path, "a readable file");
    }
    if (got == 0) break;
    bytes.insert(bytes.end(), block, block + got);
  }
  ByteBuffer buffer(bytes.size());
  if (!bytes.empty()) std::memcpy(buffer.data(), bytes.data(), bytes.size());
  size = bytes.size();
  return buffer;
}

}  // namespace

MappedFile::MappedFile(const std::filesystem::path& path) : path_(path.string()) {
  if (isUrl(path_)) {
    // A URL (core/byte_source_opener.h): fetched whole through its byte source.
    const std::unique_ptr<ByteSource> source = openByteSource(path_);
    size_ = std::size_t(source->size());
    if (size_ == 0) return;
    fallback_ = ByteBuffer(size_);
    source->read(0, std::span(fallback_.data(), size_), {.element = "the whole file"});
    data_ = fallback_.data();
    return;
  }
  int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throwSystemError(path_, "a readable file");
  struct stat info {};
  if (::fstat(fd, &info) != 0) {
    int saved = errno;
    ::close(fd);
    errno = saved;
    throwSystemError(path_, "a readable file");
  }
  if (S_ISDIR(info.st_mode)) {
    ::close(fd);
    throw InputError({.file = path_, .expected = "a file", .found = "a directory"});
  }
  if (S_ISREG(info.st_mode)) {
    size_ = std::size_t(info.st_size);
    if (size_ == 0) {
      ::close(fd);
      return;
    }
    void* p = ::mmap(nullptr, size_, PROT_READ, MAP_PRIVATE, fd, 0);
    if (p != MAP_FAILED) {
      ::close(fd);
      data_ = static_cast<const std::byte*>(p);
      mapped_ = true;
      return;
    }
  }
  try {
    fallback_ = readWhole(fd, path_, size_);
  } catch (...) {
    ::close(fd);
    throw;
  }
  ::close(fd);
  data_ = fallback_.data();
}

MappedFile::~MappedFile() {
  if (mapped_) ::munmap(const_cast<std::byte*>(data_), size_);
}

MappedFile::MappedFile(MappedFile&& other) noexcept
    : path_(std::move(other.path_)),
      data_(std::exchange(other.data_, nullptr)),
      size_(std::exchange(other.size_, 0)),
      mapped_(std::exchange(other.mapped_, false)),
      fallback_(std::move(other.fallback_)) {}

void MappedFile::adviseSequential(std::size_t offset, std::size_t length) const {
  if (!mapped_ || offset >= size_) return;
  // madvise wants a page-aligned start.
  std::size_t page = std::size_t(::sysconf(_SC_PAGESIZE));
  std::size_t aligned = offset / page * page;
  length = std::min(length + (offset - aligned), size_ - aligned);
  auto* start = const_cast<std::byte*>(data_) + aligned;
  ::madvise(start, length, MADV_SEQUENTIAL);
  ::madvise(start, length, MADV_WILLNEED);
}

}  // namespace parallax

namespace parallax {

void MappedFile::releaseRead(std::size_t offset, std::size_t length) const {
  if (!mapped_ || offset >= size_) return;
  std::size_t page = std::size_t(::sysconf(_SC_PAGESIZE));
  std::size_t first = (offset + page - 1) / page * page;
  std::size_t last = std::min(offset + length, size_) / page * page;
  if (last > first) ::madvise(const_cast<std::byte*>(data_) + first, last - first, MADV_DONTNEED);
}

}  // namespace parallax
