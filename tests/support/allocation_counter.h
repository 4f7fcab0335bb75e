// Counts what the process asks the global operator new for, so that a test can bound the memory
// a call allocates instead of timing it ("fails fast" as a number of bytes, which does not depend
// on the machine's load or a sanitizer's slowdown).
//
// Linking tests/support/allocation_counter.cpp into a test executable replaces the global
// operator new and delete (all threads: TBB's workers and the test framework's included), and
// with the linker options of parallax_count_allocations() (tests/CMakeLists.txt) it wraps malloc,
// calloc, realloc and anonymous mmap for every object linked statically: the product's modules,
// whose columns are malloc'ed or mmap'ed (src/core/column.cpp). A reader that sized its columns
// from a lying count is seen, however it allocated. Not seen: what shared libraries allocate
// inside themselves with malloc (libstdc++'s own operator new is replaced; TBB's and the C
// library's internals are small), and file mappings (page cache, not allocations).
#pragma once

#include <cstdint>

namespace parallax::test {

// Bytes requested (operator new, malloc, calloc, realloc, anonymous mmap) since the process
// started, and the largest single request.
std::uint64_t allocatedBytes();
std::uint64_t largestAllocation();
// Forgets the largest request so far (the next largestAllocation() covers only what follows).
void resetLargestAllocation();

// Bytes requested (and the largest request) from its construction on.
class AllocationScope {
 public:
  AllocationScope() : start_(allocatedBytes()) { resetLargestAllocation(); }
  std::uint64_t bytes() const { return allocatedBytes() - start_; }
  std::uint64_t largest() const { return largestAllocation(); }

 private:
  std::uint64_t start_;
};

}  // namespace parallax::test
