#include "core/column.h"

#include <sys/mman.h>

#include <cstdlib>
#include <new>
#include <utility>

namespace parallax {
namespace {

// Below this, malloc is cheaper than a system call and huge pages would waste memory.
constexpr std::size_t kMapThreshold = std::size_t{4} << 20;

}  // namespace

ByteBuffer::ByteBuffer(std::size_t size) : size_(size) {
  if (size == 0) return;
  if (size >= kMapThreshold) {
    void* p = mmap(nullptr, size, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (p == MAP_FAILED) throw std::bad_alloc();
    // Advice only: where THP is off this does nothing and the buffer still works.
    madvise(p, size, MADV_HUGEPAGE);
    data_ = static_cast<std::byte*>(p);
    mapped_ = true;
  } else {
    data_ = static_cast<std::byte*>(std::malloc(size));
    if (data_ == nullptr) throw std::bad_alloc();
  }
}

ByteBuffer::~ByteBuffer() {
  release();
}

ByteBuffer::ByteBuffer(ByteBuffer&& other) noexcept
    : data_(std::exchange(other.data_, nullptr)),
      size_(std::exchange(other.size_, 0)),
      mapped_(std::exchange(other.mapped_, false)) {}

ByteBuffer& ByteBuffer::operator=(ByteBuffer&& other) noexcept {
  if (this != &other) {
    release();
    data_ = std::exchange(other.data_, nullptr);
    size_ = std::exchange(other.size_, 0);
    mapped_ = std::exchange(other.mapped_, false);
  }
  return *this;
}

ByteBuffer ByteBuffer::clone() const {
  ByteBuffer copy(size_);
  if (size_ != 0) std::memcpy(copy.data_, data_, size_);
  return copy;
}

void ByteBuffer::release() {
  if (data_ == nullptr) return;
  if (mapped_) {
    munmap(data_, size_);
  } else {
    std::free(data_);
  }
  data_ = nullptr;
  size_ = 0;
  mapped_ = false;
}

}  // namespace parallax
