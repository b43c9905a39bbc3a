#include "pfx/base_level/base/pfx_utility_allocator.h"

#include <cstdlib>

namespace pfx {

namespace {

// std::aligned_alloc wants a size that is a multiple of the alignment.
void* defaultAllocate(std::size_t bytes, std::size_t alignment) {
  return std::aligned_alloc(alignment, (bytes + alignment - 1) & ~(alignment - 1));
}

void defaultFree(void* pointer) { std::free(pointer); }

PfxUtilityAllocateFunc g_allocate = defaultAllocate;
PfxUtilityFreeFunc g_free = defaultFree;

}  // namespace

PfxInt32 pfxSetUtilityAllocator(PfxUtilityAllocateFunc allocate, PfxUtilityFreeFunc free) {
  if (!allocate && !free) {
    g_allocate = defaultAllocate;
    g_free = defaultFree;
    return PFX_OK;
  }
  if (!allocate || !free) return PFX_ERR_NULL_POINTER;
  g_allocate = allocate;
  g_free = free;
  return PFX_OK;
}

void* pfxUtilityAllocate(std::size_t bytes, std::size_t alignment) {
  return bytes == 0 ? nullptr : g_allocate(bytes, alignment);
}

void pfxUtilityFree(void* pointer) {
  if (pointer) g_free(pointer);
}

}  // namespace pfx
