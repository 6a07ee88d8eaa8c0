// Counts heap allocations, for the tests of docs/architecture.md rule 7 ("the inner loop does not
// allocate"). It replaces the global operator new and delete, so include it in exactly one
// source file of a test executable; read AllocationCount() before and after the code under test.
#pragma once

#include <atomic>
#include <cstdlib>
#include <new>

namespace patlab::testing {
inline std::atomic<long> g_allocation_count{0};
inline long AllocationCount() { return g_allocation_count.load(); }
}  // namespace patlab::testing

void* operator new(std::size_t size) {
  ++patlab::testing::g_allocation_count;
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
