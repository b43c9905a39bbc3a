// Sorting of PfxSortData16 and PfxSortData32 by their 64-bit key (seed chapter 6).
// A stable least-significant-digit radix sort: linear in the number of records, and
// passes over bytes that are equal in every key are skipped. Stable, so equal keys keep
// their order and results are the same run after run.
#pragma once

#include "pfx/base_level/base/pfx_sort_data.h"

namespace pfx {

// `workBuff` must be 16-byte aligned and hold at least as many bytes as the data.
PfxInt32 pfxParallelSort(PfxSortData16* data, PfxUInt32 numData, void* workBuff,
                         PfxUInt32 workBytes);
PfxInt32 pfxParallelSort(PfxSortData32* data, PfxUInt32 numData, void* workBuff,
                         PfxUInt32 workBytes);

}  // namespace pfx
