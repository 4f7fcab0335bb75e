// Counts what the process asks the global operator new for, so that a test can bound the memory
// a call allocates instead of timing it ("fails fast" as a number of bytes, which does not depend
// on the machine's load or a sanitizer's slowdown).
//
// Linking tests/support/allocation_counter.cpp into a test executable replaces the global
// operator new and delete (all threads, every allocation of the process: TBB's workers and the
// test framework's included). Allocations that bypass operator new (malloc, mmap) are not seen.
#pragma once

#include <cstdint>

namespace parallax::test {

// Bytes requested from operator new since the process started, and the largest single request.
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
