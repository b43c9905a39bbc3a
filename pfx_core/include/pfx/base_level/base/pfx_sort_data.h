// Records that pfxParallelSort orders by a 64-bit key. Pairs and broadphase proxies are
// such records, so one sort serves every stage that needs one (seed chapter 6).
#pragma once

#include "pfx/base_level/base/pfx_common.h"

namespace pfx {

struct alignas(16) PfxSortData16 {
  PfxUInt64 key;
  PfxUInt32 data[2];
};

struct alignas(16) PfxSortData32 {
  PfxUInt64 key;
  PfxUInt32 data[6];
};

static_assert(sizeof(PfxSortData16) == 16, "PfxSortData16 must stay 16 bytes");
static_assert(sizeof(PfxSortData32) == 32, "PfxSortData32 must stay 32 bytes");

inline PfxUInt64 pfxGetKey(const PfxSortData16& d) { return d.key; }
inline PfxUInt64 pfxGetKey(const PfxSortData32& d) { return d.key; }
inline void pfxSetKey(PfxSortData16& d, PfxUInt64 key) { d.key = key; }
inline void pfxSetKey(PfxSortData32& d, PfxUInt64 key) { d.key = key; }

}  // namespace pfx
