// Flat, uninitialised storage for one attribute of many points.
//
// Columns are allocated without being touched: the first write (in the parallel decode loop) is
// what faults pages in, so the page-fault cost, the real wall when loading hundreds of MB, is
// spread over all cores. Large buffers come from mmap with MADV_HUGEPAGE, which cuts the number
// of faults by 512 where transparent huge pages are enabled in `madvise` mode.
#pragma once

#include <cassert>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <type_traits>
#include <utility>

namespace parallax {

// Move-only owner of `size` bytes; contents are indeterminate until written.
class ByteBuffer {
 public:
  ByteBuffer() = default;
  explicit ByteBuffer(std::size_t size);
  ~ByteBuffer();
  ByteBuffer(ByteBuffer&& other) noexcept;
  ByteBuffer& operator=(ByteBuffer&& other) noexcept;
  ByteBuffer(const ByteBuffer&) = delete;
  ByteBuffer& operator=(const ByteBuffer&) = delete;

  std::byte* data() { return data_; }
  const std::byte* data() const { return data_; }
  std::size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }

  // A deep copy (tests and small chunks; never on a hot path).
  ByteBuffer clone() const;

 private:
  void release();

  std::byte* data_ = nullptr;
  std::size_t size_ = 0;
  bool mapped_ = false;
};

// A typed view over a ByteBuffer: `size()` elements of trivially copyable T.
template <class T>
class Column {
  static_assert(std::is_trivially_copyable_v<T>);

 public:
  Column() = default;
  explicit Column(std::size_t count) : bytes_(count * sizeof(T)), count_(count) {}
  Column(Column&& other) noexcept
      : bytes_(std::move(other.bytes_)), count_(std::exchange(other.count_, 0)) {}
  Column& operator=(Column&& other) noexcept {
    bytes_ = std::move(other.bytes_);
    count_ = std::exchange(other.count_, 0);
    return *this;
  }

  T* data() { return reinterpret_cast<T*>(bytes_.data()); }
  const T* data() const { return reinterpret_cast<const T*>(bytes_.data()); }
  std::size_t size() const { return count_; }
  bool empty() const { return count_ == 0; }
  T& operator[](std::size_t i) {
    assert(i < count_ && "Column index out of range");
    return data()[i];
  }
  const T& operator[](std::size_t i) const {
    assert(i < count_ && "Column index out of range");
    return data()[i];
  }
  std::span<T> span() { return {data(), count_}; }
  std::span<const T> span() const { return {data(), count_}; }
  T* begin() { return data(); }
  T* end() { return data() + count_; }
  const T* begin() const { return data(); }
  const T* end() const { return data() + count_; }

  Column clone() const {
    Column copy;
    copy.bytes_ = bytes_.clone();
    copy.count_ = count_;
    return copy;
  }

 private:
  ByteBuffer bytes_;
  std::size_t count_ = 0;
};

}  // namespace parallax
