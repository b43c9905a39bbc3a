// Replaces the global allocation functions of a test program so that a test can count
// heap allocations (pfxAllocationCount() before and after a step). Include it in exactly
// one source file of a test program.
#pragma once

#include <atomic>
#include <cstdlib>
#include <new>

namespace pfx_test {
inline std::atomic<long> g_allocationCount{0};
inline long pfxAllocationCount() { return g_allocationCount.load(); }
}  // namespace pfx_test

// GCC 12 sees new and free paired once these are inlined into a caller and warns
// (-Wmismatched-new-delete), though the pair is the one defined here.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
#endif

void* operator new(std::size_t size) {
  ++pfx_test::g_allocationCount;
  if (void* p = std::malloc(size ? size : 1)) return p;
  throw std::bad_alloc();
}
void* operator new(std::size_t size, std::align_val_t align) {
  ++pfx_test::g_allocationCount;
  const std::size_t a = static_cast<std::size_t>(align);
  if (void* p = std::aligned_alloc(a, (size + a - 1) / a * a)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
