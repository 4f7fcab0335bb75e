// libFuzzer target for the LAZ reader: any bytes must give a cloud or an InputError, never a
// crash, an out-of-bounds read, a hang or an allocation beyond what the input's size justifies.
// Every chunk is decoded (on one thread, so that a failure reproduces exactly), and the chunk
// reader (LazChunkReader, in batches that end inside chunks) and the preview (readLazPreview,
// whole chunks spread through the file, every k-th point kept) are run on the same bytes. Those
// two read files: the input is given to them as a memory file (memfd), a new one each run, so
// that no run sees another's file (the chunk reader remembers a file's colours by path, size and
// modification time).
#include <sys/mman.h>
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

#include "core/error.h"
#include "io/laz_reader.h"

namespace {

// The input as a file: /proc/self/fd/N of a memfd holding it; closed on destruction.
class MemoryFile {
 public:
  MemoryFile(const std::uint8_t* data, std::size_t size) : fd_(memfd_create("fuzz.laz", 0)) {
    std::size_t written = 0;
    while (fd_ >= 0 && written < size) {
      const ssize_t n = write(fd_, data + written, size - written);
      if (n <= 0) break;
      written += std::size_t(n);
    }
    ok_ = fd_ >= 0 && written == size;
  }
  ~MemoryFile() {
    if (fd_ >= 0) close(fd_);
  }
  MemoryFile(const MemoryFile&) = delete;
  MemoryFile& operator=(const MemoryFile&) = delete;
  bool ok() const { return ok_; }
  std::string path() const { return "/proc/self/fd/" + std::to_string(fd_); }

 private:
  int fd_;
  bool ok_ = false;
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::span<const std::byte> bytes(reinterpret_cast<const std::byte*>(data), size);
  try {
    parallax::PointCloud cloud =
        parallax::readLazFromMemory(bytes, "fuzz.laz", {.parallel = false});
    (void)cloud;
  } catch (const parallax::InputError&) {
  }
  const MemoryFile file(data, size);
  if (!file.ok()) return 0;
  try {
    parallax::LazChunkReader reader(file.path());
    parallax::PointCloud chunk;
    while (reader.next(chunk, 257)) {
    }
  } catch (const parallax::InputError&) {
  }
  try {
    parallax::PointCloud preview = parallax::readLazPreview(file.path(), 100);
    (void)preview;
  } catch (const parallax::InputError&) {
  }
  return 0;
}
