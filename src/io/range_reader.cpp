#include "io/range_reader.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <utility>

#include "core/error.h"

namespace parallax {

RangeReader::RangeReader(const std::filesystem::path& path) : name_(path.string()) {
  fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd_ < 0) {
    throw InputError({.file = name_, .expected = "a readable file", .found = std::strerror(errno)});
  }
  struct stat info {};
  if (::fstat(fd_, &info) != 0 || !S_ISREG(info.st_mode)) {
    const int error = errno;
    ::close(fd_);
    fd_ = -1;
    throw InputError({.file = name_,
                      .expected = "a regular file",
                      .found = S_ISDIR(info.st_mode) ? "a directory" : std::strerror(error)});
  }
  size_ = std::uint64_t(info.st_size);
}

RangeReader::RangeReader(std::span<const std::byte> bytes, std::string name)
    : name_(std::move(name)), memory_(bytes), size_(bytes.size()) {}

RangeReader::~RangeReader() {
  if (fd_ >= 0) ::close(fd_);
}

RangeReader::RangeReader(RangeReader&& other) noexcept
    : name_(std::move(other.name_)),
      fd_(std::exchange(other.fd_, -1)),
      memory_(other.memory_),
      size_(other.size_) {}

void RangeReader::read(std::uint64_t offset, std::size_t length, std::byte* out) const {
  if (offset > size_ || length > size_ - offset) {
    throw InputError({.file = name_,
                      .byte_offset = offset,
                      .expected = std::to_string(length) + " bytes inside the file (" +
                                  std::to_string(size_) + " bytes)",
                      .found = "the end of the file",
                      .hint = "the file may be truncated"});
  }
  if (fd_ < 0) {
    if (length != 0) std::memcpy(out, memory_.data() + offset, length);
    return;
  }
  std::size_t done = 0;
  while (done < length) {
    const ssize_t got = ::pread(fd_, out + done, length - done, off_t(offset + done));
    if (got < 0 && errno == EINTR) continue;
    if (got <= 0) {
      throw InputError({.file = name_,
                        .byte_offset = offset + done,
                        .expected = "readable bytes",
                        .found = got < 0 ? std::strerror(errno) : "the end of the file"});
    }
    done += std::size_t(got);
  }
}

void RangeReader::willNeed(std::uint64_t offset, std::uint64_t length) const {
  if (fd_ >= 0) ::posix_fadvise(fd_, off_t(offset), off_t(length), POSIX_FADV_WILLNEED);
}

}  // namespace parallax
