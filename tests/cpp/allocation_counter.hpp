// Counts every heap allocation of the process while armed (see
// allocation_counter.cpp, which replaces the allocation functions).
#pragma once
#include <cstddef>

namespace soadyn_test {

struct AllocationCounts {
  long operator_new, c_alloc, frees;
  long allocations() const { return operator_new + c_alloc; }
};

void arm_counter();
AllocationCounts disarm_counter();
// Proves the counter sees std::vector, over-aligned new and libc's own malloc
// (prints what it saw); a test must fail when this returns false.
bool allocation_counter_works(std::size_t probe_size);

}  // namespace soadyn_test
