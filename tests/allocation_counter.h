// Counts heap allocations, for the tests of docs/architecture.md rule 7 ("the inner loop does not
// allocate"). It replaces every replaceable global operator new and delete (plain, array, nothrow,
// aligned, sized), so include it in exactly one source file of a test executable; read
// AllocationCount() before and after the code under test.
//
// All forms are replaced together on purpose: when only some are, an object allocated by the
// runtime's form (say nothrow new) is released by ours, and AddressSanitizer rightly reports an
// alloc-dealloc mismatch. Every form here allocates with malloc or aligned_alloc and releases
// with free, so any pairing of them is consistent.
#pragma once

#include <atomic>
#include <cstdlib>
#include <new>

namespace patlab::testing {
inline std::atomic<long> g_allocation_count{0};
inline long AllocationCount() { return g_allocation_count.load(); }

inline void* CountedAllocate(std::size_t size) noexcept {
  ++g_allocation_count;
  return std::malloc(size == 0 ? 1 : size);
}
inline void* CountedAllocate(std::size_t size, std::align_val_t align) noexcept {
  ++g_allocation_count;
  const auto alignment = static_cast<std::size_t>(align);
  // aligned_alloc needs a size that is a positive multiple of the alignment.
  const std::size_t rounded = (size == 0 ? 1 : size + alignment - 1) / alignment * alignment;
  return std::aligned_alloc(alignment, rounded);
}
template <typename... Align>
void* CountedAllocateOrThrow(std::size_t size, Align... align) {
  if (void* p = CountedAllocate(size, align...)) return p;
  throw std::bad_alloc();
}
}  // namespace patlab::testing

// NOLINTBEGIN(misc-new-delete-overloads, cert-dcl58-cpp)
void* operator new(std::size_t size) { return patlab::testing::CountedAllocateOrThrow(size); }
void* operator new[](std::size_t size) { return patlab::testing::CountedAllocateOrThrow(size); }
void* operator new(std::size_t size, std::align_val_t align) {
  return patlab::testing::CountedAllocateOrThrow(size, align);
}
void* operator new[](std::size_t size, std::align_val_t align) {
  return patlab::testing::CountedAllocateOrThrow(size, align);
}
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
  return patlab::testing::CountedAllocate(size);
}
void* operator new[](std::size_t size, const std::nothrow_t&) noexcept {
  return patlab::testing::CountedAllocate(size);
}
void* operator new(std::size_t size, std::align_val_t align, const std::nothrow_t&) noexcept {
  return patlab::testing::CountedAllocate(size, align);
}
void* operator new[](std::size_t size, std::align_val_t align, const std::nothrow_t&) noexcept {
  return patlab::testing::CountedAllocate(size, align);
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t, const std::nothrow_t&) noexcept { std::free(p); }
// NOLINTEND(misc-new-delete-overloads, cert-dcl58-cpp)
