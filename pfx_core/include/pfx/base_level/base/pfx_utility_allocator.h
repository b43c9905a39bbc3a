// The allocator behind every mesh the library allocates (seed chapter 7, "Precautions for
// Serialization Processing"): the arrays of a large mesh made by pfxCreateLargeTriMesh,
// the meshes pfxNewConvexMesh and pfxNewLargeTriMesh make, and the meshes a serialized
// file brings in. Nothing else in the core allocates through it.
#pragma once

#include <cstddef>

#include "pfx/base_level/base/pfx_common.h"

namespace pfx {

// Returns `bytes` bytes aligned to `alignment` (a power of two, at least
// sizeof(void*)), or null when out of memory.
using PfxUtilityAllocateFunc = void* (*)(std::size_t bytes, std::size_t alignment);
// Frees what the allocate function returned; never called with null.
using PfxUtilityFreeFunc = void (*)(void* pointer);

// Sets the pair of functions used from now on; two nulls restore the default
// (std::aligned_alloc and std::free). One null without the other is rejected
// (PFX_ERR_NULL_POINTER) and nothing changes. A mesh must be freed by the allocator that
// allocated it: change the allocator only while no mesh allocated by the previous one is
// alive, and not while another thread allocates a mesh.
PfxInt32 pfxSetUtilityAllocator(PfxUtilityAllocateFunc allocate, PfxUtilityFreeFunc free);

// What the library calls: the current allocator, and null for a request of zero bytes.
void* pfxUtilityAllocate(std::size_t bytes, std::size_t alignment);
// Safe on null.
void pfxUtilityFree(void* pointer);

}  // namespace pfx
