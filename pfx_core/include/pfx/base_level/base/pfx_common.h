// Scalar types, error codes and limits shared by every layer.
#pragma once

#include <cstddef>
#include <cstdint>

namespace pfx {

using PfxInt8 = std::int8_t;
using PfxUInt8 = std::uint8_t;
using PfxInt16 = std::int16_t;
using PfxUInt16 = std::uint16_t;
using PfxInt32 = std::int32_t;
using PfxUInt32 = std::uint32_t;
using PfxInt64 = std::int64_t;
using PfxUInt64 = std::uint64_t;
using PfxBool = bool;

#ifdef PFX_DOUBLE
using PfxFloat = double;
#else
using PfxFloat = float;
#endif

// Every public entry point returns one of these. A call that returns anything but
// PFX_OK has changed nothing.
enum : PfxInt32 {
  PFX_OK = 0,
  PFX_ERR_INVALID_VALUE = -1,      // a parameter is NaN, infinite, negative or out of range
  PFX_ERR_INVALID_ALIGNMENT = -2,  // a buffer is not 16-byte aligned
  PFX_ERR_OUT_OF_BUFFER = -3,      // a buffer is missing or too small
  PFX_ERR_OUT_OF_WORLD = -4,       // a body lies outside the world's bounds
  PFX_ERR_OUT_OF_MAX_PAIRS = -5,   // more pairs were found than the pair buffer holds
  PFX_ERR_INVALID_FLAG = -6,       // an unknown flag or enum value
  PFX_ERR_NOT_CONVEX = -7,         // a convex mesh has a concave part
  PFX_ERR_OUT_OF_RANGE = -8,       // an index or count is outside its limit
  PFX_ERR_DEGENERATE = -9,         // zero size, zero area, zero length
  PFX_ERR_NULL_POINTER = -10,      // a required pointer is null
};

// Words for an error code, for logs and exceptions.
const char* pfxErrorString(PfxInt32 errorCode);

// Limits fixed by the data layout (seed chapter 2).
constexpr PfxUInt32 PFX_NUM_CONTACTS_PER_MANIFOLD = 4;
constexpr PfxUInt32 PFX_MAX_SHAPES_PER_COLLIDABLE = 64;
// A closed triangulated convex mesh of 64 facets has 34 vertices and 96 edges (Euler).
constexpr PfxUInt32 PFX_CONVEX_MESH_MAX_FACETS = 64;
constexpr PfxUInt32 PFX_CONVEX_MESH_MAX_VERTICES = 34;
constexpr PfxUInt32 PFX_CONVEX_MESH_MAX_EDGES = 96;

// 16-byte alignment is what the seed asks of every work and pair buffer.
constexpr std::size_t PFX_BUFFER_ALIGNMENT = 16;

inline bool pfxIsAligned(const void* p) {
  return (reinterpret_cast<std::uintptr_t>(p) & (PFX_BUFFER_ALIGNMENT - 1)) == 0;
}

inline std::size_t pfxAlignBytes(std::size_t bytes) {
  return (bytes + PFX_BUFFER_ALIGNMENT - 1) & ~(PFX_BUFFER_ALIGNMENT - 1);
}

}  // namespace pfx
