// The task manager (seed chapter 3, "Initialize the Task Manager"): a stage divides its
// work into ranges of items that run in parallel. Every parallel stage takes a task manager as an
// optional last argument (pfxFindPairs(param, result, taskManager)); without one it runs on
// the calling thread. The stages use it so that their results never depend on how the
// work was divided: each item writes only its own output, lists are concatenated in index
// order, and sums of floating-point values stay in one fixed order. A world stepped with
// one thread or with many gives the same bits.
//
// PfxTbbTaskManager (pfx_tbb_task_manager.h) is the implementation the world uses; an
// application with its own scheduler can implement this interface instead.
#pragma once

#include "pfx/base_level/base/pfx_common.h"

namespace pfx {

// A task over items [begin, end) of a parallel-for; `context` is what the caller passed.
using PfxTaskFunction = void (*)(void* context, PfxUInt32 begin, PfxUInt32 end);

// The most threads a task manager may run.
constexpr PfxUInt32 PFX_MAX_THREADS = 256;

class PfxTaskManager {
 public:
  virtual ~PfxTaskManager() = default;

  // Threads that take part in a parallel-for, the calling thread included (at least 1).
  virtual PfxUInt32 getNumThreads() const = 0;

  // Calls task(context, begin, end) on disjoint ranges that together cover [0, count)
  // exactly once, possibly on several threads at once, and returns when every range is
  // done. Every range holds at least grainSize items (all of them when count is smaller),
  // so that a task is worth its scheduling. May be called from inside a task
  // (the inner loop then shares the same threads). Allocates nothing once the threads
  // have started. PFX_ERR_NULL_POINTER for a null task with items to run,
  // PFX_ERR_INVALID_VALUE for a grain size of 0; nothing runs then.
  virtual PfxInt32 parallelFor(PfxUInt32 count, PfxUInt32 grainSize, PfxTaskFunction task,
                               void* context) = 0;
};

// Runs body(begin, end) over [0, count) through the task manager, or as one range on the
// calling thread when there is none, it has one thread, or the count is within one grain.
// The body is passed by address, so nothing is allocated for it.
template <typename Body>
PfxInt32 pfxParallelFor(PfxTaskManager* taskManager, PfxUInt32 count, PfxUInt32 grainSize,
                        const Body& body) {
  if (grainSize == 0) return PFX_ERR_INVALID_VALUE;
  if (count == 0) return PFX_OK;
  if (!taskManager || count <= grainSize || taskManager->getNumThreads() < 2) {
    body(PfxUInt32(0), count);
    return PFX_OK;
  }
  const PfxTaskFunction task = [](void* context, PfxUInt32 begin, PfxUInt32 end) {
    (*static_cast<const Body*>(context))(begin, end);
  };
  return taskManager->parallelFor(count, grainSize, task,
                                  const_cast<void*>(static_cast<const void*>(&body)));
}

// How many contiguous chunks to split `count` items into for a stage that keeps one output
// per chunk (pairs found, histograms): a few per thread, so that uneven chunks still
// balance, at most maxChunks, and none smaller than minItems. Results never depend on it.
inline PfxUInt32 pfxNumChunks(const PfxTaskManager* taskManager, PfxUInt32 count,
                              PfxUInt32 minItems, PfxUInt32 maxChunks) {
  const PfxUInt32 threads = taskManager ? taskManager->getNumThreads() : 1;
  if (threads < 2 || minItems == 0) return 1;
  PfxUInt32 chunks = threads * 4 < maxChunks ? threads * 4 : maxChunks;
  const PfxUInt32 bySize = count / minItems;
  if (bySize < chunks) chunks = bySize;
  return chunks > 0 ? chunks : 1;
}

// The first item of chunk `chunk` of `numChunks` over `count` items (chunk == numChunks
// gives count), so that chunks differ in size by at most one item.
inline PfxUInt32 pfxChunkBegin(PfxUInt32 count, PfxUInt32 numChunks, PfxUInt32 chunk) {
  return static_cast<PfxUInt32>(PfxUInt64(count) * chunk / numChunks);
}

}  // namespace pfx
