#include "pfx/low_level/sort/pfx_parallel_sort.h"

#include <utility>

#include "low_level/pfx_buffer_checks.h"

namespace pfx {

namespace {

constexpr int kNumDigits = 8;  // bytes of the 64-bit key
constexpr int kNumBuckets = 256;
// Below this many records per chunk a pass is too short to be worth a task.
constexpr PfxUInt32 kMinRecordsPerChunk = 4096;
constexpr PfxUInt32 kMaxSortChunks = 16;
// Up to this many records an insertion sort is cheaper than the radix passes, whose 8 KiB
// of histograms alone cost more to clear and scan than sorting a robot's few proxies and
// pairs (a sixth of a seven-body arm's sorting time).
constexpr PfxUInt32 kMaxInsertionSorted = 32;

inline PfxUInt32 digitOf(PfxUInt64 key, int digit) {
  return static_cast<PfxUInt32>(key >> (digit * 8)) & 0xffu;
}

template <class Record>
PfxInt32 validateSort(const Record* data, PfxUInt32 numData, const void* workBuff,
                      PfxUInt32 workBytes) {
  const PfxParamNames at{"pfxParallelSort", ""};
  if (const PfxInt32 err = pfxCheckRequired(at, {{data, "data"}}, "numData", numData);
      err != PFX_OK) {
    return err;
  }
  if (!pfxIsAligned(data)) {
    return pfxRejectParam(PFX_ERR_INVALID_ALIGNMENT,
                          "pfxParallelSort: data is not 16-byte aligned");
  }
  const PfxUInt64 dataBytes = PfxUInt64(numData) * sizeof(Record);
  if (const PfxInt32 err = pfxCheckBuffer(at, "workBuff", workBuff, workBytes, dataBytes);
      err != PFX_OK) {
    return err;
  }
  if (pfxRangesOverlap(data, dataBytes, workBuff, dataBytes)) {
    return pfxRejectParam(PFX_ERR_INVALID_VALUE, "pfxParallelSort: data and workBuff share bytes");
  }
  return PFX_OK;
}

// Least-significant digit first: each pass is a stable counting sort on one byte, so after
// the last pass the records are ordered by the whole key and equal keys keep their input
// order. The result depends on nothing but the input, which keeps the pipeline
// deterministic.
template <class Record>
void serialRadixSort(Record* data, PfxUInt32 numData, void* workBuff) {
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
}

// Stable like the radix sort (a record moves only past larger keys), so equal keys keep
// their input order and the result is the same record for record.
template <class Record>
void insertionSort(Record* data, PfxUInt32 numData) {
  for (PfxUInt32 i = 1; i < numData; ++i) {
    const Record record = data[i];
    PfxUInt32 j = i;
    for (; j > 0 && data[j - 1].key > record.key; --j) data[j] = data[j - 1];
    data[j] = record;
  }
}

// The same passes over contiguous chunks of the records: each chunk counts its own
// histogram, the chunks' buckets are laid out in chunk order (all of bucket 0 first, chunk
// by chunk, then bucket 1, ...), and each chunk scatters its records in its own order. That
// is exactly the serial pass, so the result is the same for any number of chunks.
template <class Record>
void chunkedRadixSort(Record* data, PfxUInt32 numData, void* workBuff, PfxUInt32 numChunks,
                      PfxTaskManager* taskManager) {
  auto chunkBegin = [&](PfxUInt32 c) { return pfxChunkBegin(numData, numChunks, c); };
  // The bits that differ between keys decide which bytes need a pass.
  PfxUInt64 anyBits[kMaxSortChunks], allBits[kMaxSortChunks];
  pfxParallelFor(taskManager, numChunks, 1, [&](PfxUInt32 first, PfxUInt32 last) {
    for (PfxUInt32 c = first; c < last; ++c) {
      PfxUInt64 any = 0, all = ~PfxUInt64(0);
      for (PfxUInt32 i = chunkBegin(c); i < chunkBegin(c + 1); ++i) {
        any |= data[i].key;
        all &= data[i].key;
      }
      anyBits[c] = any;
      allBits[c] = all;
    }
  });
  PfxUInt64 differing = 0, all = ~PfxUInt64(0);
  for (PfxUInt32 c = 0; c < numChunks; ++c) {
    differing |= anyBits[c];
    all &= allBits[c];
  }
  differing &= ~all;

  // 16 KiB on the stack: a stage must not allocate.
  PfxUInt32 counts[kMaxSortChunks][kNumBuckets];
  Record* src = data;
  Record* dst = static_cast<Record*>(workBuff);
  for (int d = 0; d < kNumDigits; ++d) {
    if (digitOf(differing, d) == 0) continue;
    pfxParallelFor(taskManager, numChunks, 1, [&](PfxUInt32 first, PfxUInt32 last) {
      for (PfxUInt32 c = first; c < last; ++c) {
        PfxUInt32* bucket = counts[c];
        for (int b = 0; b < kNumBuckets; ++b) bucket[b] = 0;
        for (PfxUInt32 i = chunkBegin(c); i < chunkBegin(c + 1); ++i) {
          ++bucket[digitOf(src[i].key, d)];
        }
      }
    });
    PfxUInt32 offset = 0;
    for (int b = 0; b < kNumBuckets; ++b) {
      for (PfxUInt32 c = 0; c < numChunks; ++c) {
        const PfxUInt32 n = counts[c][b];
        counts[c][b] = offset;
        offset += n;
      }
    }
    pfxParallelFor(taskManager, numChunks, 1, [&](PfxUInt32 first, PfxUInt32 last) {
      for (PfxUInt32 c = first; c < last; ++c) {
        PfxUInt32* bucket = counts[c];
        for (PfxUInt32 i = chunkBegin(c); i < chunkBegin(c + 1); ++i) {
          dst[bucket[digitOf(src[i].key, d)]++] = src[i];
        }
      }
    });
    std::swap(src, dst);
  }

  if (src != data) {
    pfxParallelFor(taskManager, numData, kMinRecordsPerChunk, [&](PfxUInt32 first, PfxUInt32 last) {
      for (PfxUInt32 i = first; i < last; ++i) data[i] = src[i];
    });
  }
}

template <class Record>
PfxInt32 radixSort(Record* data, PfxUInt32 numData, void* workBuff, PfxUInt32 workBytes,
                   PfxTaskManager* taskManager) {
  const PfxInt32 err = validateSort(data, numData, workBuff, workBytes);
  if (err != PFX_OK) return err;
  if (numData < 2) return PFX_OK;
  if (numData <= kMaxInsertionSorted) {
    insertionSort(data, numData);
    return PFX_OK;
  }
  const PfxUInt32 numChunks =
      pfxNumChunks(taskManager, numData, kMinRecordsPerChunk, kMaxSortChunks);
  if (numChunks == 1) {
    serialRadixSort(data, numData, workBuff);
  } else {
    chunkedRadixSort(data, numData, workBuff, numChunks, taskManager);
  }
  return PFX_OK;
}

}  // namespace

PfxInt32 pfxParallelSort(PfxSortData16* data, PfxUInt32 numData, void* workBuff,
                         PfxUInt32 workBytes, PfxTaskManager* taskManager) {
  return radixSort(data, numData, workBuff, workBytes, taskManager);
}

PfxInt32 pfxParallelSort(PfxSortData32* data, PfxUInt32 numData, void* workBuff,
                         PfxUInt32 workBytes, PfxTaskManager* taskManager) {
  return radixSort(data, numData, workBuff, workBytes, taskManager);
}

}  // namespace pfx
