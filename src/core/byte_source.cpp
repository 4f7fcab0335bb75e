#include "core/byte_source.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cassert>
#include <cerrno>
#include <cstring>

#include "core/error.h"

namespace parallax {

std::vector<std::byte> ByteSource::readAll(const ReadContext& context) const {
  std::vector<std::byte> bytes(size());
  read(0, bytes, context);
  return bytes;
}

void ByteSource::checkRange(std::uint64_t offset, std::uint64_t size,
                            const ReadContext& context) const {
  if (offset <= this->size() && size <= this->size() - offset) return;
  throw InputError({.file = name(),
                    .byte_offset = offset,
                    .element = std::string(context.element),
                    .expected = std::to_string(size) + " bytes inside the file's " +
                                std::to_string(this->size()),
                    .found = "a range that ends past its end"});
}

namespace {

// Borrowed bytes: the caller keeps them alive (a mapped file read whole by a reader).
class MemoryViewSource : public ByteSource {
 public:
  MemoryViewSource(std::span<const std::byte> bytes, std::string name, std::string version = {})
      : bytes_(bytes), name_(std::move(name)), version_(std::move(version)) {}
  const std::string& name() const override { return name_; }
  std::uint64_t size() const override { return bytes_.size(); }
  const std::string& version() const override { return version_; }
  void read(std::uint64_t offset, std::span<std::byte> out,
            const ReadContext& context) const override {
    checkRange(offset, out.size(), context);
    if (!out.empty()) std::memcpy(out.data(), bytes_.data() + offset, out.size());
  }

 private:
  std::span<const std::byte> bytes_;
  std::string name_, version_;
};

// Owned bytes. The vector is a base class so that it is built before the view of it.
struct OwnedBytes {
  std::vector<std::byte> owned;
};
class MemorySource final : private OwnedBytes, public MemoryViewSource {
 public:
  MemorySource(std::vector<std::byte> bytes, std::string name, std::string version)
      : OwnedBytes{std::move(bytes)},
        MemoryViewSource(owned, std::move(name), std::move(version)) {}
};

class FileSource final : public ByteSource {
 public:
  explicit FileSource(const std::filesystem::path& path) : name_(path.string()) {
    fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd_ < 0) failOpen("to open the file");
    struct stat st {};
    if (::fstat(fd_, &st) != 0) failOpen("to learn its size");
    if (!S_ISREG(st.st_mode)) {
      ::close(fd_);
      fd_ = -1;
      throw InputError({.file = name_, .expected = "a regular file", .found = "something else"});
    }
    size_ = std::uint64_t(st.st_size);
    version_ = std::to_string(size_) + "-" + std::to_string(st.st_ino) + "-" +
               std::to_string(std::int64_t(st.st_mtim.tv_sec) * 1'000'000'000 + st.st_mtim.tv_nsec);
  }
  ~FileSource() override {
    if (fd_ >= 0) ::close(fd_);
  }
  FileSource(const FileSource&) = delete;
  FileSource& operator=(const FileSource&) = delete;

  const std::string& name() const override { return name_; }
  std::uint64_t size() const override { return size_; }
  const std::string& version() const override { return version_; }

  // Read-ahead on a cold page cache: the kernel starts reading the ranges now.
  void prefetch(std::span<const ByteRange> ranges) const override {
    for (const ByteRange& range : ranges) {
      ::posix_fadvise(fd_, off_t(range.offset), off_t(range.size), POSIX_FADV_WILLNEED);
    }
  }

  void read(std::uint64_t offset, std::span<std::byte> out,
            const ReadContext& context) const override {
    checkRange(offset, out.size(), context);
    std::size_t done = 0;
    while (done < out.size()) {
      const ssize_t n = ::pread(fd_, out.data() + done, out.size() - done, off_t(offset + done));
      if (n < 0 && errno == EINTR) continue;
      if (n < 0)
        failRead("to read " + std::to_string(out.size()) + " bytes", offset + done, context);
      if (n == 0) {
        throw InputError({.file = name_,
                          .byte_offset = offset + done,
                          .element = std::string(context.element),
                          .expected = std::to_string(out.size() - done) + " more bytes",
                          .found = "the end of the file",
                          .hint = "the file shrank while it was read"});
      }
      done += std::size_t(n);
    }
  }

 private:
  // While opening: the descriptor is closed (the destructor of a half-built object never runs).
  [[noreturn]] void failOpen(const std::string& what) {
    const std::string reason = std::strerror(errno);
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
    throw InputError({.file = name_, .expected = what, .found = reason});
  }
  [[noreturn]] void failRead(const std::string& what, std::uint64_t at,
                             const ReadContext& context) const {
    const std::string reason = std::strerror(errno);
    throw InputError({.file = name_,
                      .byte_offset = at,
                      .element = std::string(context.element),
                      .expected = what,
                      .found = reason});
  }

  std::string name_;
  int fd_ = -1;
  std::uint64_t size_ = 0;
  std::string version_;
};

}  // namespace

std::unique_ptr<ByteSource> openFileSource(const std::filesystem::path& path) {
  return std::make_unique<FileSource>(path);
}

std::unique_ptr<ByteSource> makeMemorySource(std::vector<std::byte> bytes, std::string name,
                                             std::string version) {
  return std::make_unique<MemorySource>(std::move(bytes), std::move(name), std::move(version));
}

std::unique_ptr<ByteSource> viewMemorySource(std::span<const std::byte> bytes, std::string name) {
  return std::make_unique<MemoryViewSource>(bytes, std::move(name));
}

}  // namespace parallax
