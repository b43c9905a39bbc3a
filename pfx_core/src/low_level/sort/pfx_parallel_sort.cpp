#include "pfx/low_level/sort/pfx_parallel_sort.h"

#include <utility>

#include "low_level/pfx_buffer_checks.h"

namespace pfx {

namespace {

constexpr int kNumDigits = 8;  // bytes of the 64-bit key
constexpr int kNumBuckets = 256;

inline PfxUInt32 digitOf(PfxUInt64 key, int digit) {
  return static_cast<PfxUInt32>(key >> (digit * 8)) & 0xffu;
}

template <class Record>
PfxInt32 validateSort(const Record* data, PfxUInt32 numData, const void* workBuff,
                      PfxUInt32 workBytes) {
  if (numData > 0 && !data) return PFX_ERR_NULL_POINTER;
  if (!pfxIsAligned(data)) return PFX_ERR_INVALID_ALIGNMENT;
  const PfxUInt64 dataBytes = PfxUInt64(numData) * sizeof(Record);
  const PfxInt32 err = pfxCheckBuffer(workBuff, workBytes, dataBytes);
  if (err != PFX_OK) return err;
  if (pfxRangesOverlap(data, dataBytes, workBuff, dataBytes)) return PFX_ERR_INVALID_VALUE;
  return PFX_OK;
}

// Least-significant digit first: each pass is a stable counting sort on one byte, so after
// the last pass the records are ordered by the whole key and equal keys keep their input
// order. The result depends on nothing but the input, which keeps the pipeline
// deterministic.
template <class Record>
PfxInt32 radixSort(Record* data, PfxUInt32 numData, void* workBuff, PfxUInt32 workBytes) {
  const PfxInt32 err = validateSort(data, numData, workBuff, workBytes);
  if (err != PFX_OK) return err;
  if (numData < 2) return PFX_OK;

  // All eight histograms in one read of the data; the array lives on the stack (8 KiB)
  // because a stage must not allocate.
  PfxUInt32 counts[kNumDigits][kNumBuckets] = {};
  for (PfxUInt32 i = 0; i < numData; ++i) {
    const PfxUInt64 key = data[i].key;
    for (int d = 0; d < kNumDigits; ++d) ++counts[d][digitOf(key, d)];
  }

  Record* src = data;
  Record* dst = static_cast<Record*>(workBuff);
  for (int d = 0; d < kNumDigits; ++d) {
    PfxUInt32* bucket = counts[d];
    // Typical keys (body ids, 16-bit sort values) leave most bytes equal in every record;
    // a pass over such a byte would only copy the data.
    if (bucket[digitOf(src[0].key, d)] == numData) continue;

    PfxUInt32 offset = 0;
    for (int b = 0; b < kNumBuckets; ++b) {
      const PfxUInt32 n = bucket[b];
      bucket[b] = offset;
      offset += n;
    }
    for (PfxUInt32 i = 0; i < numData; ++i) dst[bucket[digitOf(src[i].key, d)]++] = src[i];
    std::swap(src, dst);
  }

  if (src != data) {
    for (PfxUInt32 i = 0; i < numData; ++i) data[i] = src[i];
  }
  return PFX_OK;
}

}  // namespace

PfxInt32 pfxParallelSort(PfxSortData16* data, PfxUInt32 numData, void* workBuff,
                         PfxUInt32 workBytes) {
  return radixSort(data, numData, workBuff, workBytes);
}

PfxInt32 pfxParallelSort(PfxSortData32* data, PfxUInt32 numData, void* workBuff,
                         PfxUInt32 workBytes) {
  return radixSort(data, numData, workBuff, workBytes);
}

}  // namespace pfx
