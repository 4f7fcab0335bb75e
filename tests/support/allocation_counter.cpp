// The replacement of the global operator new and delete behind allocation_counter.h. Every form
// that can free what these forms allocate is replaced too (sized and nothrow deletes), so that
// sanitizers see malloc paired with free throughout; the aligned forms are left to the runtime
// and pair among themselves.
#include "support/allocation_counter.h"

#include <sys/mman.h>
#include <sys/types.h>

#include <atomic>
#include <cstdlib>
#include <new>

// The real functions behind the linker's --wrap (parallax_count_allocations()).
extern "C" {
void* __real_malloc(std::size_t size);
void* __real_calloc(std::size_t count, std::size_t size);
void* __real_realloc(void* p, std::size_t size);
void* __real_mmap(void* address, std::size_t length, int protection, int flags, int fd,
                  off_t offset);
}

namespace parallax::test {
namespace {

std::atomic<std::uint64_t> g_allocated{0};
std::atomic<std::uint64_t> g_largest{0};

void count(std::size_t size) noexcept {
  g_allocated.fetch_add(size, std::memory_order_relaxed);
  std::uint64_t largest = g_largest.load(std::memory_order_relaxed);
  while (size > largest &&
         !g_largest.compare_exchange_weak(largest, size, std::memory_order_relaxed)) {
  }
}

void* allocate(std::size_t size) noexcept {
  count(size);
  return __real_malloc(size == 0 ? 1 : size);
}

}  // namespace

std::uint64_t allocatedBytes() {
  return g_allocated.load(std::memory_order_relaxed);
}
std::uint64_t largestAllocation() {
  return g_largest.load(std::memory_order_relaxed);
}
void resetLargestAllocation() {
  g_largest.store(0, std::memory_order_relaxed);
}

}  // namespace parallax::test

extern "C" {
void* __wrap_malloc(std::size_t size) {
  parallax::test::count(size);
  return __real_malloc(size);
}
void* __wrap_calloc(std::size_t count, std::size_t size) {
  parallax::test::count(count * size);
  return __real_calloc(count, size);
}
// The new size is counted whole: an upper bound of what a growth adds.
void* __wrap_realloc(void* p, std::size_t size) {
  parallax::test::count(size);
  return __real_realloc(p, size);
}
// Anonymous mappings are memory; a file's mapping is the page cache's.
void* __wrap_mmap(void* address, std::size_t length, int protection, int flags, int fd,
                  off_t offset) {
  if (flags & MAP_ANONYMOUS) parallax::test::count(length);
  return __real_mmap(address, length, protection, flags, fd, offset);
}
}

void* operator new(std::size_t size) {
  if (void* p = parallax::test::allocate(size)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t size) {
  if (void* p = parallax::test::allocate(size)) return p;
  throw std::bad_alloc();
}
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
  return parallax::test::allocate(size);
}
void* operator new[](std::size_t size, const std::nothrow_t&) noexcept {
  return parallax::test::allocate(size);
}
void operator delete(void* p) noexcept {
  std::free(p);
}
void operator delete[](void* p) noexcept {
  std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
  std::free(p);
}
void operator delete[](void* p, std::size_t) noexcept {
  std::free(p);
}
void operator delete(void* p, const std::nothrow_t&) noexcept {
  std::free(p);
}
void operator delete[](void* p, const std::nothrow_t&) noexcept {
  std::free(p);
}
