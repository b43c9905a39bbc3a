// Sorting of PfxSortData16 and PfxSortData32 by their 64-bit key (seed chapter 6).
// A stable least-significant-digit radix sort: linear in the number of records, and
// passes over bytes that are equal in every key are skipped. Stable, so equal keys keep
// their order and results are the same run after run. With a task manager, large arrays
// (4,096 records or more per thread) are sorted in chunks in parallel, with the same result.
#pragma once

#include "pfx/base_level/base/pfx_sort_data.h"
#include "pfx/base_level/task/pfx_task_manager.h"

namespace pfx {

// `workBuff` must be 16-byte aligned and hold at least as many bytes as the data.
PfxInt32 pfxParallelSort(PfxSortData16* data, PfxUInt32 numData, void* workBuff,
                         PfxUInt32 workBytes, PfxTaskManager* taskManager = nullptr);
PfxInt32 pfxParallelSort(PfxSortData32* data, PfxUInt32 numData, void* workBuff,
                         PfxUInt32 workBytes, PfxTaskManager* taskManager = nullptr);

}  // namespace pfx
